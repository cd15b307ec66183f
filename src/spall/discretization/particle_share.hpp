#pragma once
// Under MPI with replicated state (docs/SCALING.md): a formulation's per-particle arrays, each rank's
// own particles (those whose node it owns, NodeStore::owns) in to every rank. The ranks own blocks
// of nodes (parallel::block_offsets); when a formulation's particles are stored in increasing node
// order, as the problem builder makes them, every rank's particles are one block of the array too
// and go in place. Otherwise (the fluid's cell order) they are gathered by rank first and put back.
#include <algorithm>
#include <numeric>
#include <span>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/types.hpp"

namespace spall::discretization {

class ParticleShare {
 public:
  ParticleShare() = default;
  // The particles' nodes, of a store of node_count nodes dealt to the world's ranks. To be made
  // again when the particles are stored in another order.
  ParticleShare(std::span<const Index> node, Index node_count) {
    const int ranks = parallel::world().size();
    const Index n = static_cast<Index>(node.size());
    const std::vector<Index> node_offsets = parallel::block_offsets(node_count, ranks);
    std::vector<int> rank(n);
    parallel::for_each(n, [&](Index a) {
      rank[a] = static_cast<int>(std::upper_bound(node_offsets.begin(), node_offsets.end(), node[a]) -
                                 node_offsets.begin()) - 1;
    });
    offsets_.assign(ranks + 1, 0);
    for (Index a = 0; a < n; ++a) ++offsets_[rank[a] + 1];
    std::partial_sum(offsets_.begin(), offsets_.end(), offsets_.begin());
    if (std::is_sorted(rank.begin(), rank.end())) return;  // each rank's particles one block already
    // Grouped by rank, each group in storage order (a counting sort).
    order_.resize(n);
    std::vector<Index> next(offsets_.begin(), offsets_.end() - 1);
    for (Index a = 0; a < n; ++a) order_[next[rank[a]]++] = a;
  }

  // Every rank's values of its own particles in, in place (nothing for an empty array: state that
  // the options switched off).
  template <typename T>
  void operator()(std::vector<T>& values) const {
    if (values.empty() || parallel::world().size() == 1) return;
    if (order_.empty()) {
      parallel::world().share(std::span(values), offsets_);
      return;
    }
    std::vector<T> by_rank(values.size());
    const Index n = static_cast<Index>(order_.size());
    parallel::for_each(n, [&](Index k) { by_rank[k] = values[order_[k]]; });
    parallel::world().share(std::span(by_rank), offsets_);
    parallel::for_each(n, [&](Index k) { values[order_[k]] = by_rank[k]; });
  }

 private:
  std::vector<Index> order_;    // the particles grouped by rank, when not stored so (else empty)
  std::vector<Index> offsets_;  // each rank's first particle in that order, then the count
};

}  // namespace spall::discretization
