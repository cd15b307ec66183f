#pragma once
// Under MPI with replicated state (docs/SCALING.md): which of a formulation's particles this rank
// computes (those whose node it owns, NodeStore::owns), and its per-particle arrays, each rank's
// own particles in to every rank. The ranks own blocks of nodes (parallel::block_offsets); when the
// particles are stored in increasing node order, as the problem builder makes them, every rank's
// particles are one block of the array too and go in place. Otherwise (the fluid's cell order) they
// are gathered by rank first and put back.
#include <algorithm>
#include <limits>
#include <numeric>
#include <span>
#include <stdexcept>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/node_store.hpp"

namespace spall::discretization {

class ParticleShare {
 public:
  // The nodes this rank computes, from the store the particles' nodes are in; until then, all.
  void bind(const NodeStore& nodes) {
    owned_begin_ = nodes.owned_begin, owned_end_ = nodes.owned_end;
    node_count_ = nodes.size();
  }
  // The particles are now stored in another order: the next share plans the exchange again.
  void reorder() { offsets_.clear(); }

  bool owns(Index node) const { return node >= owned_begin_ && node < owned_end_; }

  // Every rank's values of its own particles (`node`: each particle's node) in, in place; nothing
  // for an empty array (state that the options switched off) or a run of one process. An array may
  // hold several values a particle, one after the other (an element's Gauss points).
  template <typename... T>
  void operator()(std::span<const Index> node, std::vector<T>&... values) {
    if (parallel::world().size() == 1) return;
    if (offsets_.empty()) plan(node);
    (share(values), ...);
  }

 private:
  void plan(std::span<const Index> node) {
    const int ranks = parallel::world().size();
    const Index n = static_cast<Index>(node.size());
    const std::vector<Index> node_offsets = parallel::block_offsets(node_count_, ranks);
    std::vector<int> rank(n);
    parallel::for_each(n, [&](Index a) {
      rank[a] = static_cast<int>(std::upper_bound(node_offsets.begin(), node_offsets.end(), node[a]) -
                                 node_offsets.begin()) - 1;
    });
    offsets_.assign(ranks + 1, 0);
    for (Index a = 0; a < n; ++a) ++offsets_[rank[a] + 1];
    std::partial_sum(offsets_.begin(), offsets_.end(), offsets_.begin());
    order_.clear();
    if (std::is_sorted(rank.begin(), rank.end())) return;  // each rank's particles one block already
    // Grouped by rank, each group in storage order (a counting sort).
    order_.resize(n);
    std::vector<Index> next(offsets_.begin(), offsets_.end() - 1);
    for (Index a = 0; a < n; ++a) order_[next[rank[a]]++] = a;
  }

  template <typename T>
  void share(std::vector<T>& values) const {
    if (values.empty()) return;
    const Index n = offsets_.back();
    if (n == 0 || values.size() % n != 0)
      throw std::logic_error("ParticleShare: an array that is not a whole number of values a particle");
    const Index per = static_cast<Index>(values.size() / n);
    std::vector<Index> offsets(offsets_);
    for (Index& o : offsets) o *= per;
    if (order_.empty()) {
      parallel::world().share(std::span(values), offsets);
      return;
    }
    std::vector<T> by_rank(values.size());
    parallel::for_each(n, [&](Index k) {
      std::copy_n(values.begin() + order_[k] * per, per, by_rank.begin() + k * per);
    });
    parallel::world().share(std::span(by_rank), offsets);
    parallel::for_each(n, [&](Index k) {
      std::copy_n(by_rank.begin() + k * per, per, values.begin() + order_[k] * per);
    });
  }

  Index owned_begin_ = 0, owned_end_ = std::numeric_limits<Index>::max(), node_count_ = 0;
  std::vector<Index> order_;    // the particles grouped by rank, when not stored so (else empty)
  std::vector<Index> offsets_;  // each rank's first particle in that order, then the count; empty
                                // until planned for the particles' present order
};

}  // namespace spall::discretization
