#pragma once
// Building the SPG formulation from the model: the parts whose section is *SECTION_SOLID_SPG
// (ELFORM 47), their particles at the nodes of their *ELEMENT_SOLID mesh, nodal volumes and
// lumped masses from the elements (spg/nodal_volumes.hpp), and every section field checked: what
// Spall cannot run is an InputError naming the field.
#include <memory>
#include <vector>

#include "spall/model/model.hpp"
#include "spall/discretization/formulation.hpp"
#include "spall/discretization/node_index.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/spg/part.hpp"

namespace spall::spg {

// True when `part` is meshed with solid elements that SPG runs.
bool is_spg_part(const model::Model& model, Id part);

// One SPG part as read and checked: its settings and its particles in node order.
struct PartSetup {
  PartSettings settings;
  std::vector<ParticleSetup> particles;
};

// The SPG parts of the model (by part ID), with nodal volumes, spacings and surface flags from the
// elements; throws InputError for anything the solver cannot run.
std::vector<PartSetup> spg_parts(const model::Model& model, const discretization::NodeIndex& index_of_node,
                                 const discretization::NodeStore& nodes);

// Adds the SPG particles' masses to nodes.mass and their part to nodes.part, and returns the
// formulation (nullptr when the model has no SPG part).
std::unique_ptr<discretization::Formulation> build_spg(const model::Model& model,
                                               const discretization::NodeIndex& index_of_node,
                                               discretization::NodeStore& nodes);

}  // namespace spall::spg
