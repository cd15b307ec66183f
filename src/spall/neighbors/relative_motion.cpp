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
// particles (a fragment flying far from the rest) is not built: the answer is then false. Over
// several ranks (the grid every rank's: its corner and extent from the merged position box), each
// bins its own particles and tests the pairs whose lower cell lies from its first occupied cell to
// its last, with the other ranks' boxes of the cells those pairs reach brought in (their boxes
// overlap where the ranks' particles meet, a layer of cells between neighbouring ranks' slabs), and
// the answers are or-ed: the boxes and the answer one process would have.
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

// The particles a rank reads, [first, first + count), and the ranks whose particles make up the
// whole (none: this process holds them all).
struct Share {
  std::int64_t first = 0, count = 0;
  const parallel::Communicator* ranks = nullptr;
};

// Each box merged with the other ranks' box of the same place: the minimum of the lower corners
// and of the negated upper ones, and the finite flags as 0 / -1, in one reduction.
void merge_over_ranks(std::span<Box> boxes, const Share& share) {
  if (!share.ranks || share.ranks->size() == 1) return;
  std::vector<double> bounds(7 * boxes.size());
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    for (int k = 0; k < 3; ++k) bounds[7 * b + k] = boxes[b].lower[k], bounds[7 * b + 3 + k] = -boxes[b].upper[k];
    bounds[7 * b + 6] = boxes[b].finite ? 0 : -1;
  }
  share.ranks->minimum(bounds);
  for (std::size_t b = 0; b < boxes.size(); ++b) {
    for (int k = 0; k < 3; ++k) boxes[b].lower[k] = bounds[7 * b + k], boxes[b].upper[k] = -bounds[7 * b + 3 + k];
    boxes[b].finite = bounds[7 * b + 6] == 0;
  }
}

// Boxes as 7 doubles each (lower corner, upper corner, finite as 1 / 0), to travel.
void pack(const Box& box, double* out) {
  for (int k = 0; k < 3; ++k) out[k] = box.lower[k], out[3 + k] = box.upper[k];
  out[6] = box.finite ? 1 : 0;
}
Box unpack(const double* in) {
  Box box;
  for (int k = 0; k < 3; ++k) box.lower[k] = in[k], box.upper[k] = in[3 + k];
  box.finite = in[6] != 0;
  return box;
}

struct CellRange {
  std::int64_t first = 0, last = 0;
};

// The cells whose pairs this rank tests, from the first to the last cell its own particles are in;
// under MPI the other ranks' boxes of the cells those pairs reach (each pair once, towards higher
// cells: up to `reach` cells further along) are merged into `boxes`. Every pair of occupied cells
// is then tested by the rank of its lower cell, with the boxes of every rank's particles.
CellRange merge_reached_cells(std::span<Box> boxes, std::int64_t reach, const Share& share) {
  const auto cell_count = static_cast<std::int64_t>(boxes.size());
  CellRange own{0, cell_count};
  if (!share.ranks || share.ranks->size() == 1) return own;
  while (own.first < cell_count && boxes[own.first].empty()) ++own.first;
  own.last = cell_count;
  while (own.last > own.first && boxes[own.last - 1].empty()) --own.last;
  const parallel::Communicator& ranks = *share.ranks;
  const int size = ranks.size(), me = ranks.rank();
  const std::vector<CellRange> ranges = ranks.each(own);
  // Rank q's cells that rank r's pairs read: [first_r, last_r + reach) within [first_q, last_q).
  const auto read = [&](int r, int q) {
    const std::int64_t first = std::max(ranges[r].first, ranges[q].first);
    const std::int64_t last = std::min(ranges[r].last + reach, ranges[q].last);
    return CellRange{first, std::max(first, last)};
  };
  std::vector<Index> send_offsets(size + 1, 0), receive_offsets(size + 1, 0);
  for (int q = 0; q < size; ++q) {
    const CellRange out = q == me ? CellRange{} : read(q, me), in = q == me ? CellRange{} : read(me, q);
    send_offsets[q + 1] = send_offsets[q] + 7 * (out.last - out.first);
    receive_offsets[q + 1] = receive_offsets[q] + 7 * (in.last - in.first);
  }
  std::vector<double> send(send_offsets[size]), receive(receive_offsets[size]);
  for (int q = 0; q < size; ++q) {
    if (q == me) continue;
    const CellRange out = read(q, me);
    for (std::int64_t c = out.first; c < out.last; ++c) pack(boxes[c], &send[send_offsets[q] + 7 * (c - out.first)]);
  }
  ranks.exchange(std::span<const double>(send), send_offsets, std::span(receive), receive_offsets);
  for (int q = 0; q < size; ++q) {
    if (q == me) continue;
    const CellRange in = read(me, q);
    for (std::int64_t c = in.first; c < in.last; ++c)
      boxes[c].include(unpack(&receive[receive_offsets[q] + 7 * (c - in.first)]));
  }
  return own;
}

