#pragma once
// The blocks of the SPH solid's pair-once force pass (SolidFormulation::compute_pair_forces):
// particles [j L, (j + 1) L), L the neighbour list's largest b - a, so that block j's half rows
// (the pairs with b > a, each added to a and taken from b) touch blocks j and j + 1 only. The even
// blocks run first, side by side, then the odd ones: every particle's pair sum is taken in one
// order, its even block's terms first, whatever the thread count.
//
// Under MPI each block is run by one rank, the owner of its middle particle, and the partial sums
// travel between the halves so that the order stays the serial one: after the even blocks, the
// sums of the particles an odd block adds to go to its runner (the odd block's own particles from
// the block before's runner, the next block's from that block's); after the odd blocks, each
// particle's sum goes from the rank that added its last term to the rank that owns it. A block
// along a rank boundary is so run once, not by both ranks (the 10^5-particle Taylor bar's rank
// ran 9 of its 14 blocks with 7.5 blocks of particles of its own: docs/SCALING.md §3).
#include <span>
#include <vector>

#include <Eigen/Core>

#include "spall/core/range_array.hpp"
#include "spall/core/types.hpp"

namespace spall::sph {

class ForceBlocks {
 public:
  // `count` blocks of `length` particles over `particles` (none: the pass gathers every row whole).
  // Under MPI `particle_begin` holds every rank's first particle and then `particles` (the
  // particles are in node order, so each rank's are one run); empty for one process, which runs
  // every block.
  void assign(Index particles, Index count, Index length, std::span<const Index> particle_begin, int rank);

  Index count() const { return count_; }
  Index begin(Index block) const { return block * length_; }
  Index end(Index block) const { return block + 1 < count_ ? (block + 1) * length_ : particles_; }
  bool runs(Index block) const { return runner_.empty() || runner_[block] == rank_; }
  // Whether particle a's row is in a block this rank runs.
  bool runs_row(Index a) const { return count_ > 0 && runs(a / length_); }
  // The blocks this rank runs, of one parity (0: even, 1: odd), in increasing order.
  std::span<const Index> run(int parity) const { return run_[parity]; }
  // From the first row of this rank's blocks to the last, and to the last particle they add to
  // (the next block's); empty ranges if it runs none.
  Index first_row() const { return first_row_; }
  Index last_row() const { return last_row_; }
  Index last_touched() const { return last_touched_; }

  // Under MPI, between the even and the odd blocks, and after the odd ones (see above): in place
  // in `sums`, the partial pair sums (x, y, z, 0) of the particles, held for those of the blocks this
  // rank runs (to last_touched()) and of its own particles. Collective: every rank calls both, each
  // step the blocks run. Nothing for one process.
  void after_even(RangeArray<Eigen::Vector4d>& sums) const {
    move(handoff_, sums.data(), sums.held_begin());
  }
  void after_odd(RangeArray<Eigen::Vector4d>& sums) const {
    move(delivery_, sums.data(), sums.held_begin());
  }

 private:
  // Particles [begin, end) whose sums go from rank `from` to rank `to`.
  struct Transfer {
    Index begin, end;
    int from, to;
  };
  // This rank's part of one stage: its outgoing runs by destination rank, its incoming by source,
  // each in the order of the stage's list (the same on every rank), and the item offsets per rank.
  struct Plan {
    std::vector<Transfer> send, receive;
    std::vector<Index> send_offsets, receive_offsets;
  };
  Plan plan(const std::vector<Transfer>& transfers) const;
  // Particle a's sum at sums[a - first].
  void move(const Plan& plan, Eigen::Vector4d* sums, Index first) const;

  Index particles_ = 0, length_ = 0, count_ = 0;
  int rank_ = 0, ranks_ = 1;
  std::vector<int> runner_;  // per block; empty for one process
  std::vector<Index> run_[2];
  Index first_row_ = 0, last_row_ = 0, last_touched_ = 0;
  Plan handoff_, delivery_;
};

}  // namespace spall::sph
