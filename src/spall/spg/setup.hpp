#pragma once
// Building the SPG formulation from the model: the parts whose section is *SECTION_SOLID_SPG
// (ELFORM 47), their particles at the nodes of their *ELEMENT_SOLID mesh, nodal volumes and
// lumped masses from the elements (spg/nodal_volumes.hpp), and every section field checked: what
// Spall cannot run is an InputError naming the field.
#include <array>
#include <memory>
#include <vector>

#include "spall/model/model.hpp"
#include "spall/discretization/formulation.hpp"
#include "spall/discretization/node_index.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/spg/nodal_volumes.hpp"
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

// An *ELEMENT_SOLID card as a rank sets it up in blocks (solver::NodesInBlocks::solid_elements).
struct ElementCorners {
  const model::ElementSolid* card = nullptr;
  Index ordinal = 0;            // among the deck's *ELEMENT_SOLID cards
  std::array<Index, 8> place{};  // each corner's node's place in the node order, -1 where no *NODE card gives it
  HexCorners x{};               // their positions
};

// Set up in blocks (an SPG deck alone under MPI, docs/SCALING.md §3): the SPG parts with the
// particles on this rank's block of the node order, [blocks[rank], blocks[rank + 1]), from its
// share of the element cards (`elements`, ascending by ordinal): each corner's volume and extent
// and each face go to the ranks of their places, where they add up in the deck's order as
// spg_parts adds them. Every rank has every part, in the order of their IDs. Collective; the
// first bad element in the deck's order stops every rank with spg_parts' message.
std::vector<PartSetup> spg_parts_in_blocks(const model::Model& model, const std::vector<ElementCorners>& elements,
                                           const std::vector<Index>& blocks, const parallel::Communicator& ranks);

// build_spg set up in blocks: the particles of spg_parts_in_blocks, their masses and part on the
// rows of this rank's block (`nodes`, the first of them at place blocks[rank]). Collective.
std::unique_ptr<discretization::Formulation> build_spg_in_blocks(const model::Model& model,
                                                                 const std::vector<ElementCorners>& elements,
                                                                 const std::vector<Index>& blocks,
                                                                 discretization::NodeStore& nodes,
                                                                 const parallel::Communicator& ranks);

}  // namespace spall::spg
