#include "spall/neighbors/relative_motion.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <functional>
#include <vector>

#include "spall/core/bounding_box.hpp"
#include "spall/core/parallel.hpp"

namespace spall::neighbors {

// Why the answer is safe. Write d = x - before, and let the pair (i, j) be now closer than
// `distance`. Two tests, either of which suffices:
//
// 1. Global: every d_i lies within limit / 2 of one vector c, the centre of the displacements'
//    bounding box. Then |d_i - d_j| <= |d_i - c| + |c - d_j| <= limit for every pair (triangle
//    inequality). A rigid translation of any size passes.
//
// 2. Local: bin the particles by their CURRENT positions into cubic cells of edge C >= distance.
//    Along each axis |x_i - x_j| < distance <= C, so the cell indices of i and j differ by at most
//    one: their cells A and B are the same or neighbours among the 27 around A. Let [l_A, u_A] be
//    the bounding box of the d of cell A's particles. Each component of d_i - d_j then lies in
//    [l_A - u_B, u_A - l_B], so |d_i - d_j| <= |e_AB| with e_AB = max(u_A - l_B, u_B - l_A)
//    componentwise. If |e_AB| <= limit for every pair of occupied neighbouring cells (A = B
//    included), every close pair has moved by at most limit relative to each other. The bound
//    follows the local spread of the motion: a body stretching or spinning as a whole passes while
//    its two ends move apart by many times the limit, since only the motion across about two
//    cells enters.
//
// Binning the current positions rather than those of `before` keeps the stencil at one cell
// whatever the displacements: pairs that were far apart and are now close are found as well.
// The cell edge is `distance` enlarged by 2^-20, so that rounding in the cell index (a relative
// 2^-52 of an index below the particle count) cannot put a close pair two cells apart. The
// remaining rounding, in the bounds and their norms, is a few units in the last place of the
// displacements: of the order of the rounding of the neighbour search's own distance test.
//
// Cost: three passes over the particles (boxes, global test, binning) and two over the cells
// (merging the threads' boxes, then 14 neighbour pairs each: the bound is symmetric in A and B). A grid with more cells than
// particles (a fragment flying far from the rest) is not built: the answer is then false.
namespace {

using Box = BoundingBox;

// The largest |d_i - d_j| for d_i in box a and d_j in box b, bounded by |e_ab| (see above); squared.
Real largest_difference_squared(const Box& a, const Box& b) {
  Real sum = 0;
  for (int k = 0; k < 3; ++k) {
    const Real e = std::max(a.upper[k] - b.lower[k], b.upper[k] - a.lower[k]);
    sum += e * e;
  }
  return sum;
}

// Global test (1): every displacement within limit / 2 of the centre of their box.
bool within_half_limit_of_centre(std::span<const Vec3> x, std::span<const Vec3> before, const Box& d,
                                 Real limit) {
  const auto n = static_cast<std::int64_t>(x.size());
  const Vec3 centre = d.centre();
  const Real half = limit / 2;
  const Real half_squared = half * half;
  const bool outside = parallel::reduce_exact(
      n, false, [&](std::int64_t i) { return !((x[i] - before[i] - centre).squaredNorm() <= half_squared); },
      std::logical_or<>());
  return !outside;
}

// Dense grid of cells of edge `edge` over the box of the current positions.
struct Grid {
  Vec3 origin;
  std::array<std::int64_t, 3> cells;
  Real inverse_edge;

  std::int64_t count() const { return cells[0] * cells[1] * cells[2]; }
  std::int64_t cell_of(const Vec3& p) const {
    std::array<std::int64_t, 3> c;
    for (int a = 0; a < 3; ++a) {
      const auto i = static_cast<std::int64_t>((p[a] - origin[a]) * inverse_edge);
      c[a] = std::clamp<std::int64_t>(i, 0, cells[a] - 1);
    }
    return (c[2] * cells[1] + c[1]) * cells[0] + c[0];
  }
};

// Local test (2), on a grid of at most as many cells as particles.
bool neighbouring_cells_moved_together(std::span<const Vec3> x, std::span<const Vec3> before,
                                       const Grid& grid, Real limit) {
  const auto n = static_cast<std::int64_t>(x.size());
  const std::int64_t cell_count = grid.count();
  // One box per cell and thread, merged after: min and max are exact, so the merged boxes do not
  // depend on which thread saw which particle.
  const int threads = parallel::thread_count();
  std::vector<Box> boxes(static_cast<std::size_t>(threads) * cell_count);
  parallel::region([&](const parallel::Team& team) {
    Box* mine = boxes.data() + static_cast<std::int64_t>(team.index()) * cell_count;
    team.for_each(n, [&](std::int64_t i) { mine[grid.cell_of(x[i])].include(x[i] - before[i]); });
  });
  parallel::for_each(cell_count, [&](std::int64_t c) {
    for (int t = 1; t < threads; ++t) boxes[c].include(boxes[t * cell_count + c]);
  });

  const Real limit_squared = limit * limit;
  const auto [nx, ny, nz] = grid.cells;
  const auto cell_apart = [&](std::int64_t c) {
    const Box& a = boxes[c];
    if (a.empty()) return false;
    bool apart = false;
    const std::int64_t ix = c % nx, iy = (c / nx) % ny, iz = c / (nx * ny);
    for (std::int64_t z = std::max<std::int64_t>(iz - 1, 0); z <= std::min(iz + 1, nz - 1); ++z)
      for (std::int64_t y = std::max<std::int64_t>(iy - 1, 0); y <= std::min(iy + 1, ny - 1); ++y)
        for (std::int64_t x_cell = std::max<std::int64_t>(ix - 1, 0); x_cell <= std::min(ix + 1, nx - 1);
             ++x_cell) {
          const std::int64_t other = (z * ny + y) * nx + x_cell;
          // Each unordered pair once: the bound is symmetric.
          if (other < c || boxes[other].empty()) continue;
          apart = apart || !(largest_difference_squared(a, boxes[other]) <= limit_squared);
        }
    return apart;
  };
  return !parallel::reduce_exact(cell_count, false, cell_apart, std::logical_or<>());
}

}  // namespace

bool close_pairs_moved_together(std::span<const Vec3> x, std::span<const Vec3> before, Real distance,
                                Real limit) {
  const auto n = static_cast<std::int64_t>(x.size());
  if (n == 0) return true;
  // Boxes of the positions and of the displacements, and whether every displacement is finite (a
  // NaN would slip through min and max).
  struct Boxes {
    Box position, displacement;
  };
  const auto [position, displacement] = parallel::fold_exact(
      n, Boxes{},
      [&](Boxes& b, std::int64_t i) {
        b.position.include(x[i]);
        b.displacement.include(x[i] - before[i]);
      },
      [](Boxes& b, const Boxes& other) {
        b.position.include(other.position);
        b.displacement.include(other.displacement);
      });
  if (!displacement.finite) return false;
  if (within_half_limit_of_centre(x, before, displacement, limit)) return true;

  Grid grid;
  grid.origin = position.lower;
  const Real edge = distance * (1 + 0x1p-20);
  grid.inverse_edge = 1 / edge;
  Real cells = 1;
  for (int a = 0; a < 3; ++a) {
    const Real along = std::floor((position.upper[a] - position.lower[a]) / edge) + 1;
    cells *= along;
    if (!(cells <= Real(n))) return false;  // also when the extent overflowed
    grid.cells[a] = static_cast<std::int64_t>(along);
  }
  return neighbouring_cells_moved_together(x, before, grid, limit);
}

}  // namespace spall::neighbors
