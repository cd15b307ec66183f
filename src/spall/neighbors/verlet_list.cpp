#include "spall/neighbors/verlet_list.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <functional>
#include <stdexcept>
#include <memory>
#include <string>
#include <vector>


#include "spall/core/mapped_buffer.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/simd.hpp"
#include "spall/neighbors/cell_list.hpp"
#include "spall/neighbors/relative_motion.hpp"
#include "spall/neighbors/trimmed_stencil.hpp"

namespace spall::neighbors {

namespace {

// Cells of edge radius / 2, searched by the trimmed stencil (trimmed_stencil.hpp): on a cubic
// lattice at 2.4 spacings, 135 candidates for 54 neighbours against 338 in the 27 cells of edge
// radius (docs/PERFORMANCE.md).
constexpr int stencil_reach = 2;

// Candidates tested at once (for_each_within): a simd::Pack of them.
constexpr int search_lanes = simd::Pack::width;

// A thread's rows as the search finds them, in chunks of pages of their own (MappedBuffer) that are
// never reallocated, each row whole in one chunk (at most a chunk more than the rows a thread).
// Each chunk knows the last particle whose row it holds, so that the copy into the list, in
// particle order, gives a chunk back to the system as soon as it has passed that particle: the
// build holds the list about once, not twice (the rows found and the list they were copied into
// were 94 and 99 MB of the Taylor bar's 408 MB heap at D0/50 on one process).
class FoundRows {
 public:
  struct Chunk {
    MappedBuffer<Index> entries;
    std::size_t size = 0;
    Index last = -1;  // the last particle whose row it holds
  };
  // Room for `room` entries of the next row (a row's candidates and the search_lanes past them that
  // compress_indices may write); close() then takes the row's length.
  Index* open(std::size_t room) {
    if (chunks_.empty() || chunks_.back().entries.capacity() - chunks_.back().size < room)
      chunks_.push_back({MappedBuffer<Index>(std::max(chunk_entries, room)), 0, -1});
    Chunk& chunk = chunks_.back();
    return chunk.entries.data() + chunk.size;
  }
  void close(Index particle, Index count) {
    Chunk& chunk = chunks_.back();
    chunk.size += static_cast<std::size_t>(count);
    chunk.last = std::max(chunk.last, particle);
  }
  std::vector<Chunk>& chunks() { return chunks_; }

 private:
  static constexpr std::size_t chunk_entries = std::size_t(1) << 19;  // 2 MiB
  std::vector<Chunk> chunks_;
};

// Positions in cell order, one array per coordinate, and the particle at each position: the
// candidates of a particle are contiguous runs of these arrays, read front to back, search_lanes
// at a time. Each array has search_lanes entries past the last particle, so that the last load of
// a run stays inside it (those lanes are masked off).
struct CellOrderedPositions {
  std::vector<Real> x, y, z;
  std::vector<Index> particle;
  Vec3 lower;

  // order[k]: the particle at position k of the cells.
  CellOrderedPositions(StretchView<Vec3> positions, const CellList& cells, std::span<const Index> order)
      : x(order.size() + search_lanes), y(x.size()), z(x.size()), particle(x.size()), lower(cells.lower()) {
    const auto n = static_cast<std::int64_t>(order.size());
    parallel::for_each(n, [&](std::int64_t k) {
      const Vec3& p = positions[order[k]];
      x[k] = p.x();
      y[k] = p.y();
      z[k] = p.z();
      particle[k] = order[k];
    });
  }

  // Position minus the grid corner, as CellList::build bins it.
  Vec3 offset(Index k) const { return Vec3(x[k] - lower.x(), y[k] - lower.y(), z[k] - lower.z()); }

  // The squared distances from a to the pack of candidates b, b + 1, ...
  simd::Pack distance_squared(Index a, Index b) const {
    using simd::Pack;
    const Pack dx = Pack(x[a]) - Pack::load(&x[b]);
    const Pack dy = Pack(y[a]) - Pack::load(&y[b]);
    const Pack dz = Pack(z[a]) - Pack::load(&z[b]);
    return fma(dz, dz, fma(dy, dy, dx * dx));
  }
};

// One search radius for every pair.
struct UniformRadius {
  Real radius;
  Real radius_squared;
  // The largest radius of a pair of a, for the stencil.
  Real largest(Index) const { return radius; }
  simd::Pack squared(Index, Index) const { return simd::Pack(radius_squared); }
};

// reach_a + reach_b + skin, the reaches in cell order (search_lanes entries past the last
// particle, like the positions). Symmetric in a and b bit for bit (a sum of two numbers does not
// depend on their order), so j is in i's row exactly when i is in j's.
struct PairRadius {
  std::vector<Real> reach;
  Real largest_reach;
  Real skin;

