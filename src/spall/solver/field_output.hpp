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

// The nodes this process computes (NodeStore::owns: all of them in a run of one process, a rank's
// share under MPI, its piece of the output) and the cells whose first node is one of them, with
// the cells' other nodes; nodes without mass (used by no formulation) and in no such cell are left
// out. Every block of cells is there, with no cells when the piece has none of it, so that every
// piece has the same fields.
FieldSnapshot snapshot_fields(const Problem& problem);

}  // namespace spall::solver
