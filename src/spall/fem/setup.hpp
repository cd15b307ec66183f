#pragma once
// Building the solid finite elements from the model: the parts whose section is *SECTION_SOLID,
// each checked against what fem/solid_elements.hpp runs (ELFORM, AET, *HOURGLASS, bulk
// viscosity); what Spall cannot run is an InputError naming the card and field.
#include <memory>
#include <vector>

#include "spall/discretization/formulation.hpp"
#include "spall/discretization/node_index.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/model/model.hpp"

namespace spall::fem {

// True when `part` is meshed with solid finite elements (a *SECTION_SOLID section).
bool is_fem_part(const model::Model& model, Id part);

// Adds the elements' lumped masses to nodes.mass and their part to nodes.part (where no other
// part has it), and returns the formulation (nullptr when the model has no finite element).
std::unique_ptr<discretization::Formulation> build_fem(const model::Model& model,
                                                       const discretization::NodeIndex& index_of_node,
                                                       discretization::NodeStore& nodes);

}  // namespace spall::fem
