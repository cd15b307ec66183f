#pragma once
// The SPH fluid of a model: its *MAT_NULL parts (with their *EOS_), checked, as one
// FluidFormulation (the fluid's own set-up, as spg/setup.hpp is SPG's). Called by the solver's
// build_problem for the particles of those parts.
#include <memory>
#include <vector>

#include "spall/discretization/node_store.hpp"
#include "spall/model/model.hpp"
#include "spall/sph/fluid.hpp"

namespace spall::sph {

// True when part `pid` exists and its material is a *MAT_NULL: its particles are liquid.
bool is_fluid_part(const model::Model& model, Id pid);

struct FluidParticle {
  const model::ElementSph* element = nullptr;
  Index node = 0;        // its node's row; -1 when the set-up holds a block of the nodes without it
  Index model_node = 0;  // its node's card in model.nodes (a 2D fluid's plane is checked there)
};

// Sets the particles' masses and part IDs on the nodes they have rows on (and holds z in plane
// strain) and returns the formulation of those particles; checks every particle and throws
// InputError at the card for what the fluid cannot run.
std::unique_ptr<FluidFormulation> build_fluid(const model::Model& model,
                                                   const std::vector<FluidParticle>& particles,
                                                   const ArtificialViscosity& viscosity,
                                                   int dimension, discretization::NodeStore& nodes);

}  // namespace spall::sph
