#include "spall/neighbors/trimmed_stencil.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>

namespace spall::neighbors {

TrimmedStencil::TrimmedStencil(const CellList& cells, int reach)
    : cells_(cells), reach_(reach), inverse_edge_(1 / cells.cell_size()) {
  if (reach < 1 || reach > max_reach)
    throw std::invalid_argument("neighbour search: the stencil reaches 1 to 3 cells");
  // A position in cell units is (x - lower) / edge, rounded like the binning in CellList::build;
  // its error and that of the block-relative coordinate are a few ulps of the largest one.
  const auto& along = cells.cells_along();
  const Real largest = static_cast<Real>(std::max({along[0], along[1], along[2]})) + 2 * reach + 2;
  slack_ = 64 * std::numeric_limits<Real>::epsilon() * largest;
}

void TrimmedStencil::step(int k, int r) {
  // Column x clamped to [0, cells along x]: the key past the row's last cell is the next row's
  // first, so the walk never leaves the row. Consecutive columns differ by at most one key, and
  // the cell list ends in a sentinel key, so one conditional step suffices.
  const std::int64_t x = std::clamp<std::int64_t>(ix_ - reach_ + k, 0, cells_.cells_along()[0]);
  const Index j = next_cell_[r] + (cells_.cell_key(next_cell_[r]) < row_key_[r] + CellKey(x));
  next_cell_[r] = j;
  start(k, r) = cells_.cell_start(j);
}

void TrimmedStencil::prepare(Index c) {
  const auto [ix, iy, iz] = cells_.coordinates(c);
  const int columns = 2 * reach_ + 2;  // the starts of 2 reach + 1 cells and the end of the last
  if (prepared_ && iy == iy_ && iz == iz_ && ix > ix_ && ix - ix_ < columns) {
    // The next cell along the same row of cells: the block moves by `shift` columns, the rows stay.
    const int shift = static_cast<int>(ix - ix_);
    std::copy(start_.begin() + shift * range_capacity, start_.begin() + columns * range_capacity,
              start_.begin());
    ix_ = ix;
    corner_.x() = static_cast<Real>(ix - reach_);
    for (int k = columns - shift; k < columns; ++k)
      for (int r = 0; r < row_count_; ++r) step(k, r);
    return;
  }
  const Index first_row_hint = prepared_ && row_count_ > 0 ? next_cell_[0] : 0;
  prepared_ = true;
  ix_ = ix, iy_ = iy, iz_ = iz;
  corner_ = Vec3(static_cast<Real>(ix - reach_), static_cast<Real>(iy - reach_),
                 static_cast<Real>(iz - reach_));
  const auto& along = cells_.cells_along();
  row_count_ = 0;
  for (int jz = 0; jz <= 2 * reach_; ++jz) {
    const std::int64_t z = iz - reach_ + jz;
    if (z < 0 || z >= along[2]) continue;
    for (int jy = 0; jy <= 2 * reach_; ++jy) {
      const std::int64_t y = iy - reach_ + jy;
      if (y < 0 || y >= along[1]) continue;
      const int r = row_count_++;
      row_y_[r] = jy;
      row_z_[r] = jz;
      row_key_[r] = cells_.key(0, y, z);
      // Rows come in key order, so each search starts where the previous row's ended; the first
      // where the last block's first row did (the thread's previous cell is mostly nearby).
      const Index hint = r > 0 ? next_cell_[r - 1] : first_row_hint;
      next_cell_[r] = cells_.first_cell_near(row_key_[r] + CellKey(std::max<std::int64_t>(ix - reach_, 0)), hint);
      start(0, r) = cells_.cell_start(next_cell_[r]);
      for (int k = 1; k < columns; ++k) step(k, r);
    }
  }
}

int TrimmedStencil::block(Ranges& ranges) const {
  for (int r = 0; r < row_count_; ++r) ranges[r] = {start(0, r), start(2 * reach_ + 1, r)};
  return row_count_;
}

}  // namespace spall::neighbors
