#pragma once
// The point fields written at each output time: kinematics from the node store, then every
// formulation's own fields (pressure, von Mises stress, density, ...).
#include <vector>

#include "spall/io/output/vtu.hpp"
#include "spall/solver/problem.hpp"

namespace spall::solver {

struct FieldSnapshot {
  std::vector<Vec3> points;
  std::vector<io::output::PointField> fields;
};

// Nodes without mass (used by no formulation) are left out.
FieldSnapshot snapshot_fields(const Problem& problem);

}  // namespace spall::solver