bool any_over_ranks(bool mine, const Share& share) {
  if (!share.ranks || share.ranks->size() == 1) return mine;
  return share.ranks->any(mine);
}

// Global test (1): every displacement within limit / 2 of the centre of their box.
bool within_half_limit_of_centre(StretchView<Vec3> x, StretchView<Vec3> before, const Box& d, Real limit,
                                 const Share& share) {
  const Vec3 centre = d.centre();
  const Real half = limit / 2;
  const Real half_squared = half * half;
  const bool outside = parallel::reduce_exact(
      share.count, false,
      [&](std::int64_t k) {
        const std::int64_t i = share.first + k;
        return !((x[i] - before[i] - centre).squaredNorm() <= half_squared);
      },
      std::logical_or<>());
  return !any_over_ranks(outside, share);
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
bool neighbouring_cells_moved_together(StretchView<Vec3> x, StretchView<Vec3> before,
                                       const Grid& grid, Real limit, const Share& share) {
  const std::int64_t cell_count = grid.count();
  // One box per cell and thread, merged after: min and max are exact, so the merged boxes do not
  // depend on which thread saw which particle.
  const int threads = parallel::thread_count();
  std::vector<Box> boxes(static_cast<std::size_t>(threads) * cell_count);
  parallel::region([&](const parallel::Team& team) {
    Box* mine = boxes.data() + static_cast<std::int64_t>(team.index()) * cell_count;
    team.for_each(share.count, [&](std::int64_t k) {
      const std::int64_t i = share.first + k;
      mine[grid.cell_of(x[i])].include(x[i] - before[i]);
    });
  });
  parallel::for_each(cell_count, [&](std::int64_t c) {
    for (int t = 1; t < threads; ++t) boxes[c].include(boxes[t * cell_count + c]);
  });
  const auto [nx, ny, nz] = grid.cells;
  const CellRange tested = merge_reached_cells(std::span(boxes).first(cell_count), nx * ny + nx + 1, share);

  const Real limit_squared = limit * limit;
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
  const bool apart = parallel::reduce_exact(
      tested.last - tested.first, false, [&](std::int64_t k) { return cell_apart(tested.first + k); },
      std::logical_or<>());
  return !any_over_ranks(apart, share);
}

bool moved_together(StretchView<Vec3> x, StretchView<Vec3> before, Real distance, Real limit,
                    const Share& share) {
  const auto n = static_cast<std::int64_t>(x.size());
  if (n == 0) return true;
  // Boxes of the positions and of the displacements, and whether every displacement is finite (a
  // NaN would slip through min and max).
  struct Boxes {
    Box position, displacement;
  };
  auto [position, displacement] = parallel::fold_exact(
      share.count, Boxes{},
      [&](Boxes& b, std::int64_t k) {
        const std::int64_t i = share.first + k;
        b.position.include(x[i]);
        b.displacement.include(x[i] - before[i]);
      },
      [](Boxes& b, const Boxes& other) {
        b.position.include(other.position);
        b.displacement.include(other.displacement);
      });
  Box both[2] = {position, displacement};
  merge_over_ranks(both, share);
  position = both[0], displacement = both[1];
  if (!displacement.finite) return false;
  if (within_half_limit_of_centre(x, before, displacement, limit, share)) return true;

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
  return neighbouring_cells_moved_together(x, before, grid, limit, share);
}

}  // namespace

bool close_pairs_moved_together(StretchView<Vec3> x, StretchView<Vec3> before, Real distance,
                                Real limit) {
  return moved_together(x, before, distance, limit, {0, static_cast<std::int64_t>(x.size()), nullptr});
}

bool close_pairs_moved_together(StretchView<Vec3> x, StretchView<Vec3> before, Real distance, Real limit,
                                ParticleRange own, const parallel::Communicator& ranks) {
  return moved_together(x, before, distance, limit, {own.begin, own.end - own.begin, &ranks});
}

}  // namespace spall::neighbors
