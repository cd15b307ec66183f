#pragma once
// The one node store every discretization shares (DESIGN: "every discretization owns its points as
// nodes"): SPH particles, SPG particles and hexahedron corners are all nodes here, so coupling
// through shared nodes needs no extra machinery: two formulations that use a node both add their
// force to it. Structure of arrays, dense indices. Under MPI each rank computes its own share of
// the nodes and holds every node (replicated state, docs/SCALING.md), or, dealt by region, its own
// and those near them (rows of its own).
#include <algorithm>
#include <cstdint>
#include <span>
#include <stdexcept>
#include <utility>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/regions.hpp"

namespace spall::discretization {

struct NodeStore {
  // A node that belongs to no rigid body.
  static constexpr std::int32_t no_body = -1;

  std::vector<Id> id;      // the deck's node ID
  std::vector<Vec3> x0;    // reference position
  std::vector<Vec3> x;     // current position x^n
  std::vector<Vec3> v;     // velocity at the half step v^{n-1/2} (central difference)
  std::vector<Vec3> f;     // force at x^n
  std::vector<Real> mass;  // lumped mass; 0 for a node no formulation uses
  std::vector<std::uint8_t> fixed;    // bit d set: translation d is held by an SPC
  std::vector<std::uint8_t> active;   // 0 once every element or particle on the node has eroded
  std::vector<std::int32_t> body;     // the rigid body the node moves with, or no_body
  std::vector<Id> part;               // the deck's part ID of the node's particle or element, 0 if none
  // Under MPI each rank computes the forces and new velocities of its own nodes and shares them
  // with the others every step (the time loop's halo phase). The nodes are dealt out in blocks of
  // the node order, or, in a deck of SPH fluid alone, by region (`regions`, docs/SCALING.md §3).
  // `owner`: dealt by region, each row's rank (empty otherwise: in blocks `rank_begin` tells).
  std::vector<std::int32_t> owner;
  int rank = 0;
  // A range that holds every node this process computes, [owned_begin, owned_end): all of them for
  // one process or by region, a rank's block otherwise (and then exactly its nodes).
  Index owned_begin = 0;
  Index owned_end = 0;
  // Dealt in blocks: every rank's first node, then size() (ranks + 1 entries; empty for one process
  // or by region).
  std::vector<Index> rank_begin;
  // Dealt by region: the regions' cuts and this process's nodes, ascending (both empty otherwise).
  Regions regions;
  std::vector<Index> owned;
  // The time loop deals the nodes anew when the ranks' loads drift apart (docs/SCALING.md), and by
  // region they move between ranks as they flow (keep, add); `partition` counts the
  // changes, so that what was planned for a partition knows when it is stale.
  long long partition = 0;
  // Counts the changes of which nodes the rows are and in what order (a new partition, a keep, a
  // new window: hold_window), so that what keeps rows (a wall's, a prescribed motion's) finds them
  // again; the rows added by region since the last keep come after the others and change none.
  long long layout = 0;
  // Dealt by region, a rank has rows of its own: it keeps its own nodes and the others' that its
  // passes read, no more (memory O(N / P), docs/SCALING.md §3), and the rows change at each of the
  // formulation's rebuilds (keep, add). `global`: each row's place in the deck's order (empty while
  // the rows are every node in that order, as the set-up builds them).
  std::vector<Index> global;
  // Under MPI: true when the halo brings in only the velocities that the formulations read (the
  // halo by reach, set by the time loop), so that the other ranks' nodes beyond that are stale and
  // the constraints act on a rank's own nodes; false when every velocity is shared each step.
  bool velocities_by_reach = false;
  // Under MPI in blocks, with the halo by reach: true when the time loop lets the one formulation
  // hold the window of the nodes it reads beyond its own block (hold_window), which it brings in.
  bool window_by_reads = false;

  Index size() const { return static_cast<Index>(id.size()); }
  Index deck_index(Index row) const { return global.empty() ? window_first_ + row : global[row]; }
  // The row of the node at `deck_index`, -1 when this rank holds none.
  Index row_of(Index deck_index) const;
  // A formulation names a node by its row where the rows have places of their own (`global`: by
  // region, where rows move and are reordered), else by its place in the node order, from which a
  // window's rows are offset: the name's place and its row.
  Index node_place(Index name) const { return global.empty() ? name : global[name]; }
  Index node_row(Index name) const { return global.empty() ? name - window_first_ : name; }

  // n owned nodes, at rest, massless, free, active, in no body.
  void resize(Index n) {
    id.resize(n);
    x0.resize(n);
    x.resize(n);
    v.assign(n, Vec3::Zero());
    f.assign(n, Vec3::Zero());
    mass.assign(n, 0);
    fixed.assign(n, 0);
    active.assign(n, 1);
    body.assign(n, no_body);
    part.assign(n, 0);
    owned_begin = 0;
    owned_end = n;
    window_first_ = 0;
    windowed_ = false;
  }

  bool by_region() const { return !regions.empty(); }
  bool owns(Index i) const {
    return by_region() ? owner[i] == rank : rank_begin.empty() || (owned_begin <= i && i < owned_end);
  }
  // The rank that computes row i (this process's rank until the nodes are dealt).
  int rank_of(Index i) const {
    if (by_region()) return owner[i];
    if (rank_begin.empty()) return rank;
    return static_cast<int>(std::upper_bound(rank_begin.begin(), rank_begin.end(), deck_index(i)) - rank_begin.begin()) - 1;
  }
  // The nodes this process computes: owned_node(k) for k in [0, owned_count()), ascending.
  Index owned_count() const { return by_region() ? static_cast<Index>(owned.size()) : owned_end - owned_begin; }
  Index owned_node(Index k) const { return by_region() ? owned[k] : owned_begin + k; }

