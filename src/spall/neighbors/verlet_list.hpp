#pragma once
// Neighbour search: a cell-linked list (cell_list.hpp) builds Verlet lists with a skin; particles
// can be put in cell order for memory locality. OpenMP inside; the result never depends on the
// thread count.
#include <algorithm>
#include <limits>
#include <span>
#include <stdexcept>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/bounding_box.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/range_array.hpp"
#include "spall/core/stretch_view.hpp"
#include "spall/core/types.hpp"
#include "spall/core/uninitialized_allocator.hpp"
#include "spall/neighbors/cell_list.hpp"

namespace spall::neighbors {

// Compressed rows: the neighbours of particle i are neighbors[offsets[i] .. offsets[i+1]).
// Full lists (j in i's row and i in j's row), self excluded, each row in the order asked of the
// build (RowOrder). The entries' pages are written by the build's copy alone (no pass of zeros),
// which frees the search's buffers as it goes: the build never holds the list twice.
struct NeighborList {
  std::vector<Index> offsets;
  std::vector<Index, UninitializedAllocator<Index>> neighbors;
  Index count(Index i) const { return offsets[i + 1] - offsets[i]; }
};

// The order of the neighbours within a row: ascending index (what a caller that searches its rows
// or pairs them with each other needs: the SPG bonds), or the order the cell search met them in,
// cell by cell of the search's grid, which keeps neighbours that are close in space next to each
// other in the row and saves sorting (the SPH solid: +10 % on the Taylor bar, docs/PERFORMANCE.md).
// Either order is a function of the positions alone, never of the thread count.
enum class RowOrder { ascending, search };

// A build that bins only some of the particles (a rank's own under MPI and the others' within reach
// of the rows it searches): their indices, ascending, with the grid's box and the largest reach of
// every particle, so that the grid, the cells' order and hence every row searched are those of the
// build that bins them all.
struct BinnedSubset {
  std::span<const Index> particles;
  BoundingBox grid;
  Real largest_reach = 0;
};

class VerletList {
 public:
  // Lists every pair closer than cutoff + skin (cutoff > 0, skin >= 0). The list stays valid
  // (contains every pair closer than cutoff) while needs_rebuild() is false. Throws
  // InstabilityError when a position is not finite. With `rows`, only the rows of the particles
  // [rows.begin, rows.end) are searched, the others left empty: a rank's own particles under MPI,
  // whose rows the other ranks share (the SPG bonds).
  void build(StretchView<Vec3> x, Real cutoff, Real skin,
             ParticleRange rows = {0, std::numeric_limits<Index>::max()});
  // Per-particle reach (every reach_i > 0): lists every pair closer than reach_i + reach_j + skin,
  // and stays valid for the pairs closer than reach_i + reach_j while needs_rebuild() is false.
  // Particles of very different reach then share a list without the small ones listing as far as
  // the largest. cutoff() is twice the largest reach. With `rows`, as above: the rows a rank
  // computes under MPI (the SPH solid's).
  // With `binned`, only its particles are binned (and only their positions and reaches read): each
  // row searched must have all its neighbours among them, and `x` may be a stretch of the particles
  // that holds them (StretchView); without, `x` is every particle's.
  // `reach` may be a stretch that holds the binned particles, as `x`.
  void build(StretchView<Vec3> x, StretchView<Real> reach, Real skin,
             RowOrder order = RowOrder::ascending, ParticleRange rows = {0, std::numeric_limits<Index>::max()},
             const BinnedSubset* binned = nullptr);
  // Whether the last build left rows empty that it was not asked for.
  bool partial() const { return rows_.begin > 0 || rows_.end < count_; }
  // Whether the last build searched every row of `rows`.
  bool searched(ParticleRange rows) const {
    return rows.begin >= rows.end || (rows_.begin <= rows.begin && rows.end <= rows_.end);
  }
  // After a build with per-particle reach: the rows `rows` searched in place of those it searched,
  // from the positions of that build and the same `reach`, each the row a build of every row would
  // have made (the others left empty). Not a build: builds() does not count it. After a build of a
  // binned subset, only once complete_positions has brought in every position. The SPH solid
  // under MPI: the rows a rank computes once it knows the force blocks' length, which the first
  // build's rows give (every row of the list would be every rank's).
  void search_rows(std::span<const Real> reach, ParticleRange rows);
  // search_rows of every row: the list a build of every row would have made.
  void search_every_row(std::span<const Real> reach);
  // search_rows from the positions at the build of the particles `binned` alone (ascending, held
  // here: hold_positions, set_position_at_build) and their reaches, in the grid of the build: each
  // row of `rows` must have all its neighbours among them. Under MPI after a new deal: a rank's new
  // rows from its particles' positions at the build and those near them, from their ranks.
  void search_binned_rows(StretchView<Real> reach, ParticleRange rows, std::span<const Index> binned);
  // After a build of a binned subset, whose positions at the build are all it holds current, or
  // hold_positions: `complete(positions)` makes a RangeArray of every particle's position whole,
  // those held already in place (under MPI, from the ranks that binned each particle, its own).
  // Called whether or not this list holds them all, since under MPI `complete` is the ranks'
  // together.
  template <typename Complete>
  void complete_positions(Complete&& complete) {
    x_at_build_.hold(0, count_);
    complete(x_at_build_);
    subset_ = false;
  }
  // Holds the positions at the build of the particles `keep` from now on: those held already keep
  // theirs, the others are unset until set (set_position_at_build). Under MPI a rank keeps its
  // own, which its rebuild test reads and complete_positions brings to the others
  // (docs/SCALING.md §3, "The list's positions at its build by rank").
  void hold_positions(ParticleRange keep);
  void set_position_at_build(Index p, const Vec3& x) { x_at_build_[p] = x; }
  // The box of every particle's position at the build: the grid it binned them in.
  const BoundingBox& grid() const { return grid_; }
  // The positions at the last build that the list holds: every particle's, or a stretch.
  StretchView<Vec3> positions_at_build() const { return x_at_build_.view(count_); }
  // False while every pair now within the cutoff (reach_i + reach_j) has moved by at most the skin
  // relative to each other since the build, which keeps such pairs in the list (triangle
  // inequality). Checked globally (every displacement within skin / 2 of a common vector: a rigid
  // translation costs no rebuild) and, failing that, between neighbouring cells of the current
  // positions (close_pairs_moved_together): a body that stretches or spins as a whole keeps its
  // list while neighbouring particles move together. True also for a non-finite position, a
  // changed particle count, or no build.
  bool needs_rebuild(StretchView<Vec3> x) const;
  // The same over several ranks, each holding current only the positions of its particles `own`
  // (`x` may be a stretch that holds them): every rank gets the answer one process would give.
  bool needs_rebuild(StretchView<Vec3> x, ParticleRange own, const parallel::Communicator& ranks) const;
  const NeighborList& list() const { return list_; }
  Real cutoff() const { return cutoff_; }
  Real skin() const { return skin_; }
  // Lists built since construction: how often needs_rebuild() said yes, for the benchmarks.
  long long builds() const { return builds_; }
  // Bytes held besides the list itself: the positions saved at the build.
  std::size_t reference_positions_bytes() const { return x_at_build_.capacity_bytes(); }

