// A deck's node and particle cards held in shares (model::CardShare, docs/SCALING.md §5 step 4 f1-f4),
// run as 1, 2 and 3 ranks: each rank keeps its chunks of the *NODE and *ELEMENT_SPH cards (those a
// *DEFINE_SPH_MESH_BOX generates among them, whose two counts differ here), the cards gathered are
// the deck's, and the set-up in blocks from the shares builds on each rank the rows of its block
// of the one-process node order, byte for byte the whole set-up's, with the nodes other cards name
// found over the ranks. Bad cards (a node or a particle given twice, a particle on no node or of no
// part, coordinates out of range, two of them in one deck; an SPH solid's parts that cannot run)
// stop every rank with the one-process run's message, whichever rank holds the card; so do an SPG
// deck's bad element cards and section, set up in blocks from the node cards in shares.
#include <gtest/gtest.h>

#include <fmt/format.h>

#include <string>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/problem.hpp"
#include "spall/sph/fluid.hpp"
#include "support/whole_rows.hpp"

namespace spall::solver {
namespace {

const model::CardShare& shares() {
  static const model::CardShare share{parallel::world().rank(), parallel::world().size()};
  return share;
}

// A water block from a mesh box of 25 x 20 x 20 particles (nodes 900 004 to 910 003), ten
// particles of their own cards on nodes 10-19 beside it, and three nodes without particles
// (900 001-900 003) given first, so that the generated node cards are three ahead of the particle
// cards; `extra` goes before *END. With `solid` the block is of an elastic solid, not water.
std::string deck(const std::string& extra = "", bool solid = false) {
  std::string text = "*KEYWORD\n*CONTROL_TERMINATION\n      0.01\n";
  text += "*SECTION_SPH\n         1       1.3       1.0       1.0\n";
  if (solid)
    text += "*PART\nrubber\n         1         1         1\n*MAT_ELASTIC\n         1    1000.0    1.0e+7      0.45\n";
  else
    text += "*PART\nwater\n         1         1         1         1\n"
            "*MAT_NULL\n         1    1000.0       0.0     0.001\n*EOS_MURNAGHAN\n         1       7.0   81843.4\n";
  text += "*NODE\n";
  for (int k = 1; k <= 3; ++k) text += fmt::format("{:8d}{:16g}{:16g}{:16g}\n", 900000 + k, 0.5, 0.01 * k, 0.0);
  for (int k = 0; k < 10; ++k) text += fmt::format("{:8d}{:16g}{:16g}{:16g}\n", 10 + k, -0.01, 0.01 * k, 0.005);
  text += "*ELEMENT_SPH\n";
  for (int k = 0; k < 10; ++k) text += fmt::format("{:8d}{:8d}{:16g}\n", 10 + k, 1, -1e-6);
  text +=
      "*DEFINE_SPH_MESH_BOX\n       0.0       0.0       0.0      0.25       0.2       0.2\n"
      "         1        25        20        20                   0       0.0\n";
  // Held along z: the first 600 generated nodes and node 900 002; one node given a velocity, one moved.
  text += "*SET_NODE_LIST_GENERATE\n         1\n    900004    900603\n*SET_NODE_LIST\n         2\n    900002\n";
  text += "*BOUNDARY_SPC_SET\n         1         0         0         0         1\n";
  text += "*BOUNDARY_SPC_SET\n         2         0         1         1         1\n";
  text += "*INITIAL_VELOCITY_NODE\n    909000       0.5      -0.5       0.0\n";
  text += "*BOUNDARY_PRESCRIBED_MOTION_NODE\n    907000         1         0         1\n";
  text +=
      "*DEFINE_CURVE\n         1\n                 0.0                 1.0\n                 1.0                 1.0\n";
  return text + extra + "*END\n";
}

TEST(CardsInShares, EachRankKeepsItsChunksAndGathersTheDeck) {
  const model::Model whole = io::keyword::read_deck_text(deck(), "shares.k");
  model::Model shared = io::keyword::read_deck_text(deck(), "shares.k", shares());
  ASSERT_EQ(whole.nodes.size(), 10013u);
  ASSERT_EQ(whole.sph_elements.size(), 10010u);
  EXPECT_EQ(shared.node_card_count(), 10013);
  EXPECT_EQ(shared.sph_card_count(), 10010);
  Index nodes = 0, particles = 0;
  for (Index k = 0; k < 10013; ++k) nodes += shares().holds(k);
  for (Index k = 0; k < 10010; ++k) particles += shares().holds(k);
  ASSERT_EQ(static_cast<Index>(shared.nodes.size()), nodes);
  ASSERT_EQ(static_cast<Index>(shared.sph_elements.size()), particles);
  for (std::size_t k = 0; k < shared.nodes.size(); ++k) {
    const model::Node &held = shared.nodes[k], &card = whole.nodes[shares().ordinal(static_cast<Index>(k))];
    ASSERT_EQ(held.id, card.id);
    ASSERT_EQ(held.x, card.x);
    ASSERT_EQ(held.where.line, card.where.line);
  }
  for (std::size_t k = 0; k < shared.sph_elements.size(); ++k) {
    const model::ElementSph &held = shared.sph_elements[k],
                            &card = whole.sph_elements[shares().ordinal(static_cast<Index>(k))];
    ASSERT_EQ(held.nid, card.nid);
    ASSERT_EQ(held.mass, card.mass);
  }
  EXPECT_NO_THROW(io::keyword::validate(shared));
  EXPECT_EQ(sets_up_in_blocks(shared), parallel::world().size() > 1);
  shared.gather_cards();
  EXPECT_TRUE(shared.cards.whole());
  ASSERT_EQ(shared.nodes.size(), whole.nodes.size());
  ASSERT_EQ(shared.sph_elements.size(), whole.sph_elements.size());
  for (std::size_t k = 0; k < whole.nodes.size(); ++k) {
    ASSERT_EQ(shared.nodes[k].id, whole.nodes[k].id);
    ASSERT_EQ(shared.nodes[k].x, whole.nodes[k].x);
    ASSERT_EQ(shared.nodes[k].where.line, whole.nodes[k].where.line);
  }
  for (std::size_t k = 0; k < whole.sph_elements.size(); ++k)
    ASSERT_EQ(shared.sph_elements[k].nid, whole.sph_elements[k].nid);
}

TEST(CardsInShares, TheSetUpInBlocksIsTheWholeSetUps) {
  const parallel::Communicator& ranks = parallel::world();
  const model::Model whole_model = io::keyword::read_deck_text(deck(), "shares.k");
  const model::Model shared = io::keyword::read_deck_text(deck(), "shares.k", shares());
  io::keyword::validate(shared);
  const Problem whole = build_problem(whole_model, SetUp::whole);
  const Problem blocks = build_problem(shared, SetUp::in_blocks_where_possible);
  const auto& w = whole.nodes;
  const auto& b = blocks.nodes;
  ASSERT_EQ(w.size(), 10013);
  test_support::expect_whole_rows(w, b);
  // The conditions reached their nodes: 601 held along z (node 900 002 along every axis), one velocity.
  int held = 0, moving = 0;
  for (Index i = 0; i < w.size(); ++i) held += (w.fixed[i] & 4u) != 0, moving += w.v[i] != Vec3::Zero();
  EXPECT_EQ(held, 601);
  EXPECT_EQ(moving, 1);
  ASSERT_EQ(blocks.motions.size(), 1u);
  EXPECT_EQ(blocks.motions[0].node, whole.motions[0].node);
  ASSERT_EQ(blocks.formulations.size(), 1u);
  const auto& fluid = dynamic_cast<const sph::FluidFormulation&>(*blocks.formulations.front());
  std::int64_t counts[2] = {fluid.particle_count(), 0};
  for (Index r = 0; r < b.size(); ++r) counts[1] += b.mass[r] > 0;
  EXPECT_EQ(counts[0], counts[1]);
  ranks.sum(counts);
  EXPECT_EQ(counts[0], 10010);
}

// The message a deck stops with, as one process reads and sets it up whole, or as each rank reads
// its share and the ranks set it up in blocks (the cards gathered where the deck is not set up so).
std::string failure(const std::string& text, bool in_shares) {
  try {
    model::Model model = io::keyword::read_deck_text(text, "bad.k", in_shares ? shares() : model::CardShare{});
    if (!model.cards.whole() && !sets_up_in_blocks(model)) model.gather_cards();
    io::keyword::validate(model);
    build_problem(model, in_shares ? SetUp::in_blocks_where_possible : SetUp::whole);
  } catch (const InputError& e) {
    return e.what();
  }
  return {};
}

TEST(CardsInShares, BadCardsStopEveryRankAsOneProcess) {
  const auto node_card = [](Id id, Real x, Real y, Real z) {
    return fmt::format("*NODE\n{:8d}{:16g}{:16g}{:16g}\n", id, x, y, z);
  };
  std::string many_nodes;
  for (int k = 0; k < 4100; ++k) many_nodes += node_card(1000 + k, 1.0, 0.001 * k, 0.0);
  const std::vector<std::pair<std::string, std::string>> cases = {
      // A node card 4 100 cards after the first of its ID: the repeat is in the second chunk, held by
      // the second rank.
      {many_nodes + node_card(1000, 1.0, 1.0, 1.0), "node 1000 is defined twice (first at bad.k:"},
      {"*ELEMENT_SPH\n      15       1  -1e-06\n", "particle 15 is defined twice"},
      {"*ELEMENT_SPH\n   99999       1  -1e-06\n", "particle 99999: node 99999 is not defined"},
      {"*ELEMENT_SPH\n       3       7  -1e-06\n", "particle 3: part 7 is not defined"},
      {node_card(5, 1e101, 0.0, 0.0), "coordinates beyond"},
      // Two: the node card's coordinates come before the repeat, which the checks find first.
      {node_card(5, 1e101, 0.0, 0.0) + "*ELEMENT_SPH\n      12       1  -1e-06\n", "particle 12 is defined twice"},
      {"*BOUNDARY_PRESCRIBED_MOTION_NODE\n     30000         1         0         1\n", "node 30000 is not defined"},
  };
  for (const auto& [extra, expected] : cases) {
    const std::string text = deck(extra);
    const std::string one_process = failure(text, false), in_shares = failure(text, true);
    EXPECT_NE(one_process.find(expected), std::string::npos) << one_process << " for " << extra;
    EXPECT_EQ(in_shares, one_process) << extra;
  }
  // The SPH solid alone, set up in blocks too: two parts whose sections have a death time, which
  // stops the set-up at the first particle of either in the deck's order (the cards past the mesh
  // box's, in the third chunk).
  std::string dying;
  for (int part = 2; part <= 3; ++part)
    dying += fmt::format("*PART\nbad\n{:10d}{:10d}{:10d}\n*SECTION_SPH\n{:10d}       1.3       1.0       1.0{:>20s}\n",
                         part, part, 1, part, "1.0");
  std::vector<std::string> messages;
  for (const auto& [first, second] : {std::pair(2, 3), std::pair(3, 2)}) {
    const std::string text =
        deck(dying + fmt::format("*ELEMENT_SPH\n  900003{:8d}  -1e-06\n  900002{:8d}  -1e-06\n", first, second), true);
    const std::string one_process = failure(text, false), in_shares = failure(text, true);
    EXPECT_NE(one_process.find("DEATH/START: particle birth and death are not implemented"), std::string::npos)
        << one_process;
    EXPECT_EQ(in_shares, one_process);
    messages.push_back(one_process);
  }
  EXPECT_NE(messages[0], messages[1]);  // each at its own section's card
  EXPECT_EQ(failure(deck("", true), true), "");
}

// An SPG block of 16 x 16 x 16 elements of 1 mm (4 913 nodes: two chunks of node cards, the
// 4 096 elements one), IDs k + 1 in x-fastest order; `extra` goes before *END.
std::string spg_deck(const std::string& extra = "") {
  std::string text = "*KEYWORD\n*CONTROL_TERMINATION\n      0.01\n*PART\nblock\n         1         1         1\n";
  text += "*SECTION_SOLID_SPG\n         1        47\n       1.6       1.6       1.6\n         1\n";
  text += "*MAT_ELASTIC\n         1    7850.0   2.0e+11       0.3\n*NODE\n";
  const auto id = [](int i, int j, int k) { return 1 + i + 17 * (j + 17 * k); };
  for (int k = 0; k <= 16; ++k)
    for (int j = 0; j <= 16; ++j)
      for (int i = 0; i <= 16; ++i)
        text += fmt::format("{:8d}{:16g}{:16g}{:16g}\n", id(i, j, k), 1e-3 * i, 1e-3 * j, 1e-3 * k);
  text += "*ELEMENT_SOLID\n";
  int eid = 1;
  for (int k = 0; k < 16; ++k)
    for (int j = 0; j < 16; ++j)
      for (int i = 0; i < 16; ++i)
        text += fmt::format("{:8d}{:8d}\n{:8d}{:8d}{:8d}{:8d}{:8d}{:8d}{:8d}{:8d}\n", eid++, 1, id(i, j, k),
                            id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k), id(i, j, k + 1), id(i + 1, j, k + 1),
                            id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1));
  return text + extra + "*END\n";
}

