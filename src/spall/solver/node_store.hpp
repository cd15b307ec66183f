#pragma once
// The one node store every discretization shares (DESIGN: "every discretization owns its points as
// nodes"): SPH particles, SPG particles and hexahedron corners are all nodes here, so coupling
// through shared nodes needs no extra machinery. Structure of arrays, dense indices.
#include <cstdint>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::solver {

struct NodeStore {
  std::vector<Id> id;      // the deck's node ID
  std::vector<Vec3> x0;    // reference position
  std::vector<Vec3> x;     // current position x^n
  std::vector<Vec3> v;     // velocity at the half step v^{n-1/2} (central difference)
  std::vector<Vec3> f;     // force at x^n
  std::vector<Real> mass;  // lumped mass; 0 for a node no formulation uses
  std::vector<std::uint8_t> fixed;  // bit d set: translation d is held by an SPC

  Index size() const { return static_cast<Index>(id.size()); }

  void resize(Index n) {
    id.resize(n);
    x0.resize(n);
    x.resize(n);
    v.assign(n, Vec3::Zero());
    f.assign(n, Vec3::Zero());
    mass.assign(n, 0);
    fixed.assign(n, 0);
  }
};

}  // namespace spall::solver
