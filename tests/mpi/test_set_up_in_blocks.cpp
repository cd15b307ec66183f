// The set-up of a deck of SPH fluid alone under MPI (docs/SCALING.md §3, "The set-up in blocks"),
// run as 1, 2 and 3 ranks: each rank builds the rows of its block of the node order only, and every
// row is the whole set-up's row of that node (ID, positions, velocity from
// *INITIAL_VELOCITY_GENERATION and _NODE, mass, the SPC bits of *BOUNDARY_SPC_SET and the plane
// strain, part); the blocks are every node once; the fluid takes the particles of its block; a
// rigid wall tracks every rank's nodes in the node order with the same contact state (NSIDEX and
// OFFSET applied to each block) and a prescribed motion names its node alike. A deck of SPH solid
// alone is set up in blocks too; one with an SPH solid particle beside the fluid is set up whole.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <cstring>
#include <string>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/discretization/node_index.hpp"
#include "spall/solver/nodes_in_blocks.hpp"
#include "spall/solver/problem.hpp"
#include "spall/spg/formulation.hpp"
#include "spall/spg/setup.hpp"
#include "spall/sph/fluid.hpp"
#include "spall/sph/solid.hpp"
#include "support/spg_block.hpp"
#include "support/whole_rows.hpp"

namespace spall::solver {
namespace {

// A 2D water block of 9 x 7 particles 1 cm apart, written in an order of its own with sparse IDs,
// two nodes that carry no particle, and, with `solid`, one particle of an elastic part; with
// `rubber`, the block is of an elastic solid instead of water.
std::string deck(bool solid, bool rubber = false) {
  std::string text = "*KEYWORD\n*CONTROL_TERMINATION\n      0.01\n*CONTROL_SPH\n                                       2\n";
  text += "*SECTION_SPH\n         1       1.3       1.0       1.0\n";
  if (rubber)
    text += "*PART\nrubber\n         1         1         1\n*MAT_ELASTIC\n         1    1000.0    1.0e+7      0.45\n";
  else
    text += "*PART\nwater\n         1         1         1         1\n"
            "*MAT_NULL\n         1    1000.0       0.0     0.001\n*EOS_MURNAGHAN\n         1       7.0   81843.4\n";
  if (solid)
    text += "*PART\nsteel\n         2         2         2\n*SECTION_SPH\n         2       1.3       1.0       1.0\n"
            "*MAT_ELASTIC\n         2    7850.0   2.0e+11       0.3\n";
  text += "*NODE\n";
  std::vector<Id> particles;
  for (int k = 0; k < 63; ++k) {
    const int i = (k * 29) % 63;  // every node once, out of order
    const Id id = 10 + 7 * i;
    text += fmt::format("{:8d}{:16g}{:16g}{:16g}\n", id, 0.01 * (i % 9), 0.01 * (i / 9), 0.0);
    particles.push_back(id);
  }
  text += fmt::format("{:8d}{:16g}{:16g}{:16g}\n{:8d}{:16g}{:16g}{:16g}\n", 3, 0.2, 0.0, 0.0, 4, 0.2, 0.1, 0.0);
  if (solid) text += fmt::format("{:8d}{:16g}{:16g}{:16g}\n", 5, -0.05, 0.0, 0.0);
  text += "*ELEMENT_SPH\n";
  for (const Id id : particles) text += fmt::format("{:8d}{:8d}{:16g}\n", id, 1, 0.1);
  if (solid) text += fmt::format("{:8d}{:8d}{:16g}\n", 5, 2, 0.785);
  // Held along x and y: the particles of the first column, and node 3.
  text += "*SET_NODE_LIST\n         1\n";
  for (int j = 0; j < 7; ++j) text += fmt::format("{:10d}", 10 + 7 * 9 * j);
  text += fmt::format("{:10d}\n*BOUNDARY_SPC_SET\n         1         0         1         1\n", 3);
  // Turning about (0.04, 0.03) at 2 rad/s, one particle given its own velocity.
  text += "*INITIAL_VELOCITY_GENERATION\n         1         2       2.0       0.0       0.0       0.0\n"
          "      0.04      0.03       0.0       0.0       0.0       1.0\n";
  text += fmt::format("*INITIAL_VELOCITY_NODE\n{:10d}       0.5      -0.5       0.0\n", 10 + 7 * 40);
  text += fmt::format("*BOUNDARY_PRESCRIBED_MOTION_NODE\n{:10d}         1         0         1\n", 10 + 7 * 8);
  text += "*DEFINE_CURVE\n         1\n                 0.0                 1.0\n                 1.0                 1.0\n";
  // A floor at y = 0.015 (the first row of particles behind it), tracking the nodes within 2.05 cm
  // of it (three rows) but the second row's (NSIDEX).
  text += "*SET_NODE_LIST\n         2\n";
  for (int i = 0; i < 9; ++i) text += fmt::format("{:10d}{}", 10 + 7 * (9 + i), i % 8 == 7 ? "\n" : "");
  text += "\n*RIGIDWALL_PLANAR\n         0         2         0    0.0205\n"
          "       0.0     0.015       0.0       0.0       1.0       0.0\n*END\n";
  return text;
}

Problem set_up(const model::Model& model, SetUp how) { return build_problem(model, how); }

TEST(SetUpInBlocks, EachRankBuildsItsBlockOfTheWholeSetUp) {
  const parallel::Communicator& ranks = parallel::world();
  const model::Model model = io::keyword::read_deck_text(deck(false), "blocks.k");
  Problem whole = set_up(model, SetUp::whole);
  Problem blocks = set_up(model, SetUp::in_blocks_where_possible);
  const auto& w = whole.nodes;
  const auto& b = blocks.nodes;
  ASSERT_EQ(w.size(), 65);
  EXPECT_FALSE(w.holds_a_block());
  // Each row as it would travel (place, ID, part, positions, velocity, mass, SPC bits, ...).
  test_support::expect_whole_rows(w, b);
  const Index first = parallel::block_begin(w.size(), ranks.rank(), ranks.size());
  for (Index r = 0; r < b.size(); ++r) {
    const Index i = b.deck_index(r);
    ASSERT_EQ(i, first + r);
    EXPECT_EQ(b.row_of(i), r);
  }
  // The deck's conditions reached the rows: eight nodes held along x and y, every particle turning
  // but the one on the axis, one with its own velocity.
  int held = 0, moving = 0;
  for (Index i = 0; i < w.size(); ++i) held += (w.fixed[i] & 3u) == 3u, moving += w.v[i] != Vec3::Zero();
  EXPECT_EQ(held, 8);
  EXPECT_EQ(moving, 62);
  // Every node once over the ranks, the mass of every node.
  std::int64_t rows = b.size();
  ranks.sum({&rows, 1});
  EXPECT_EQ(rows, w.size());
  const Real mass = parallel::exact_sum(b.size(), [&](Index r) { return b.mass[r]; }, &ranks);
  EXPECT_EQ(mass, parallel::exact_sum(w.size(), [&](Index i) { return w.mass[i]; }));
  EXPECT_DOUBLE_EQ(mass, 63 * 0.1);
  // The fluid of the block's particles.
  ASSERT_EQ(blocks.formulations.size(), 1u);
  const auto& fluid = dynamic_cast<const sph::FluidFormulation&>(*blocks.formulations.front());
  Index particles = 0;
  for (Index r = 0; r < b.size(); ++r) particles += b.mass[r] > 0;
  EXPECT_EQ(fluid.particle_count(), particles);
  // The wall tracks the first row (behind it), the third and the fourth (in front), not the nodes
  // without mass: on every rank the whole set-up's nodes, with the same contact state.
  ASSERT_EQ(blocks.rigid_walls.size(), 1u);
  EXPECT_EQ(blocks.rigid_walls[0].tracked(), whole.rigid_walls[0].tracked());
  EXPECT_EQ(whole.rigid_walls[0].tracked().size(), 27u);
  Archive wall_in_blocks = Archive::for_writing(), wall_whole = Archive::for_writing();
  blocks.rigid_walls[0].checkpoint(wall_in_blocks);
  whole.rigid_walls[0].checkpoint(wall_whole);
  EXPECT_EQ(wall_in_blocks.bytes(), wall_whole.bytes());
  ASSERT_EQ(blocks.motions.size(), 1u);
  EXPECT_EQ(blocks.motions[0].node, whole.motions[0].node);
}

// The SPH solid alone is set up in blocks too: the rows are the whole set-up's, and so is the
// solid (its every particle, each on the same node, the largest sound speed).
TEST(SetUpInBlocks, TheSphSolidAloneIsSetUpInBlocksToo) {
  const model::Model model = io::keyword::read_deck_text(deck(false, true), "rubber.k");
  const Problem whole = set_up(model, SetUp::whole);
  const Problem blocks = set_up(model, SetUp::in_blocks_where_possible);
  const auto& w = whole.nodes;
  const auto& b = blocks.nodes;
  test_support::expect_whole_rows(w, b);
  ASSERT_NE(blocks.sph_solid, nullptr);
  EXPECT_EQ(blocks.sph_solid->particle_count(), 63);
  for (Index a = 0; a < 63; ++a) EXPECT_EQ(blocks.sph_solid->node_of(a), whole.sph_solid->node_of(a));
  EXPECT_GT(whole.sph_solid->max_wave_speed(), 0);
  EXPECT_EQ(blocks.sph_solid->max_wave_speed(), whole.sph_solid->max_wave_speed());
  EXPECT_EQ(blocks.rigid_walls[0].tracked(), whole.rigid_walls[0].tracked());
}

// SPG alone is set up in blocks too: each rank's rows are the whole set-up's (their masses the
// nodal volumes, added up in the same order), and its particles of each part are the whole
// set-up's on its block's nodes, byte for byte: the nodal volumes, spacings and surface flags
// (spg/setup.hpp) from the corners and faces that came from the other ranks' elements.
TEST(SetUpInBlocks, SpgAloneIsSetUpInBlocksToo) {
  const parallel::Communicator& ranks = parallel::world();
  test_support::SpgBlock bar = test_support::bar_along_z();
  bar.elements = {3, 2, 9};
  bar.jitter = 0.2;  // no two volumes alike
  model::Model model = test_support::spg_block_model(bar);
  // Two parts, the upper half of the bar the second, sharing the nodes between them.
  model.parts.push_back(model.parts.front());
  model.parts.back().id = 2;
  for (auto& e : model.solid_elements) e.pid = e.eid > 3 * 2 * 5 ? 2 : 1;
  const Problem whole = set_up(model, SetUp::whole);
  // As read under MPI: each rank holds its share of the node cards (every element card).
  model::Model dealt = model;
  dealt.cards = model::CardShare{ranks.rank(), ranks.size()};
  dealt.node_cards = static_cast<Index>(model.nodes.size());
  dealt.nodes.clear();
  for (Index k = 0; k < dealt.node_cards; ++k)
    if (dealt.cards.holds(k)) dealt.nodes.push_back(model.nodes[k]);
  const Problem blocks = set_up(ranks.size() > 1 ? dealt : model, SetUp::in_blocks_where_possible);
  const auto& w = whole.nodes;
  const auto& b = blocks.nodes;
  ASSERT_EQ(w.size(), 4 * 3 * 10);
  test_support::expect_whole_rows(w, b);
  ASSERT_EQ(blocks.formulations.size(), 1u);
  const auto& formulation = dynamic_cast<const spg::SpgFormulation&>(*blocks.formulations.front());
  EXPECT_EQ(formulation.particle_count(), 4 * 3 * 10 + 4 * 3);

  // The particles, from the element cards this rank is dealt, against the whole set-up's.
  discretization::NodeStore store;
  const NodesInBlocks in_blocks(dealt, store, ranks);
  const std::vector<spg::PartSetup> parts = spg::spg_parts_in_blocks(
      dealt, in_blocks.solid_elements(store), parallel::block_offsets(in_blocks.deck_nodes(), ranks.size()), ranks);
  discretization::NodeIndex index;
  ASSERT_EQ(index.assign(w.id), -1);
  const std::vector<spg::PartSetup> every = spg::spg_parts(model, index, w);
  ASSERT_EQ(parts.size(), 2u);
  ASSERT_EQ(every.size(), 2u);
  const Index first = parallel::block_begin(w.size(), ranks.rank(), ranks.size());
  int surface = 0, inside = 0;
  for (std::size_t p = 0; p < 2; ++p) {
    EXPECT_EQ(parts[p].settings.part_id, every[p].settings.part_id);
    std::vector<spg::ParticleSetup> held;
    for (const auto& particle : every[p].particles)
      if (particle.node >= first && particle.node < first + b.size()) held.push_back(particle);
    ASSERT_EQ(parts[p].particles.size(), held.size());
    for (std::size_t k = 0; k < held.size(); ++k) {
      const spg::ParticleSetup &built = parts[p].particles[k], &reference = held[k];
      EXPECT_EQ(built.node, reference.node);
      EXPECT_EQ(std::memcmp(&built.volume, &reference.volume, sizeof built.volume), 0) << "particle at " << built.node;
      EXPECT_EQ(std::memcmp(built.spacing.data(), reference.spacing.data(), 3 * sizeof(Real)), 0);
      EXPECT_EQ(built.on_surface, reference.on_surface) << "particle at " << built.node;
      ++(reference.on_surface ? surface : inside);
    }
  }
  // Inside the parts of 3 x 2 x 5 and 3 x 2 x 4 elements: 2 x 1 x 4 nodes and 2 x 1 x 3.
  std::int64_t counts[2] = {surface, inside};
  ranks.sum(counts);
  EXPECT_EQ(counts[1], 8 + 6);
  EXPECT_EQ(counts[0] + counts[1], 4 * 3 * 10 + 4 * 3);  // the layer between the parts twice
}

TEST(SetUpInBlocks, ADeckWithAnSphSolidBesideTheFluidIsSetUpWhole) {
  const model::Model model = io::keyword::read_deck_text(deck(true), "solid.k");
  const Problem problem = set_up(model, SetUp::in_blocks_where_possible);
  EXPECT_FALSE(problem.nodes.holds_a_block());
  EXPECT_EQ(problem.nodes.size(), 66);
  EXPECT_EQ(problem.formulations.size(), 2u);
}

}  // namespace
}  // namespace spall::solver