  PairRadius(StretchView<Real> reach_by_particle, std::span<const Index> order, Real largest_reach,
             Real skin)
      : reach(order.size() + search_lanes), largest_reach(largest_reach), skin(skin) {
    const auto n = static_cast<std::int64_t>(order.size());
    parallel::for_each(n, [&](std::int64_t k) { reach[k] = reach_by_particle[order[k]]; });
  }
  Real largest(Index a) const { return reach[a] + largest_reach + skin; }
  // For the pack of candidates b, b + 1, ... of a.
  simd::Pack squared(Index a, Index b) const {
    using simd::Pack;
    const Pack r = (Pack(reach[a]) + Pack::load(&reach[b])) + Pack(skin);
    return r * r;
  }
};

// The candidates j in `range`, j != k, within the radius of k, handed to take(j_first, mask) a
// pack at a time (bit i of mask: j_first + i is within; the lanes past the range are masked off).
template <typename Radius, typename Take>
inline void for_each_within(const CellOrderedPositions& p, const Radius& radius, Index k,
                            ParticleRange range, Take&& take) {
  for (Index j = range.begin; j < range.end; j += search_lanes) {
    auto mask = static_cast<unsigned>((p.distance_squared(k, j) < radius.squared(k, j)).lanes());
    if (range.end - j < search_lanes) mask &= (1u << (range.end - j)) - 1;
    if (k >= j && k < j + search_lanes) mask &= ~(1u << (k - j));
    take(j, mask);
  }
}

}  // namespace

void VerletList::build(StretchView<Vec3> x, Real cutoff, Real skin, ParticleRange rows) {
  if (!(cutoff > 0) || !(skin >= 0)) {
    throw std::invalid_argument("neighbour search: need cutoff > 0 and skin >= 0, got cutoff " +
                                std::to_string(cutoff) + " and skin " + std::to_string(skin));
  }
  cutoff_ = cutoff;
  skin_ = skin;
  ++builds_;
  const Real radius = cutoff + skin;
  build_rows(x, radius, [&](std::span<const Index>) { return UniformRadius{radius, radius * radius}; },
             RowOrder::ascending, rows);
}

void VerletList::build(StretchView<Vec3> x, StretchView<Real> reach, Real skin, RowOrder order,
                       ParticleRange rows, const BinnedSubset* binned) {
  if (reach.size() != x.size())
    throw std::invalid_argument("neighbour search: need one reach per particle");
  Real largest = 0;
  const auto check = [&](Real r) {
    if (!(r > 0)) throw std::invalid_argument("neighbour search: need every reach > 0, got " + std::to_string(r));
    largest = std::max(largest, r);
  };
  if (binned) {
    // Ascending (a cell's particles in index order, as binning every particle leaves them), and
    // every row asked for binned.
    const std::span<const Index> subset = binned->particles;
    const auto n = static_cast<Index>(x.size());
    const Index first = std::clamp(rows.begin, Index(0), n), last = std::clamp(rows.end, Index(0), n);
    const auto rows_binned = std::lower_bound(subset.begin(), subset.end(), last) -
                             std::lower_bound(subset.begin(), subset.end(), first);
    const bool ascending = std::adjacent_find(subset.begin(), subset.end(), std::greater_equal<>()) == subset.end();
    if (!ascending || (first < last && rows_binned != last - first))
      throw std::invalid_argument("neighbour search: binned particles not ascending, or a row asked for not binned");
    for (const Index i : subset) check(reach[i]);
    if (largest > binned->largest_reach)
      throw std::invalid_argument("neighbour search: a binned reach above the largest given");
    largest = binned->largest_reach;
  } else {
    for (const Real r : reach.every()) check(r);
  }
  if (!(skin >= 0)) throw std::invalid_argument("neighbour search: need skin >= 0, got " + std::to_string(skin));
  cutoff_ = 2 * largest;
  skin_ = skin;
  order_ = order;
  ++builds_;
  build_reach(x, reach, rows, binned);
}

void VerletList::build_reach(StretchView<Vec3> x, StretchView<Real> reach, ParticleRange rows,
                             const BinnedSubset* binned) {
  const Real largest = cutoff_ / 2, skin = skin_;
  build_rows(x, cutoff_ + skin,
             [&](std::span<const Index> cell_order) { return PairRadius(reach, cell_order, largest, skin); },
             order_, rows, binned);
}

void VerletList::search_rows(std::span<const Real> reach, ParticleRange rows) {
  const Index n = count_;
  rows = {std::clamp(rows.begin, Index(0), n), std::clamp(rows.end, Index(0), n)};
  if (rows.begin == rows_.begin && rows.end == rows_.end) return;
  if (subset_) throw std::logic_error("VerletList::search_rows: positions at the build not all current");
  // build_rows keeps its argument as the new x_at_build_
  const std::vector<Vec3> x(x_at_build_.data(), x_at_build_.data() + n);
  build_reach(x, reach, rows);
}

void VerletList::search_every_row(std::span<const Real> reach) {
  if (partial()) search_rows(reach, {0, count_});
}

void VerletList::hold_positions(ParticleRange keep) {
  if (keep.begin >= keep.end) keep = {0, 0};  // none (a rank without particles of its own)
  if (keep.begin == x_at_build_.held_begin() && keep.end == x_at_build_.held_end()) return;
  x_at_build_.hold(keep.begin, keep.end);
  subset_ = true;
}

void VerletList::search_binned_rows(StretchView<Real> reach, ParticleRange rows, std::span<const Index> binned) {
  rows = {std::clamp(rows.begin, Index(0), count_), std::clamp(rows.end, Index(0), count_)};
  if (rows.begin == rows_.begin && rows.end == rows_.end) return;
  const RangeArray<Vec3> x = x_at_build_;  // build_rows keeps the binned ones as the new x_at_build_
  const BinnedSubset subset{.particles = binned, .grid = grid_, .largest_reach = cutoff_ / 2};
  build_reach(x.view(count_), reach, rows, &subset);
}

template <typename MakeRadius>
void VerletList::build_rows(StretchView<Vec3> x, Real radius, const MakeRadius& make_radius,
                            RowOrder row_order, ParticleRange rows, const BinnedSubset* binned) {
  const auto n = static_cast<Index>(x.size());
  count_ = n;
  // Of a subset, its positions alone, over the stretch from its first to its last (the others'
  // are not current here, and are not read).
  if (binned) {
    const std::span<const Index> subset = binned->particles;
    grid_ = binned->grid;
    x_at_build_.clear();  // freed first: never both at once
    x_at_build_.resize(0);
    if (!subset.empty()) x_at_build_.hold(subset.front(), subset.back() + 1);
    for (const Index a : subset) x_at_build_[a] = x[a];
  } else {
    const std::span<const Vec3> every = x.every();
    grid_ = bounding_box(n, [&](Index a) { return every[a]; });
    x_at_build_.clear();
    x_at_build_.resize(n);
    std::copy(every.begin(), every.end(), x_at_build_.data());
  }
  subset_ = binned != nullptr;
  rows_ = {std::clamp(rows.begin, Index(0), n), std::clamp(rows.end, Index(0), n)};
  list_.offsets.assign(n + 1, 0);
  decltype(list_.neighbors)().swap(list_.neighbors);  // freed first: never the old list and the new at once
  if (n == 0) return;

  // order[k]: the particle at position k of the cells (of a subset: binned in the order given, so
  // that a cell's particles keep ascending index, as the build of every particle has them).
  CellList cells;
  std::vector<Index> order;
  if (binned) {
    const std::span<const Index> subset = binned->particles;
    std::vector<Vec3> subset_x(subset.size());
    for (std::size_t k = 0; k < subset.size(); ++k) subset_x[k] = x[subset[k]];
    cells.build(subset_x, radius / stencil_reach, {}, &binned->grid);
    order = cells.take_order();
    for (Index& k : order) k = subset[k];
  } else {
    cells.build(x.every(), radius / stencil_reach);
    order = cells.take_order();
  }
  const CellOrderedPositions p(x, cells, order);
  const auto pair_radius = make_radius(order);
  const Index cell_count = cells.cell_count();

  // Calls visit(k, ranges, range_count) with the trimmed candidate ranges of every particle k (in
  // cell order), shared among the team of a parallel region. Chunks of consecutive cells, so that
  // the stencil mostly slides along a row of cells; dynamic scheduling because cells hold
  // different numbers of particles: it changes who computes a row, never what it holds.
  const auto for_each_particle = [&](const parallel::Team& team, auto&& visit) {
    TrimmedStencil stencil(cells, stencil_reach);
    TrimmedStencil::Ranges ranges;
    team.for_each(cell_count, [&](Index c) {
      stencil.prepare(c);
      const ParticleRange own = cells.cell(c);
      for (Index k = own.begin; k < own.end; ++k)
        if (order[k] >= rows.begin && order[k] < rows.end)  // else a row not asked for: left empty
          visit(k, ranges, stencil.trimmed(p.offset(k), pair_radius.largest(k), ranges));
    }, {.chunk = 64});
  };

  // One walk: each thread appends the rows it finds to buffers of its own, with each row's length
  // and where it is; once the lengths give the offsets, the rows are copied into place in particle
  // order, a slab at a time, and each buffer is given back once the copy has passed its last row.
  // Every row is written by one thread and holds what the search found, so the list is the same
  // for any thread count.
  std::vector<FoundRows> found_rows;
  std::vector<const Index*> found_at(n, nullptr);
  parallel::region([&](const parallel::Team& team) {
    team.single([&] { found_rows.resize(team.size()); });
    // Candidates are gathered search_lanes at a time without a branch per candidate (about one in
    // three is a neighbour, so a branch would mispredict often).
    FoundRows& found = found_rows[team.index()];
    for_each_particle(team, [&](Index k, const TrimmedStencil::Ranges& ranges, int range_count) {
      Index candidates = 0;
      for (int r = 0; r < range_count; ++r) candidates += ranges[r].end - ranges[r].begin;
      Index* row = found.open(static_cast<std::size_t>(candidates) + search_lanes);
      Index count = 0;
      for (int r = 0; r < range_count; ++r)
        for_each_within(p, pair_radius, k, ranges[r], [&](Index j, unsigned mask) {
          simd::Pack::compress_indices(p.particle.data() + j, static_cast<int>(mask), row + count);
          count += std::popcount(mask);
        });
      // Particles already in cell order give sorted rows.
      if (row_order == RowOrder::ascending && !std::is_sorted(row, row + count)) std::sort(row, row + count);
      found.close(order[k], count);
      found_at[order[k]] = row;
      list_.offsets[order[k] + 1] = count;
    });
  });
  for (Index i = 0; i < n; ++i) list_.offsets[i + 1] += list_.offsets[i];
  list_.neighbors.resize(static_cast<std::size_t>(list_.offsets[n]));  // pages written by the copy alone
  std::vector<FoundRows::Chunk*> by_last;
  for (FoundRows& found : found_rows)
    for (FoundRows::Chunk& chunk : found.chunks()) by_last.push_back(&chunk);
  std::sort(by_last.begin(), by_last.end(), [](const auto* a, const auto* b) { return a->last < b->last; });
  constexpr Index slab = Index(1) << 14;  // rows a copy pass
  std::size_t given_back = 0;
  for (Index first = 0; first < n; first += slab) {
    const Index end = std::min(n, first + slab);
    parallel::for_each(parallel::Range{first, end}, [&](Index i) {
      std::copy_n(found_at[i], list_.count(i), list_.neighbors.begin() + list_.offsets[i]);
    });
    while (given_back < by_last.size() && by_last[given_back]->last < end) by_last[given_back++]->entries.release();
  }
}

bool VerletList::needs_rebuild(StretchView<Vec3> x) const {
  if (list_.offsets.empty() || x.size() != count_) return true;
  // The list holds every pair within r_ij + skin at the build (r_ij <= cutoff_). A pair now closer
  // than r_ij was within |x_i - x_j| + |d_i - d_j| < r_ij + |d_i - d_j| then (triangle inequality,
  // d = x - x_at_build_), so it is listed when its relative displacement is at most the skin.
  return !close_pairs_moved_together(x, positions_at_build(), cutoff_, skin_);
}

bool VerletList::needs_rebuild(StretchView<Vec3> x, ParticleRange own, const parallel::Communicator& ranks) const {
  if (list_.offsets.empty() || x.size() != count_) return true;
  return !close_pairs_moved_together(x, positions_at_build(), cutoff_, skin_, own, ranks);
}

std::vector<Index> spatial_order(std::span<const Vec3> x, Real cell_size) {
  CellList cells;
  cells.build(x, cell_size);
  const std::span<const Index> order = cells.order();
  return {order.begin(), order.end()};
}

}  // namespace spall::neighbors
