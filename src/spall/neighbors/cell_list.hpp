#pragma once
// Cell-linked list: particles binned into cubic cells over their bounding box, stored in cell order.
//
// The grid is virtual: only occupied cells are stored, as a sorted list of row-major cell keys with
// the first particle of each. A huge box with few particles (a fragment flying away from the
// target, a tool far from the part) then costs memory for its particles only, and cells keep the
// size asked for; capping a dense grid instead would make the cells of the dense part larger and
// its search quadratic. A neighbour cell is found by search over the occupied keys, once per cell
// rather than once per particle. Row-major keys put the cells of one (iy, iz) row next to each
// other, so any run of cells along x is one contiguous particle range (trimmed_stencil.hpp).
#include <array>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/bounding_box.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/types.hpp"

namespace spall::neighbors {

// Row-major key of a cell: up to 2^42 cells an axis, so that a far-flung particle does not force
// the cells of everyone else to grow (see CellList::build).
using CellKey = unsigned __int128;

// A contiguous run of positions in CellList::order(), or of particles: [begin, end), which the
// seam's loops run over.
using ParticleRange = parallel::Range;

class CellList {
 public:
  // Bins the particles into cells of edge at least `cell_size` (> 0). Throws InstabilityError
  // when a position is not finite: a NaN in the positions means the run has already blown up.
  // With `tie` (a key a particle, e.g. its node ID), the particles of a cell are in ascending tie
  // order, so the cell order depends on the positions and the keys alone, not on the input order
  // (the storage order, which MPI changes: docs/SCALING.md §2). With `grid`, the grid is that
  // box's (every particle inside it) instead of the particles' own: a rank that bins only the
  // particles near its own gets the cells of the run that bins them all.
  void build(std::span<const Vec3> x, Real cell_size, std::span<const Id> tie = {}, const BoundingBox* grid = nullptr);
  // The list `build` makes, from the particles' keys in a grid given by its corner, cell edge and
  // cells along each axis (another build's, whose particles were binned where they were known).
  void build_from_keys(std::span<const CellKey> key, std::span<const Id> tie, const Vec3& lower, Real cell_size,
                       const std::array<std::int64_t, 3>& cells_along);
  // The edge of the cells `build` makes over `box` when asked for `cell_size`.
  static Real cell_size_over(const BoundingBox& box, Real cell_size);

  // order()[k] is the particle at position k in cell order; within a cell, in ascending tie or,
  // without ties, in input order.
  std::span<const Index> order() const { return order_; }
  // Hands order() over (it is empty afterwards), for a caller that puts its particles in cell
  // order and from then on only needs the cells: their positions in order() are then particle
  // indices.
  std::vector<Index> take_order() { return std::move(order_); }
  Index cell_count() const { return static_cast<Index>(cell_key_.size()) - 1; }
  // The particles of occupied cell c, as positions in order().
  ParticleRange cell(Index c) const { return {cell_start_[c], cell_start_[c + 1]}; }
  // Position in order() of the first particle of occupied cell c; cell_start(cell_count()) is the
  // particle count.
  Index cell_start(Index c) const { return cell_start_[c]; }
  // Key of occupied cell c; cell_key(cell_count()) is larger than any key of a cell.
  CellKey cell_key(Index c) const { return cell_key_[c]; }
  // Cell (ix, iy, iz) of occupied cell c.
  std::array<std::int64_t, 3> coordinates(Index c) const;
  // Cells along x, y, z of the virtual grid; cell (ix, iy, iz) covers
  // lower() + cell_size() * [ix, ix + 1) x [iy, iy + 1) x [iz, iz + 1).
  const std::array<std::int64_t, 3>& cells_along() const { return cells_; }
  // Corner of the grid: the lower corner of the particles' bounding box.
  const Vec3& lower() const { return lower_; }
  CellKey key(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
    return (CellKey(iz) * CellKey(cells_[1]) + CellKey(iy)) * CellKey(cells_[0]) + CellKey(ix);
  }
  // First occupied cell with key >= k (cell_count() when none), searched outwards from cell
  // `hint` (any cell): a few comparisons when the answer lies near it.
  Index first_cell_near(CellKey k, Index hint = 0) const;
  // Edge of the cells actually used: the one asked for, or larger when the box is more than 2^42
  // cells wide.
  Real cell_size() const { return cell_size_; }
  // Bytes held between builds: the order and the occupied cells.
  std::size_t memory_bytes() const {
    return order_.capacity() * sizeof(Index) + cell_key_.capacity() * sizeof(CellKey) +
           cell_start_.capacity() * sizeof(Index);
  }

  void checkpoint(Archive& a) { a(cell_size_, lower_, cells_, order_, cell_key_, cell_start_); }

 private:
  // order_, cell_key_ and cell_start_ from each particle's key.
  void sort_into_cells(std::vector<CellKey>& particle_key, std::span<const Id> tie);

  Real cell_size_ = 0;
  Vec3 lower_ = Vec3::Zero();
  std::array<std::int64_t, 3> cells_{1, 1, 1};  // cells along x, y, z of the virtual grid
  std::vector<Index> order_;
  std::vector<CellKey> cell_key_;  // occupied cells, ascending, and a sentinel past the last
  std::vector<Index> cell_start_;  // cell_count() + 1 entries into order_
};

}  // namespace spall::neighbors
