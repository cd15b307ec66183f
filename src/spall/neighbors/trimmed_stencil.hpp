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
#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include "spall/core/simd.hpp"
#include "spall/core/types.hpp"
#include "spall/neighbors/cell_list.hpp"

namespace spall::neighbors {

class TrimmedStencil {
 public:
  static constexpr int max_reach = 3;
  static constexpr int max_rows = (2 * max_reach + 1) * (2 * max_reach + 1);
  // Room trimmed() needs: max_rows rounded up to the eight lanes it works in.
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

// Called once per particle or box: inline, eight rows at a time with AVX-512 (double precision)
// or AVX2 (single precision, the reach widened to cover its rounding), without a branch per row.
int TrimmedStencil::trimmed(const Vec3& lower, const Vec3& upper, Real radius, Ranges& ranges) const {
  // The slabs of the widest block, and one more: the AVX-512 path holds all eight in a register.
  constexpr int slab_count = 2 * max_reach + 2;
  const int width = 2 * reach_ + 1;
  // The box relative to the block corner, in cell units: cell (i, j, k) of the block covers
  // [i, i + 1) x [j, j + 1) x [k, k + 1).
  const Vec3 lo = lower * inverse_edge_ - corner_, hi = upper * inverse_edge_ - corner_;
  const Real reach = radius * inverse_edge_ * (1 + 1e-9) + slack_;
  // Squared distance from the box to the slab of cells j along y (and along z).
  alignas(64) std::array<Real, slab_count> gap_y, gap_z;
  for (int j = 0; j < slab_count; ++j) {
    const Real y = std::max({Real(0), j - hi.y(), lo.y() - (j + 1)});
    const Real z = std::max({Real(0), j - hi.z(), lo.z() - (j + 1)});
    gap_y[j] = y * y;
    gap_z[j] = z * z;
  }
  // Row r reaches when left = reach^2 - gap_y^2 - gap_z^2 >= 0; its cells i in reach are those
  // with [i, i + 1] meeting [lo.x - sqrt(left), hi.x + sqrt(left)]. A row out of reach gets
  // first = past_last; min after max keeps a NaN inside the block.
  const Real last_cell = width - 1;
#if defined(SPALL_SIMD_AVX512)
  const __m512d lx = _mm512_set1_pd(lo.x()), hx = _mm512_set1_pd(hi.x()), r2 = _mm512_set1_pd(reach * reach);
  const __m512d zero = _mm512_setzero_pd(), one = _mm512_set1_pd(1), last = _mm512_set1_pd(last_cell);
  const __m512d all_gap_y = _mm512_load_pd(gap_y.data()), all_gap_z = _mm512_load_pd(gap_z.data());
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i stride = _mm256_set1_epi32(range_capacity);
  // Lane 2i of a pair of begins and ends is begin i, lane 2i + 1 end i (of the second operand).
  const __m512i interleave = _mm512_setr_epi32(0, 16, 1, 17, 2, 18, 3, 19, 4, 20, 5, 21, 6, 22, 7, 23);
  for (int r = 0; r < row_count_; r += 8) {
    const __m512i y = _mm512_cvtepi32_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(&row_y_[r])));
    const __m512i z = _mm512_cvtepi32_epi64(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(&row_z_[r])));
    const __m512d left = _mm512_sub_pd(_mm512_sub_pd(r2, _mm512_permutexvar_pd(y, all_gap_y)),
                                       _mm512_permutexvar_pd(z, all_gap_z));
    const __m512d half = _mm512_sqrt_pd(_mm512_max_pd(left, zero));
    const __m512d first = _mm512_min_pd(_mm512_max_pd(_mm512_floor_pd(_mm512_sub_pd(lx, half)), zero), last);
    const __m512d past_last = _mm512_mask_add_pd(
        first, _mm512_cmp_pd_mask(left, zero, _CMP_GE_OQ),
        _mm512_min_pd(_mm512_max_pd(_mm512_floor_pd(_mm512_add_pd(hx, half)), zero), last), one);
    // Index of start(k, r) for the eight rows.
    const __m256i row = _mm256_add_epi32(_mm256_set1_epi32(r), lane);
    const __m256i begin = _mm256_i32gather_epi32(
        start_.data(), _mm256_add_epi32(_mm256_mullo_epi32(_mm512_cvttpd_epi32(first), stride), row), 4);
    const __m256i end = _mm256_i32gather_epi32(
        start_.data(), _mm256_add_epi32(_mm256_mullo_epi32(_mm512_cvttpd_epi32(past_last), stride), row), 4);
    _mm512_storeu_si512(&ranges[r], _mm512_permutex2var_epi32(_mm512_castsi256_si512(begin), interleave,
                                                               _mm512_castsi256_si512(end)));
  }
