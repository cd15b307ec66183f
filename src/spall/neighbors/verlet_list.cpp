#include "spall/neighbors/verlet_list.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

#include "spall/neighbors/cell_list.hpp"

namespace spall::neighbors {

namespace {

// Positions in cell order, one array per coordinate: the candidates of a particle are 9 contiguous
// runs of these arrays, read front to back, and the distance test over a run vectorises.
struct CellOrderedPositions {
  std::vector<Real> x, y, z;

  CellOrderedPositions(std::span<const Vec3> positions, std::span<const Index> order)
      : x(order.size()), y(order.size()), z(order.size()) {
    const auto n = static_cast<std::int64_t>(order.size());
#pragma omp parallel for
    for (std::int64_t k = 0; k < n; ++k) {
      const Vec3& p = positions[order[k]];
      x[k] = p.x();
      y[k] = p.y();
      z[k] = p.z();
    }
  }

  // The count pass and the fill pass both decide "is a neighbour" through this one expression,
  // so they agree on every pair and the fill writes exactly the counted entries.
  Real distance_squared(Index a, Index b) const {
    const Real dx = x[a] - x[b];
    const Real dy = y[a] - y[b];
    const Real dz = z[a] - z[b];
    return dx * dx + dy * dy + dz * dz;
  }
};

}  // namespace

void VerletList::build(std::span<const Vec3> x, Real cutoff, Real skin) {
  if (!(cutoff > 0) || !(skin >= 0)) {
    throw std::invalid_argument("neighbour search: need cutoff > 0 and skin >= 0, got cutoff " +
                                std::to_string(cutoff) + " and skin " + std::to_string(skin));
  }
  cutoff_ = cutoff;
  skin_ = skin;
  x_at_build_.assign(x.begin(), x.end());
  const auto n = static_cast<Index>(x.size());
  list_.offsets.assign(n + 1, 0);
  if (n == 0) {
    list_.neighbors.clear();
    return;
  }

  const Real radius = cutoff + skin;
  const Real radius_squared = radius * radius;
  CellList cells;
  cells.build(x, radius);
  const std::span<const Index> order = cells.order();
  const CellOrderedPositions p(x, order);
  const Index cell_count = cells.cell_count();

  // Two passes, each writing only its own rows, so the list is the same for any thread count:
  // the count pass sizes the rows, the fill pass writes them. Dynamic scheduling because cells
  // hold different numbers of particles; it changes who computes a row, never what it holds.
#pragma omp parallel for schedule(dynamic, 16)
  for (Index c = 0; c < cell_count; ++c) {
    std::array<ParticleRange, 9> ranges;
    const int range_count = cells.neighborhood(c, ranges);
    const ParticleRange own = cells.cell(c);
    for (Index k = own.begin; k < own.end; ++k) {
      Index within = 0;
      for (int r = 0; r < range_count; ++r) {
        for (Index j = ranges[r].begin; j < ranges[r].end; ++j) {
          within += p.distance_squared(k, j) < radius_squared;
        }
      }
      list_.offsets[order[k] + 1] = within - 1;  // k itself, at distance 0, was counted
    }
  }
  for (Index i = 0; i < n; ++i) list_.offsets[i + 1] += list_.offsets[i];
  // The storage is kept from one rebuild to the next, where the count barely changes (resize
  // then writes nothing), unless it is more than twice what this build needs.
  const auto total = static_cast<std::size_t>(list_.offsets[n]);
  if (list_.neighbors.capacity() > 2 * total) std::vector<Index>().swap(list_.neighbors);
  list_.neighbors.resize(total);

#pragma omp parallel
  {
    // One particle's neighbours, gathered without a branch per candidate (about one candidate in
    // seven is a neighbour, so a branch would mispredict often), then sorted and copied out.
    std::vector<Index> found;
#pragma omp for schedule(dynamic, 16)
    for (Index c = 0; c < cell_count; ++c) {
      std::array<ParticleRange, 9> ranges;
      const int range_count = cells.neighborhood(c, ranges);
      Index candidates = 0;
      for (int r = 0; r < range_count; ++r) candidates += ranges[r].end - ranges[r].begin;
      if (found.size() < static_cast<std::size_t>(candidates)) found.resize(candidates);
      const ParticleRange own = cells.cell(c);
      for (Index k = own.begin; k < own.end; ++k) {
        Index count = 0;
        for (int r = 0; r < range_count; ++r) {
          for (Index j = ranges[r].begin; j < ranges[r].end; ++j) {
            found[count] = order[j];
            count += (j != k) & (p.distance_squared(k, j) < radius_squared);
          }
        }
        // Particles already in cell order (as the solver keeps them) give sorted rows.
        if (!std::is_sorted(found.begin(), found.begin() + count)) {
          std::sort(found.begin(), found.begin() + count);
        }
        std::copy(found.begin(), found.begin() + count,
                  list_.neighbors.begin() + list_.offsets[order[k]]);
      }
    }
  }
}

bool VerletList::needs_rebuild(std::span<const Vec3> x) const {
  if (list_.offsets.empty() || x.size() != x_at_build_.size()) return true;
  const Real half_skin = skin_ / 2;
  const Real limit_squared = half_skin * half_skin;
  const auto n = static_cast<std::int64_t>(x.size());
  bool moved_too_far = false;
  // Written as "not within" so that a NaN position asks for a rebuild, whose cell list then
  // reports the particle instead of searching with a stale list.
#pragma omp parallel for reduction(|| : moved_too_far)
  for (std::int64_t i = 0; i < n; ++i) {
    moved_too_far = moved_too_far || !((x[i] - x_at_build_[i]).squaredNorm() <= limit_squared);
  }
  return moved_too_far;
}

std::vector<Index> spatial_order(std::span<const Vec3> x, Real cell_size) {
  CellList cells;
  cells.build(x, cell_size);
  const std::span<const Index> order = cells.order();
  return {order.begin(), order.end()};
}

}  // namespace spall::neighbors
