#pragma once
// The fields written at each output time: the node store's own (velocity, displacement, mass,
// part and node ID), then every formulation's, merged by name (discretization/field_set.hpp).
#include <vector>

#include "spall/discretization/field_set.hpp"
#include "spall/solver/problem.hpp"

namespace spall::solver {

struct FieldSnapshot {
  std::vector<Vec3> points;
  std::vector<discretization::Field> fields;
  std::vector<discretization::CellBlock> cell_blocks;  // connectivity in indices of `points`
};

// Nodes without mass (used by no formulation) are left out.
FieldSnapshot snapshot_fields(const Problem& problem);

}  // namespace spall::solver