// SPG alone is set up in blocks: bad element cards (a corner on no node, of no part, an inverted
// element, two of them in one deck) and a section that cannot run stop every rank as one process.
TEST(CardsInShares, BadSpgCardsStopEveryRankAsOneProcess) {
  model::Model shared = io::keyword::read_deck_text(spg_deck(), "spg.k", shares());
  EXPECT_EQ(sets_up_in_blocks(shared), parallel::world().size() > 1);
  // Element 5001 on the first cell upside down (N5-N8 below N1-N4); 5002 on the last cell likewise.
  const std::string inverted_first =
      "*ELEMENT_SOLID\n    5001       1\n     290     291     308     307       1       2      19      18\n";
  const std::string inverted_last =
      "*ELEMENT_SOLID\n    5002       1\n    4895    4896    4913    4912    4606    4607    4624    4623\n";
  const std::vector<std::pair<std::string, std::string>> cases = {
      {"*ELEMENT_SOLID\n    5000       1\n       1       2   99999      18     290     291     308     307\n",
       "element 5000: node N3 = 99999 is not defined"},
      {"*ELEMENT_SOLID\n    5000       7\n       1       2      19      18     290     291     308     307\n",
       "element 5000: part 7 is not defined"},
      // Two: the missing node of the later card is found at another rank than the part of the first.
      {"*ELEMENT_SOLID\n    5000       7\n       1       2      19      18     290     291     308     307\n"
       "    5003       1\n       1       2   99999      18     290     291     308     307\n",
       "element 5000: part 7 is not defined"},
      {inverted_first, "element 5001: inverted or flat"},
      {inverted_last + inverted_first, "element 5002: inverted or flat"},
      {inverted_first + inverted_last, "element 5001: inverted or flat"},
  };
  for (const auto& [extra, expected] : cases) {
    const std::string text = spg_deck(extra);
    const std::string one_process = failure(text, false), in_shares = failure(text, true);
    EXPECT_NE(one_process.find(expected), std::string::npos) << one_process << " for " << extra;
    EXPECT_EQ(in_shares, one_process) << extra;
  }
  std::string itb3 = spg_deck();
  itb3.replace(itb3.find("\n         1\n*MAT_ELASTIC"), 12, "\n         1       0.0       0.0         3\n");
  const std::string one_process = failure(itb3, false);
  EXPECT_NE(one_process.find("ITB 3"), std::string::npos) << one_process;
  EXPECT_EQ(failure(itb3, true), one_process);
  EXPECT_EQ(failure(spg_deck(), true), "");
}

}  // namespace
}  // namespace spall::solver
