#pragma once
// The set-up of a rank's block of the node order from every rank's share of the deck's node and
// particle cards (model::CardShare), for a deck of SPH fluid or SPH solid alone under MPI
// (docs/SCALING.md §5 step 4 f1-f4), and of a deck of SPG alone (§3): no rank holds every node.
// The node order is the one-process run's (the cells of the nodes' box, then the deck's order),
// found as a sort over the ranks; a node's place is looked up at the rank of its ID, where every
// node card's ID and place went.
#include <utility>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/model/model.hpp"
#include "spall/spg/setup.hpp"
#include "spall/sph/fluid_setup.hpp"

namespace spall::solver {

// Refuses a node whose coordinates no double arithmetic of the run could take (InputError at its card).
void check_node_position(const model::Node& node);
// The edge of the cells whose order, with the deck's within a cell, is the node order: about 16
// nodes a cell for a uniform cloud of `count` nodes in `box` (the order matters, the exact size not).
Real node_order_cell(const BoundingBox& box, Index count);

// The axes of the node order: the cells are row-major over the box's axes from its shortest extent
// to its longest (ties in x, y, z order), so that a block of the order is a slab across a body's
// length (a bar, a sheet's width), whose elements and particles read the nodes within a layer of
// cells either side, not a slab along it, whose neighbours lie a whole layer of cells away in the
// order (docs/SCALING.md §3, "The node order's axes").
struct NodeOrderAxes {
  explicit NodeOrderAxes(const BoundingBox& box);
  // The position as the cells of the order bin it: its coordinates on those axes, in that order.
  Vec3 operator()(const Vec3& x) const { return {x[axis[0]], x[axis[1]], x[axis[2]]}; }
  BoundingBox operator()(const BoundingBox& box) const;
  std::array<int, 3> axis{0, 1, 2};
};

class NodesInBlocks {
 public:
  // This rank's block of the node order, [first_row(), first_row() + nodes.size()), as rows of
  // `nodes`, from its share of the node cards (every card's share by CardShare{rank, ranks} where the
  // model is whole). Collective; the first bad card in the deck's order stops every rank.
  NodesInBlocks(const model::Model& model, discretization::NodeStore& nodes, const parallel::Communicator& ranks);

  Index first_row() const { return first_row_; }
  Index deck_nodes() const { return deck_nodes_; }

  // The (ID, place) of the nodes these IDs name, ascending by ID, the same list on every rank: an
  // ID no card gives is not in it. Collective.
  std::vector<std::pair<Id, Index>> places_of(std::vector<Id> ids) const;

  // The deck's particles on the nodes of this rank's block, in the deck's order (their cards are
  // kept here), each with its node's row. Collective; a particle on no node or on a node that
  // carries another stops every rank at the first such card in the deck's order.
  std::vector<sph::ParticleCard> particles();

  // This rank's share of the *ELEMENT_SOLID cards (every rank holds them all; CardShare{rank,
  // ranks} deals them), ascending in the deck's order, with their corners' places (asked of the
  // ranks of their IDs) and positions (of the ranks whose blocks of `nodes` hold them). Collective.
  std::vector<spg::ElementCorners> solid_elements(const discretization::NodeStore& nodes) const;

 private:
  struct Entry {  // a node card's ID, its place in the node order and its line
    Id id;
    Index place;
    model::Model::CardLine line;
  };
  const model::Model& model_;
  const parallel::Communicator& ranks_;
  Index deck_nodes_ = 0;
  Index first_row_ = 0;
  std::vector<Entry> directory_;              // the node cards whose IDs this rank keeps, by ID
  std::vector<model::ElementSph> particles_;  // the cards of particles()
};

}  // namespace spall::solver