#elif defined(__AVX2__)
  // Eight rows at a time in single precision: the slab gaps of the block (at most eight slabs,
  // one register) picked by row with a permute, one 8-lane square root where double precision
  // took two 4-lane ones and four gathers. Single precision errs by about 1e-6 of the cell, so
  // the reach is widened by 1e-4 of a cell: the runs stay a superset (a particle within 1e-4
  // of a cell from the ball's edge may add that cell).
  static_assert(slab_count == 8 && range_capacity % 8 == 0);
  const float widened = static_cast<float>(reach + 1e-4);
  const __m256 lx = _mm256_set1_ps(static_cast<float>(lo.x())), hx = _mm256_set1_ps(static_cast<float>(hi.x()));
  const __m256 r2 = _mm256_set1_ps(widened * widened);
  const __m256 zero = _mm256_setzero_ps(), one = _mm256_set1_ps(1), last = _mm256_set1_ps(static_cast<float>(last_cell));
  const auto to_floats = [](const Real* eight) {
    return _mm256_set_m128(_mm256_cvtpd_ps(_mm256_load_pd(eight + 4)), _mm256_cvtpd_ps(_mm256_load_pd(eight)));
  };
  const __m256 all_gap_y = to_floats(gap_y.data()), all_gap_z = to_floats(gap_z.data());
  const __m256i lane = _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7);
  const __m256i stride = _mm256_set1_epi32(range_capacity);
  for (int r = 0; r < row_count_; r += 8) {
    const __m256i y = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&row_y_[r]));
    const __m256i z = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(&row_z_[r]));
    const __m256 left = _mm256_sub_ps(_mm256_sub_ps(r2, _mm256_permutevar8x32_ps(all_gap_y, y)),
                                      _mm256_permutevar8x32_ps(all_gap_z, z));
    const __m256 half = _mm256_sqrt_ps(_mm256_max_ps(left, zero));
    const __m256 first = _mm256_min_ps(_mm256_max_ps(_mm256_floor_ps(_mm256_sub_ps(lx, half)), zero), last);
    __m256 past_last = _mm256_add_ps(
        _mm256_min_ps(_mm256_max_ps(_mm256_floor_ps(_mm256_add_ps(hx, half)), zero), last), one);
    past_last = _mm256_blendv_ps(first, past_last, _mm256_cmp_ps(left, zero, _CMP_GE_OQ));
    // Index of start(k, r) for the eight rows.
    const __m256i row = _mm256_add_epi32(_mm256_set1_epi32(r), lane);
    const __m256i begin = _mm256_i32gather_epi32(
        start_.data(), _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(first), stride), row), 4);
    const __m256i end = _mm256_i32gather_epi32(
        start_.data(), _mm256_add_epi32(_mm256_mullo_epi32(_mm256_cvttps_epi32(past_last), stride), row), 4);
    // (begin, end) pairs of rows r .. r + 7: unpack within the 128-bit lanes gives rows 0, 1, 4, 5
    // and 2, 3, 6, 7; the lane swap puts them in order.
    const __m256i low = _mm256_unpacklo_epi32(begin, end), high = _mm256_unpackhi_epi32(begin, end);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(&ranges[r]), _mm256_permute2x128_si256(low, high, 0x20));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(&ranges[r + 4]), _mm256_permute2x128_si256(low, high, 0x31));
  }
#else
  for (int r = 0; r < row_count_; ++r) {
    const Real left = reach * reach - gap_y[row_y_[r]] - gap_z[row_z_[r]];
    const Real half = std::sqrt(std::fmax(left, Real(0)));
    const Real first = std::fmin(std::fmax(std::floor(lo.x() - half), Real(0)), last_cell);
    const Real past_last = left >= 0 ? std::fmin(std::fmax(std::floor(hi.x() + half), Real(0)), last_cell) + 1 : first;
    ranges[r] = {start(static_cast<int>(first), r), start(static_cast<int>(past_last), r)};
  }
#endif
  return row_count_;
}

}  // namespace spall::neighbors
