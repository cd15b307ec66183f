#pragma once
// Building the SPG formulation from the model: the parts whose section is *SECTION_SOLID_SPG
// (ELFORM 47), their particles at the nodes of their *ELEMENT_SOLID mesh, nodal volumes and
// lumped masses from the elements (spg/nodal_volumes.hpp), and every section field checked: what
// Spall cannot run is an InputError naming the field.
#include <memory>
#include <unordered_map>
#include <vector>

#include "spall/model/model.hpp"
#include "spall/solver/formulation.hpp"
#include "spall/solver/node_store.hpp"

namespace spall::spg {

// True when `part` is meshed with solid elements that SPG runs.
bool is_spg_part(const model::Model& model, Id part);

// Adds the SPG particles' masses to nodes.mass and their part to part_of_node, and returns the
// formulation (nullptr when the model has no SPG part).
std::unique_ptr<solver::Formulation> build_spg(const model::Model& model,
                                               const std::unordered_map<Id, Index>& index_of_node,
                                               solver::NodeStore& nodes, std::vector<Id>& part_of_node);

}  // namespace spall::spg
