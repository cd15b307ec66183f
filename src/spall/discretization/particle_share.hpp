#pragma once
// Under MPI with replicated state (docs/SCALING.md): which of a formulation's particles this rank
// computes (those whose node it owns, NodeStore::owns), and its per-particle arrays, each rank's
// own particles in to every rank. When the ranks own blocks of nodes (NodeStore::rank_begin) and
// the particles are stored in increasing node order, as the problem builder makes them, every
// rank's particles are one block of the array too and go in place. Otherwise (the fluid's cell
// order, nodes dealt by region) they are gathered by rank and node first and put back.
#include <algorithm>
#include <cstdint>
#include <numeric>
#include <span>
#include <stdexcept>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/range_array.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/node_store.hpp"

namespace spall::discretization {

class ParticleShare {
 public:
  // The nodes this rank computes, from the store the particles' nodes are in; until then, all.
  void bind(const NodeStore& nodes) {
    if (bound_ && partition_ == nodes.partition) return;
    // By region each node's rank, in blocks every rank's first node: O(P), not O(N).
    owner_ = nodes.by_region() ? nodes.owner : std::vector<std::int32_t>{};
    rank_begin_ = nodes.by_region() ? std::vector<Index>{} : nodes.rank_begin;
    rank_ = nodes.rank;
    partition_ = nodes.partition;
    offsets_.clear();  // planned again for the new blocks
    bound_ = true;
  }
  // The particles are now stored in another order: the next share plans the exchange again.
  void reorder() { offsets_.clear(); }
  // Bound to blocks that the nodes have since been dealt anew from.
  bool stale(const NodeStore& nodes) const { return bound_ && partition_ != nodes.partition; }

  bool owns(Index node) const { return !dealt() || rank_of(node) == rank_; }
  // Whether the nodes are dealt to the ranks (bound under MPI): until then this rank computes all.
  bool dealt() const { return !owner_.empty() || !rank_begin_.empty(); }
  int rank() const { return rank_; }
  // The rank that computes a node, in the partition bound to (once bound, under MPI). In blocks
  // the rows are every node in the deck's order, so a row is its place in the blocks.
  int rank_of(Index node) const {
    if (!owner_.empty()) return owner_[node];
    return static_cast<int>(std::upper_bound(rank_begin_.begin(), rank_begin_.end(), node) - rank_begin_.begin()) - 1;
  }
  // The ranks a sum over the particles this rank computes must be taken across: none until bound
  // (every rank computes every particle then, as in the set-up).
  const parallel::Communicator* across() const { return bound_ ? &parallel::world() : nullptr; }

  // Every rank's values of its own particles (`node`: each particle's node) in, in place; nothing
  // for an empty array (state that the options switched off), a run of one process or before
  // bind. An array may hold several values a particle, one after the other (an element's Gauss
  // points); a RangeArray must hold every particle.
  template <typename... Array>
  void operator()(std::span<const Index> node, Array&... values) {
    if (!bound_ || parallel::world().size() == 1) return;
    if (offsets_.empty()) plan(node);
    (share(values), ...);
  }

  // The particles' nodes' positions and velocities from every rank's own particles in (written
  // back to the store for the other ranks' particles), with `values` as operator() shares them:
  // for a formulation whose halo brings in only the nodes it reads, where it needs them all.
  template <typename... T>
  void complete_nodes(std::span<const Index> node, NodeStore& nodes, std::vector<T>&... values) {
    if (!bound_ || parallel::world().size() == 1) return;
    const Index n = static_cast<Index>(node.size());
    std::vector<Vec3> x(n), v(n);
    if (nodes.windowed() && nodes.size() < nodes.deck_node_count())
      throw std::logic_error("ParticleShare::complete_nodes: a window of the nodes, not every node");
    parallel::for_each(n, [&](Index a) {
      const Index i = nodes.node_row(node[a]);
      x[a] = nodes.x[i], v[a] = nodes.v[i];
    });
    (*this)(node, x, v, values...);
    parallel::for_each(n, [&](Index a) {
      if (owns(node[a])) return;
      nodes.x[nodes.node_row(node[a])] = x[a];
      nodes.v[nodes.node_row(node[a])] = v[a];
    });
  }

 private:
  void plan(std::span<const Index> node) {
    const int ranks = parallel::world().size();
    const Index n = static_cast<Index>(node.size());
    if (!dealt()) throw std::logic_error("ParticleShare: the nodes were not dealt out to the ranks");
    std::vector<int> rank(n);
    parallel::for_each(n, [&](Index a) { rank[a] = rank_of(node[a]); });
    offsets_.assign(ranks + 1, 0);
    for (Index a = 0; a < n; ++a) ++offsets_[rank[a] + 1];
    std::partial_sum(offsets_.begin(), offsets_.end(), offsets_.begin());
    order_.clear();
    // Each rank's particles one block already, in node order (the order every rank agrees on).
    if (std::is_sorted(rank.begin(), rank.end()) && std::is_sorted(node.begin(), node.end())) return;
    // Grouped by rank, each group in node order: the particles' storage order may be each rank's own
    // (the fluid's cells near a rank's region), their nodes are every rank's.
    const Index nodes = n == 0 ? 0 : *std::max_element(node.begin(), node.end()) + 1;
    std::vector<Index> particle(nodes, -1);
    for (Index a = 0; a < n; ++a) particle[node[a]] = a;
    order_.resize(n);
    std::vector<Index> next(offsets_.begin(), offsets_.end() - 1);
    for (const Index a : particle)
      if (a >= 0) order_[next[rank[a]]++] = a;
  }

  // The values of an array, every particle's.
  template <typename T>
  static std::span<T> every_value(std::vector<T>& values) {
    return values;
  }
  template <typename T>
  static std::span<T> every_value(RangeArray<T>& values) {
    if (values.held_begin() != 0) throw std::logic_error("ParticleShare: a RangeArray that does not hold every particle");
    return {values.data(), static_cast<std::size_t>(values.held_end())};
  }

  template <typename Array>
  void share(Array& array) const {
    if (array.empty()) return;
    const auto values = every_value(array);
    const Index n = offsets_.back();
    if (n == 0 || values.size() % n != 0)
      throw std::logic_error("ParticleShare: an array that is not a whole number of values a particle");
    const Index per = static_cast<Index>(values.size() / n);
    std::vector<Index> offsets(offsets_);
    for (Index& o : offsets) o *= per;
    if (order_.empty()) {
      parallel::world().share(values, offsets);
      return;
    }
    std::vector<typename Array::value_type> by_rank(values.size());
    parallel::for_each(n, [&](Index k) {
      std::copy_n(values.begin() + order_[k] * per, per, by_rank.begin() + k * per);
    });
    parallel::world().share(std::span(by_rank), offsets);
    parallel::for_each(n, [&](Index k) {
      std::copy_n(by_rank.begin() + k * per, per, values.begin() + order_[k] * per);
    });
  }

  // The partition bound to: by region NodeStore::owner, in blocks NodeStore::rank_begin (both
  // empty: this rank computes every node).
  std::vector<std::int32_t> owner_;
  std::vector<Index> rank_begin_;
  int rank_ = 0;
  long long partition_ = 0;
  bool bound_ = false;
  std::vector<Index> order_;    // the particles grouped by rank, when not stored so (else empty)
  std::vector<Index> offsets_;  // each rank's first particle in that order, then the count; empty
                                // until planned for the particles' present order
};

}  // namespace spall::discretization
