#pragma once
// The one node store every discretization shares (DESIGN: "every discretization owns its points as
// nodes"): SPH particles, SPG particles and hexahedron corners are all nodes here, so coupling
// through shared nodes needs no extra machinery: two formulations that use a node both add their
// force to it. Structure of arrays, dense indices. Under MPI every rank holds every node (replicated
// state, docs/SCALING.md) and computes its own share of them.
#include <cstdint>
#include <utility>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/types.hpp"

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
  // The nodes this process computes, [owned_begin, owned_end): all of them, unless an MPI run deals
  // them out to its ranks; each rank then computes the forces and new velocities of its own nodes
  // and shares them with the others every step (the time loop's halo phase).
  Index owned_begin = 0;
  Index owned_end = 0;
  // Under MPI: every rank's first node, then size() (ranks + 1 entries; empty for one process).
  // The time loop deals the blocks anew when the ranks' loads drift apart (docs/SCALING.md);
  // `partition` counts the deals, so that what was planned for a partition knows when it is stale.
  std::vector<Index> rank_begin;
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

  bool owns(Index i) const { return i >= owned_begin && i < owned_end; }

  // Rank `rank` computes the nodes [begins[rank], begins[rank + 1]).
  void deal(std::vector<Index> begins, int rank) {
    rank_begin = std::move(begins);
    owned_begin = rank_begin[rank];
    owned_end = rank_begin[rank + 1];
    ++partition;
  }

  // Everything but the IDs (the deck's), which must match, and the share of a rank (the run's).
  void checkpoint(Archive& a) {
    a.expect_size("nodes", id.size());
    a(x0, x, v, f, mass, fixed, active, body);
  }
};

}  // namespace spall::discretization
