#pragma once
// Cell-linked list: particles binned into cubic cells over their bounding box, stored in cell order.
//
// The grid is virtual: only occupied cells are stored, as a sorted list of row-major cell keys with
// the first particle of each. A huge box with few particles (a fragment flying away from the
// target, a tool far from the part) then costs memory for its particles only, and cells keep the
// size asked for; capping a dense grid instead would make the cells of the dense part larger and
// its search quadratic. A neighbour cell is found by binary search over the occupied keys, once per
// cell rather than once per particle. Row-major keys put the three cells (ix-1, ix, ix+1) of one
// (iy, iz) row next to each other, so the 27 cells around a cell are 9 contiguous particle ranges.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::neighbors {

// Row-major key of a cell: up to 2^42 cells an axis, so that a far-flung particle does not force
// the cells of everyone else to grow (see CellList::build).
using CellKey = unsigned __int128;

// A contiguous run of positions in CellList::order(): [begin, end).
struct ParticleRange {
  Index begin = 0;
  Index end = 0;
};

class CellList {
 public:
  // Bins the particles into cells of edge at least `cell_size` (> 0). Throws InstabilityError
  // when a position is not finite: a NaN in the positions means the run has already blown up.
  void build(std::span<const Vec3> x, Real cell_size);

  // order()[k] is the particle at position k in cell order; within a cell, input order is kept.
  std::span<const Index> order() const { return order_; }
  Index cell_count() const { return static_cast<Index>(cell_key_.size()); }
  // The particles of occupied cell c, as positions in order().
  ParticleRange cell(Index c) const { return {cell_start_[c], cell_start_[c + 1]}; }
  // The particles of the (up to 27) occupied cells around and including cell c, as at most 9
  // ranges of positions in order(); returns how many ranges were written.
  int neighborhood(Index c, std::array<ParticleRange, 9>& ranges) const;
  // Edge of the cells actually used: the one asked for, or larger when the box is more than 2^42
  // cells wide.
  Real cell_size() const { return cell_size_; }
  // Bytes held between builds: the order and the occupied cells.
  std::size_t memory_bytes() const {
    return order_.capacity() * sizeof(Index) + cell_key_.capacity() * sizeof(CellKey) +
           cell_start_.capacity() * sizeof(Index);
  }

 private:
  CellKey key(std::int64_t ix, std::int64_t iy, std::int64_t iz) const {
    return (CellKey(iz) * CellKey(cells_[1]) + CellKey(iy)) * CellKey(cells_[0]) + CellKey(ix);
  }
  // First occupied cell with key >= k (cell_count() when none).
  Index first_cell_from(CellKey k) const;

  Real cell_size_ = 0;
  std::array<std::int64_t, 3> cells_{1, 1, 1};  // cells along x, y, z of the virtual grid
  std::vector<Index> order_;
  std::vector<CellKey> cell_key_;  // occupied cells, ascending
  std::vector<Index> cell_start_;  // cell_count() + 1 entries into order_
};

}  // namespace spall::neighbors
