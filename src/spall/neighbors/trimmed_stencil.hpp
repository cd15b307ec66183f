#pragma once
// Candidates of a neighbour search on fine cells: with cells of edge radius / m, the particles
// within the radius of a point lie in the (2m + 1)^3 cells around the point's cell (its block),
// and of those only in the cells that come within the radius of the point itself. Per (y, z) row
// of the block that is one run of cells along x, from the row's distance to the point; row-major
// keys make the run one contiguous range of CellList::order(). Rows too far from the point are
// dropped.
//
// Per cell, prepare() makes the table of the cell starts of the block's rows (searches over the
// occupied keys); per particle, trimmed() only looks its runs up in that table. A cell that follows
// the last prepared one along its row of cells shifts the table and searches only the new columns.
//
// Candidates per neighbour in a uniform cloud: the 27 cells of edge 1.1 radius hold
// 27 * 1.1^3 / (4/3 pi) = 8.6 times the ball; the trimmed runs of cells of edge 1.1 radius / 2
// about 2.3 to 2.5 times (docs/PERFORMANCE.md).
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>

#include "spall/core/simd.hpp"
#include "spall/core/types.hpp"
#include "spall/neighbors/cell_list.hpp"

namespace spall::neighbors {

class TrimmedStencil {
 public:
  static constexpr int max_reach = 3;
  static constexpr int max_rows = (2 * max_reach + 1) * (2 * max_reach + 1);
  // Room trimmed() needs: max_rows rounded up to a multiple of eight (the widest double pack).
  static constexpr int range_capacity = (max_rows + 7) / 8 * 8;
  using Ranges = std::array<ParticleRange, range_capacity>;

  // Over `cells`, whose edge must be at least (radius + m) / reach for every radius asked of
  // trimmed(), m being how far the point has moved from where it was binned (reach: 1 to
  // max_reach cells on each side of a particle's cell): the block then holds every particle
  // binned within the radius of the point.
  TrimmedStencil(const CellList& cells, int reach);

  // Makes the cell starts of the rows of the block around occupied cell c.
  void prepare(Index c);
  // Every particle of the prepared block, as one range of positions in order() per row of cells
  // (some may be empty), in ascending order; returns how many were written.
  int block(Ranges& ranges) const;
  // A superset of the particles of the prepared block closer than `radius` to the point at
  // `offset` (its position minus cells.lower()), as one range per row of cells (empty for a row
  // out of reach), in ascending order; returns how many were written. The particles are taken
  // where they were binned: a caller whose particles have since moved widens the radius by the
  // largest move. The point may lie outside the prepared cell (it too may have moved).
  int trimmed(const Vec3& offset, Real radius, Ranges& ranges) const { return trimmed(offset, offset, radius, ranges); }
  // The same for every point of the box [lower, upper] (offsets as above): a superset of the
  // particles closer than `radius` to any point of the box, each row's run covering the runs of
  // all of its points.
  inline int trimmed(const Vec3& lower, const Vec3& upper, Real radius, Ranges& ranges) const;

 private:
  // start_[k * range_capacity + r]: the first particle of the cells x >= ix - reach + k of row r,
  // k = 0 .. 2 reach + 1.
  Index& start(int k, int r) { return start_[k * range_capacity + r]; }
  Index start(int k, int r) const { return start_[k * range_capacity + r]; }
  // Records column k of row r: moves next_cell_[r], which is at the first occupied cell of column
  // k - 1 or later, to the first of column k or later (one step: keys are distinct integers).
  void step(int k, int r);

  const CellList& cells_;
  int reach_;
  Real inverse_edge_;
  // Rounding of the positions in cell units: at most a few ulps of the largest cell coordinate.
  Real slack_;

  // The prepared cell and its block.
  bool prepared_ = false;
  std::int64_t ix_ = 0, iy_ = 0, iz_ = 0;
  Vec3 corner_ = Vec3::Zero();  // the block's lower cell (ix, iy, iz) - reach, in cell units
  int row_count_ = 0;           // rows of the block inside the grid, in key order
  // A row's y and z from the block corner (0 for the lanes past row_count_).
  std::array<std::int32_t, range_capacity> row_y_{}, row_z_{};
  std::array<CellKey, max_rows> row_key_{};    // key of cell x = 0 of the row
  std::array<Index, max_rows> next_cell_{};    // occupied cell the row's walk stopped at
  std::array<Index, (2 * max_reach + 2) * range_capacity> start_{};
};

// Called once per particle or box: inline, a pack of rows at a time (simd::Pack: eight doubles
// with AVX-512, four with AVX2), without a branch per row.
int TrimmedStencil::trimmed(const Vec3& lower, const Vec3& upper, Real radius, Ranges& ranges) const {
  using P = simd::Pack;
  static_assert(range_capacity % P::width == 0);
  constexpr int slab_count = 2 * max_reach + 1;
  const int width = 2 * reach_ + 1;
  // The box relative to the block corner, in cell units: cell (i, j, k) of the block covers
  // [i, i + 1) x [j, j + 1) x [k, k + 1).
  const Vec3 lo = lower * inverse_edge_ - corner_, hi = upper * inverse_edge_ - corner_;
  const Real reach = radius * inverse_edge_ * (1 + 1e-9) + slack_;
  // Squared distance from the box to the slab of cells j along y (and along z).
  std::array<Real, slab_count> gap_y, gap_z;
  for (int j = 0; j < slab_count; ++j) {
    const Real y = std::max({Real(0), j - hi.y(), lo.y() - (j + 1)});
    const Real z = std::max({Real(0), j - hi.z(), lo.z() - (j + 1)});
    gap_y[j] = y * y;
    gap_z[j] = z * z;
  }
  // Row r reaches when left = reach^2 - gap_y^2 - gap_z^2 >= 0; its cells i in reach are those
  // with [i, i + 1] meeting [lo.x - sqrt(left), hi.x + sqrt(left)]. A row out of reach gets
  // first = past_last. min after max keeps a NaN inside the block (max takes its second operand
  // where a lane is NaN).
  const P lx(lo.x()), hx(hi.x()), r2(reach * reach), zero(0), one(1), last(width - 1);
  for (int r = 0; r < row_count_; r += P::width) {
    const P left = r2 - P::template gather<1>(gap_y.data(), &row_y_[r]) - P::template gather<1>(gap_z.data(), &row_z_[r]);
    const P half = sqrt(max(left, zero));
    const P first = min(max(floor(lx - half), zero), last);
    const P past_last = select(left < zero, first, min(max(floor(hx + half), zero), last) + one);
    alignas(64) Real firsts[P::width], pasts[P::width];
    first.store(firsts);
    past_last.store(pasts);
    for (int i = 0; i < P::width; ++i)
      ranges[r + i] = {start(static_cast<int>(firsts[i]), r + i), start(static_cast<int>(pasts[i]), r + i)};
  }
  return row_count_;
}

}  // namespace spall::neighbors
