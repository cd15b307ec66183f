#pragma once
// Under MPI (replicated state, docs/SCALING.md "Load balance"): each rank computes a block of the
// node store, and the blocks follow the work measured on them, so that no rank waits for the
// others at every step's reductions. The results do not depend on the blocks; only the speed does.
#include <span>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::solver {

// How the time loop keeps the ranks' work even. Every `interval` steps each rank's own work since
// the last check (its wall time outside the collectives) is compared; when the busiest rank's
// exceeds the mean by more than `threshold` (0.1: 10 %), the node blocks are dealt anew so that
// each holds an equal share of the work measured.
struct LoadBalance {
  long long interval = 100;
  double threshold = 0.1;
};

// Blocks of the nodes, in the same order, that share the work evenly: rank r's old block is
// [begin[r], begin[r + 1]) and did work[r] (negative counts as none), taken as spread evenly over its
// nodes; the cut between ranks k - 1 and k falls where the work before it is k / ranks of the whole.
// No work at all keeps the blocks.
std::vector<Index> balanced_blocks(std::span<const Index> begin, std::span<const double> work);

}  // namespace spall::solver
