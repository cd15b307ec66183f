#pragma once
// The SPH fluid of a model: its *MAT_NULL parts (with their *EOS_), checked, as one
// FluidFormulation (the fluid's own set-up, as spg/setup.hpp is SPG's). Called by the solver's
// build_problem for the particles of those parts.
#include <cstdint>
#include <memory>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/model/model.hpp"
#include "spall/sph/fluid.hpp"

namespace spall::sph {

// True when part `pid` exists and its material is a *MAT_NULL: its particles are liquid.
bool is_fluid_part(const model::Model& model, Id pid);

// An *ELEMENT_SPH card as the set-up takes it, the fluid's here and the solid's in the solver's
// set-up in blocks (solver::NodesInBlocks::particles).
struct ParticleCard {
  const model::ElementSph* element = nullptr;
  Index node = 0;     // its node's row
  Index ordinal = 0;  // its card's place among the deck's *ELEMENT_SPH cards
};

// A part's first particle card in the deck: its ordinal and line (a card's line as every rank
// names it), by which the set-up orders the parts and names where a part fails.
struct FirstParticle {
  Id pid;
  Index ordinal;
  model::Model::CardLine line;
  std::int32_t padding = 0;  // no unset byte travels
};

// The parts of `particles` in the order of their first particles in the deck (the material
// table's order), over the ranks with `across`, where a part may be listed once by each rank
// holding some of its particles (the first of them first).
std::vector<FirstParticle> parts_by_first_particle(const model::Model& model,
                                                   const std::vector<ParticleCard>& particles,
                                                   const parallel::Communicator* across);

// Sets the particles' masses and part IDs on their nodes (and holds z in plane strain) and
// returns the formulation of those particles; checks every particle and throws
// InputError at the card for what the fluid cannot run, the first in the deck's order. `particles`
// are in the deck's order: every particle of the deck, or, with `across`, this rank's share of them
// (those on its block of the nodes; the checks and the parts' spacings then go over the ranks).
std::unique_ptr<FluidFormulation> build_fluid(const model::Model& model,
                                                   const std::vector<ParticleCard>& particles,
                                                   const ArtificialViscosity& viscosity,
                                                   int dimension, discretization::NodeStore& nodes,
                                                   const parallel::Communicator* across = nullptr);

}  // namespace spall::sph