  // How it searched, not its rows nor where the particles were at the build (the next rebuild
  // depends on it), which the caller writes as it holds them (positions_at_build: under MPI a
  // rank's own) and hands back as it read them (restore_positions): read back, no row is searched,
  // and search_rows (search_binned_rows under MPI) gives each the row this build would have made (a
  // rank's rows, from a file any count of ranks wrote, without every rank holding every row to
  // write or read them).
  void checkpoint(Archive& a) {
    a(count_, order_, cutoff_, skin_, builds_, grid_.lower, grid_.upper, grid_.finite);
    if (!a.reading()) return;
    x_at_build_.clear();
    x_at_build_.resize(0);
    list_.offsets.assign(count_ + 1, 0);
    list_.neighbors.clear();
    rows_ = {0, 0}, subset_ = count_ > 0;  // until restore_positions
  }
  // After a checkpoint is read: the positions at the build of every particle, or of a stretch of
  // them (under MPI a rank's own, as hold_positions keeps them).
  void restore_positions(RangeArray<Vec3> held) {
    if (held.held_begin() < 0 || held.held_end() > count_)
      throw std::logic_error("VerletList::restore_positions: positions of particles the list does not have");
    x_at_build_ = std::move(held);
    subset_ = x_at_build_.held_begin() > 0 || x_at_build_.held_end() < count_;
  }

 private:
  // Lists the pairs within make_radius(cell order).squared(k, j), radius being the largest pair
  // radius.
  template <typename MakeRadius>
  void build_rows(StretchView<Vec3> x, Real radius, const MakeRadius& make_radius, RowOrder order,
                  ParticleRange rows, const BinnedSubset* binned = nullptr);

  // The per-particle reach build's rows (build_reach), searched on every rank alike.
  void build_reach(StretchView<Vec3> x, StretchView<Real> reach, ParticleRange rows,
                   const BinnedSubset* binned = nullptr);

  NeighborList list_;
  // The positions at the build of a stretch of the count_ particles.
  RangeArray<Vec3> x_at_build_;
  Index count_ = 0;
  BoundingBox grid_;
  ParticleRange rows_;  // the rows the last build searched
  // Not every particle's position at the build current here: a build of a binned subset (current
  // there alone) or hold_positions.
  bool subset_ = false;
  RowOrder order_ = RowOrder::ascending;
  Real cutoff_ = 0;
  Real skin_ = 0;
  long long builds_ = 0;
};

// A permutation that puts particles in cell order (cells of `cell_size`, row-major over the cell
// grid of the bounding box, ties in input order): new index k holds the particle formerly at
// order[k].
std::vector<Index> spatial_order(std::span<const Vec3> x, Real cell_size);

}  // namespace spall::neighbors
