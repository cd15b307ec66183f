#pragma once
// The one node store every discretization shares (DESIGN: "every discretization owns its points as
// nodes"): SPH particles, SPG particles and hexahedron corners are all nodes here, so coupling
// through shared nodes needs no extra machinery: two formulations that use a node both add their
// force to it. Structure of arrays, dense indices. Under MPI every rank holds every node (replicated
// state, docs/SCALING.md) and computes its own share of them.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/archive.hpp"
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
  // Under MPI each rank computes the forces and new velocities of its own nodes and shares them
  // with the others every step (the time loop's halo phase). The nodes are dealt out in blocks of
  // the node order, or, in a deck of SPH fluid alone, by region (`regions`, docs/SCALING.md §3).
  // `owner`: every node's rank (empty for one process).
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
  // region they move between ranks as they flow (migrate); `partition` counts the changes, so that
  // what was planned for a partition knows when it is stale.
  long long partition = 0;
  // Under MPI: true when the halo brings in only the velocities that the formulations read (the
  // halo by reach, set by the time loop), so that the other ranks' nodes beyond that are stale and
  // the constraints act on a rank's own nodes; false when every velocity is shared each step.
  bool velocities_by_reach = false;

  Index size() const { return static_cast<Index>(id.size()); }

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
    owned_begin = 0;
    owned_end = n;
  }

  bool owns(Index i) const { return owner.empty() || owner[i] == rank; }
  bool by_region() const { return !regions.empty(); }
  // The nodes this process computes: owned_node(k) for k in [0, owned_count()), ascending.
  Index owned_count() const { return by_region() ? static_cast<Index>(owned.size()) : owned_end - owned_begin; }
  Index owned_node(Index k) const { return by_region() ? owned[k] : owned_begin + k; }

  // Rank `r` computes the nodes [begins[r], begins[r + 1]); this process is rank `self`.
  void deal(std::vector<Index> begins, int self) {
    rank_begin = std::move(begins);
    regions = {};
    owned.clear();
    rank = self;
    owned_begin = rank_begin[rank];
    owned_end = rank_begin[rank + 1];
    owner.resize(size());
    for (int r = 0; r + 1 < static_cast<int>(rank_begin.size()); ++r)
      std::fill(owner.begin() + rank_begin[r], owner.begin() + rank_begin[r + 1], r);
    ++partition;
  }

  // Each node computed by the rank whose region holds its position; this process is rank `self`.
  void deal(Regions cuts, int self) {
    regions = std::move(cuts);
    rank_begin.clear();
    rank = self;
    owned_begin = 0;
    owned_end = size();
    owner.resize(size());
    for (Index i = 0; i < size(); ++i) owner[i] = regions.rank_of(x[i]);
    list_owned();
    ++partition;
  }

  // By region, cut anew: each node stays with its rank until it migrates at the formulations'
  // next rebuild (on the serial run's schedule, so that no sum changes order), so nothing travels
  // here and the partition is the same until then.
  void recut(Regions cuts) { regions = std::move(cuts); }

  // By region: each of `moving`'s nodes that this rank computes goes to the rank of the region its
  // position is in now (only the owner's copy of a position need be current), and every rank
  // learns every change (the changes alone travel), so that all hold the same owners. Counts as a
  // new partition when a node changed rank; false when none did (or the nodes are dealt in
  // blocks). Collective: every rank calls it at once.
  bool migrate(std::span<const Index> moving);
  // `owned` from `owner`.
  void list_owned() {
    owned.clear();
    for (Index i = 0; i < size(); ++i)
      if (owner[i] == rank) owned.push_back(i);
  }

  // Everything but the IDs (the deck's), which must match, and the share of a rank (the run's).
  void checkpoint(Archive& a) {
    a.expect_size("nodes", id.size());
    a(x0, x, v, f, mass, fixed, active, body);
  }
};

}  // namespace spall::discretization
