#include "spall/spg/bonds.hpp"

#include <algorithm>
#include <iterator>

namespace spall::spg {

namespace {

// The neighbours of row i, held.
std::span<const Index> row(const BondList& bonds, Index i) {
  return {bonds.neighbour.data() + (bonds.offsets[i] - bonds.neighbour.held_begin()),
          static_cast<std::size_t>(bonds.count(i))};
}

}  // namespace

Index BondList::broken_count(Index i) const {
  Index c = 0;
  for (Index k = offsets[i]; k < offsets[i + 1]; ++k) c += broken[k];
  return c;
}

Index BondList::find(Index i, Index j) const {
  const std::span<const Index> r = row(*this, i);
  const auto it = std::lower_bound(r.begin(), r.end(), j);
  return it == r.end() || *it != j ? -1 : offsets[i] + static_cast<Index>(it - r.begin());
}

std::vector<Index> row_offsets(std::span<const Index> length) {
  std::vector<Index> offsets(length.size() + 1, 0);
  for (std::size_t i = 0; i < length.size(); ++i) offsets[i + 1] = offsets[i] + length[i];
  return offsets;
}

Real previous_rest_length(const BondList& previous, Index i, Index j, bool& found) {
  const Index k = i < previous.size() ? previous.find(i, j) : -1;
  found = k >= 0;
  return found ? previous.rest_length[k] : 0;
}

void break_bonds(BondList& bonds, StretchView<std::uint8_t> held, std::span<const BondPair> pairs,
                 std::vector<BondPair>& broken_pairs) {
  const auto holds = [&](Index i) {
    return held.size() == 0 || (i >= held.held_begin() && i < held.held_end() && held[i]);
  };
  for (const auto& [i, j] : pairs) {
    if (holds(i)) bonds.broken[bonds.find(i, j)] = 1;
    if (holds(j)) bonds.broken[bonds.find(j, i)] = 1;
  }
  std::vector<BondPair> merged;
  merged.reserve(broken_pairs.size() + pairs.size());
  std::set_union(broken_pairs.begin(), broken_pairs.end(), pairs.begin(), pairs.end(), std::back_inserter(merged));
  broken_pairs.swap(merged);
}

void link_mirrors(BondList& bonds, parallel::Range rows) {
  const parallel::Range held = bonds.entries(rows);
  bonds.mirror.hold_afresh(held.begin, held.end);
  parallel::for_each(rows, [&](Index i) {
    // The pattern is symmetric, so i is in row j.
    for (Index k = bonds.offsets[i]; k < bonds.offsets[i + 1]; ++k) bonds.mirror[k] = bonds.find(bonds.neighbour[k], i);
  }, particle_loops);
}

std::vector<BondPair> bonds_breaking(const BondList& bonds, StretchView<Real> quantity, StretchView<Vec3> x,
                                     Real critical_value, Real critical_stretch, parallel::Range rows) {
  if (rows.size() == 0) return {};
  const Index first = bonds.offsets[rows.begin];
  std::vector<std::uint8_t> breaks(static_cast<std::size_t>(bonds.offsets[rows.end] - first), 0);
  // Each side decides from the same symmetric expression, so the two flags of a bond agree.
  parallel::for_each(rows, [&](Index i) {
    for (Index k = bonds.offsets[i]; k < bonds.offsets[i + 1]; ++k) {
      if (bonds.broken[k]) continue;
      const Index j = bonds.neighbour[k];
      const Real average = Real(0.5) * (quantity[i] + quantity[j]);
      if (!(average > critical_value)) continue;
      const Real stretch = (x[i] - x[j]).norm() / bonds.rest_length[k];
      breaks[k - first] = stretch > critical_stretch;
    }
  }, particle_loops);
  std::vector<BondPair> pairs;
  for (Index i = rows.begin; i < rows.end; ++i)
    for (Index k = bonds.offsets[i]; k < bonds.offsets[i + 1]; ++k)
      if (breaks[k - first]) pairs.push_back(std::minmax(i, bonds.neighbour[k]));
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

}  // namespace spall::spg