  // Rank `r` computes the nodes [begins[r], begins[r + 1]); this process is rank `self`. Holding a
  // window of the nodes (hold_window), each rank first holds the hull of it and its new block, the
  // rows it lacks from the ranks that computed them: collective then. Rows that are the set-up's
  // block of the nodes (hold_block) must be this rank's new block, and become the window of it.
  void deal(std::vector<Index> begins, int self);

  // Dealt in blocks: from now on this rank holds the nodes [first, end) of the node order, row i the
  // node at place first + i (a window of the rows, docs/SCALING.md §5 step 5), which must hold its
  // own block. A row it held keeps its state; one it lacked comes whole (NodeStore::Row, no force)
  // from the rank that computes it, which holds its own block. Collective: every rank names its
  // window at once. What its rows read of the other ranks' nodes stays the formulations' to bring in.
  void hold_window(Index first, Index end);
  // Whether the rows are a window of the node order (hold_window), the first of them at place
  // window_first().
  bool windowed() const { return windowed_; }
  Index window_first() const { return window_first_; }
  // The places of the rows, [window_first(), window_first() + size()): a window's, or every node's
  // while the rows are every node in the node order.
  parallel::Range window() const { return {window_first_, window_first_ + size()}; }
  // Whether a row holds the node at `place` (one of window()'s places).
  bool holds_place(Index place) const { return window_first_ <= place && place < window_first_ + size(); }

  // Each node computed by the rank whose region holds its position; this process is rank `self`.
  // Rows that are a block of the nodes (hold_block) stay with this rank until the formulations'
  // first rebuild migrates them to their regions' ranks, as after a re-cut.
  void deal(Regions cuts, int self) {
    if (windowed_) throw std::logic_error("NodeStore::deal: rows that are a window of the node order dealt by region");
    regions = std::move(cuts);
    rank_begin.clear();
    rank = self;
    owned_begin = 0;
    owned_end = size();
    owner.resize(size());
    for (Index i = 0; i < size(); ++i) owner[i] = block_ ? self : regions.rank_of(x[i]);
    block_ = false;
    list_owned();
    ++partition;
    ++layout;
  }

  // The rows are the nodes [first, first + size()) of the deck's `every` (a rank's block of them,
  // built by the set-up under MPI), not every node.
  void hold_block(Index first, Index every);
  // True from hold_block until the nodes are dealt: each rank holds a block of them, so a sum over
  // every node is each rank's over its rows, summed over the ranks.
  bool holds_a_block() const { return block_; }

  // By region, cut anew: each node stays with its rank until it migrates at the formulations'
  // next rebuild (on the serial run's schedule, so that no sum changes order), so nothing travels
  // here and the partition is the same until then.
  void recut(Regions cuts) { regions = std::move(cuts); }

  // A node as it travels between ranks with its rows (explicit padding: no unset byte travels).
  struct Row {
    std::int64_t global;
    Id id, part;
    Vec3 x0, x, v;
    Real mass;
    std::int32_t body;
    std::uint8_t fixed, active, padding[2];
  };
  Row row(Index i) const {
    return {deck_index(i), id[i], part[i], x0[i], x[i], v[i], mass[i], body[i], fixed[i], active[i], {0, 0}};
  }
  // By region: a row for a node that came in, computed by rank `by`; returns its row.
  Index add(const Row& row, int by);
  // Room for `rows` rows in all, so that adding up to them allocates once.
  void reserve(Index rows);
  // By region: only the rows `kept`, in that order (each row's state goes with it); a new
  // partition.
  void keep(std::span<const Index> kept);

  // `owned` from `owner`.
  void list_owned() {
    owned.clear();
    for (Index i = 0; i < size(); ++i)
      if (owner[i] == rank) owned.push_back(i);
  }

  // Every node of the deck, whether this rank holds it or not.
  Index deck_node_count() const { return numbered_ || windowed_ ? deck_nodes_ : size(); }
  // Whether the rows are every node in the deck's order (not rows of a rank's own: a block, a
  // window or a region's).
  bool holds_every_node() const { return !numbered_ && !windowed_; }
  // The places in the deck's order from the lowest of the rows' to past the highest: every place
  // (of any Index) while the rows are every node.
  std::pair<Index, Index> places_held() const;

  // Each node's row and force, in pieces (core/pieces.hpp): each rank's own rows where the rows are
  // not every node (by region, in a window), else rank 0's every row (the whole state, made current
  // there by the formulations' complete_state). Read back into every node, or into the rows of a
  // rank's own (a block of them, as the set-up in blocks builds them), whatever the ranks that wrote
  // them; the IDs (the deck's) are checked, the share of a rank (the run's) is not written.
  // Collective, but for reading every node.
  void checkpoint(Archive& a);

 private:
  // By region: (deck index, row) of the rows at the last keep, sorted by deck index (the first
  // sorted_by_deck_), then of those added since.
  std::vector<std::pair<Index, Index>> by_deck_;
  std::size_t sorted_by_deck_ = 0;
  Index deck_nodes_ = 0;  // every node of the deck, counted when the rows were last whole or built
  bool numbered_ = false;  // global holds the rows' places
  bool block_ = false;     // the rows are a block of the nodes (hold_block), not yet dealt
  bool windowed_ = false;  // the rows are the window [window_first_, window_first_ + size())
  Index window_first_ = 0;
  void index_by_deck();
  // Rows that are every node in the deck's order get their places (global), before they change.
  void number_rows();
};

}  // namespace spall::discretization
