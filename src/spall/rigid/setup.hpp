#pragma once
// Building the rigid bodies from the model: every part whose material is *MAT_RIGID and that is
// meshed with *ELEMENT_SOLID (any solid section: for a rigid part it sets only the geometry) is
// one body; lumped nodal masses RO V / (nodes per element); *MAT_RIGID CMO 1 with CON1 CON2; and
// *BOUNDARY_PRESCRIBED_MOTION_RIGID. What Spall cannot run is an InputError naming the field.
#include <vector>

#include "spall/discretization/node_index.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/model/model.hpp"
#include "spall/rigid/rigid_bodies.hpp"

namespace spall::rigid {

// True when `part`'s material is *MAT_RIGID.
bool is_rigid_part(const model::Model& model, Id part);

// Adds the rigid parts' element masses to nodes.mass (before the bodies are formed).
void add_rigid_masses(const model::Model& model, const discretization::NodeIndex& index_of_node,
                      discretization::NodeStore& nodes);

// The bodies, from the nodes' masses, positions and initial velocities (call after the initial
// velocities are set), with their constraints and prescribed motions.
RigidBodies build_rigid_bodies(const model::Model& model, const discretization::NodeIndex& index_of_node,
                               discretization::NodeStore& nodes);

}  // namespace spall::rigid
