#pragma once
// Under MPI (replicated state, docs/SCALING.md "Load balance"): each rank computes a block of the
// node store, and the blocks follow the work measured on them, so that no rank waits for the
// others at every step's reductions. The results do not depend on the blocks; only the speed does.
#include <span>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::solver {

// How the time loop keeps the ranks' work even. At each check (checks_at) each rank's own work since
// the last check (its wall time outside the collectives) is compared; when the busiest rank's
// exceeds the mean by more than `threshold` (0.1: 10 %), the nodes are dealt anew so that each rank
// holds an equal share of the work measured.
struct LoadBalance {
  long long interval = 100;
  double threshold = 0.1;
  // The first checks come early, after first_check, 2 first_check, 4 first_check, ... steps while
  // those are below `interval`, then every `interval` steps: the first deal is a guess (a fluid's
  // wall particles weigh nothing in it, a solid's blocks hold equal nodes, not equal plastic work)
  // that the measured work corrects within a few tens of steps, where a run of a few hundred steps
  // would otherwise keep it for a hundred (docs/SCALING.md §4, "Weak scaling, measured").
  static constexpr long long first_check = 10;
  // Whether the ranks' work is compared before step `step` (none before step 1, none for an
  // interval <= 0).
  bool checks_at(long long step) const;
};

// Blocks of the nodes, in the same order, that share the work evenly: rank r's old block is
// [begin[r], begin[r + 1]) and did work[r] (negative counts as none), taken as spread evenly over its
// nodes; the cut between ranks k - 1 and k falls where the work before it is k / ranks of the whole.
// No work at all keeps the blocks.
std::vector<Index> balanced_blocks(std::span<const Index> begin, std::span<const double> work);

}  // namespace spall::solver
