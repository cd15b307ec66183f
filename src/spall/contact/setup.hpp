#pragma once
// Building the penalty contacts from the model (*CONTACT_..., *CONTROL_CONTACT, *SET_SEGMENT):
// the slave nodes of side A, the master segments of side B (the exterior faces of its solid
// elements, or its segment set, always turned to face out of their element), their penalty
// stiffnesses and release depths. Call after the rigid bodies are built (a node's body decides
// how a segment of it is treated). What Spall cannot run is an InputError naming the field.
#include <vector>

#include "spall/contact/penalty_contact.hpp"
#include "spall/discretization/node_index.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/model/model.hpp"

namespace spall::contact {

std::vector<PenaltyContact> build_contacts(const model::Model& model,
                                           const discretization::NodeIndex& index_of_node,
                                           const discretization::NodeStore& nodes);

}  // namespace spall::contact
