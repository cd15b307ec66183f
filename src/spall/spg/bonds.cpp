#include "spall/spg/bonds.hpp"

#include <algorithm>
#include <iterator>

namespace spall::spg {

Index BondList::broken_count(Index i) const {
  Index c = 0;
  for (Index k = offsets[i]; k < offsets[i + 1]; ++k) c += broken[k];
  return c;
}

Real previous_rest_length(const BondList& previous, Index i, Index j, bool& found) {
  found = false;
  if (i >= previous.size()) return 0;
  const auto begin = previous.neighbour.begin() + previous.offsets[i];
  const auto end = previous.neighbour.begin() + previous.offsets[i + 1];
  const auto it = std::lower_bound(begin, end, j);
  if (it == end || *it != j) return 0;
  found = true;
  return previous.rest_length[it - previous.neighbour.begin()];
}

void record_broken_pairs(const BondList& bonds, std::vector<BondPair>& broken_pairs) {
  std::vector<BondPair> now;
  for (Index i = 0; i < bonds.size(); ++i)
    for (Index k = bonds.offsets[i]; k < bonds.offsets[i + 1]; ++k)
      if (bonds.broken[k] && i < bonds.neighbour[k]) now.emplace_back(i, bonds.neighbour[k]);
  std::vector<BondPair> merged;
  merged.reserve(broken_pairs.size() + now.size());
  std::set_union(broken_pairs.begin(), broken_pairs.end(), now.begin(), now.end(), std::back_inserter(merged));
  broken_pairs.swap(merged);
}

void link_mirrors(BondList& bonds) {
  const Index n = bonds.size();
  bonds.mirror.resize(bonds.neighbour.size());
  parallel::for_each(n, [&](Index i) {
    for (Index k = bonds.offsets[i]; k < bonds.offsets[i + 1]; ++k) {
      const Index j = bonds.neighbour[k];
      const auto begin = bonds.neighbour.begin() + bonds.offsets[j];
      const auto end = bonds.neighbour.begin() + bonds.offsets[j + 1];
      // The pattern is symmetric, so i is in row j.
      bonds.mirror[k] = static_cast<Index>(std::lower_bound(begin, end, i) - bonds.neighbour.begin());
    }
  }, particle_loops);
}

std::vector<Index> bonds_breaking(const BondList& bonds, std::span<const Real> quantity, std::span<const Vec3> x,
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
  std::vector<Index> positions;
  for (std::size_t k = 0; k < breaks.size(); ++k)
    if (breaks[k]) positions.push_back(first + static_cast<Index>(k));
  return positions;
}

}  // namespace spall::spg
