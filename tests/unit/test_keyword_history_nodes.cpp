// *DATABASE_HISTORY_NODE (_SET) and *DATABASE_NODOUT: the nodes nodout.csv follows, in the order
// the cards name them and each once, the interval (GLSTAT's without the card, as LS-DYNA's ASCII
// histories), and bad input at its line; *DATABASE_HISTORY_SOLID and *DATABASE_ELOUT likewise for
// elout.csv. The motion written is checked against free fall, the stress against a column's
// weight, in tests/scripts/test_cli.sh, and both across ranks in tests/scripts/test_mpi_solid.sh.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/problem.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::prefix;
using test::read_error;
using test::row;

const std::initializer_list<int> node_widths = {8, 16, 16, 16, 8, 8};

// Three SPH particles and a node set {3, 1}: a deck the solver can build (21 lines).
const std::string particle_deck =
    "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"1.0e-3"}) + "*NODE\n" +
    row({"1", "0.0", "0.0", "0.5"}, node_widths) + row({"2", "0.0", "0.0", "0.7"}, node_widths) +
    row({"3", "0.0", "0.0", "0.9"}, node_widths) + "*SET_NODE_LIST\n" + row({"7"}) + row({"3", "1"}) +
    "*PART\nblock\n" + row({"1", "1", "1"}) + "*SECTION_SPH\n" + row({"1", "1.2", "1.0", "1.0"}) +
    "*MAT_ELASTIC\n" + row({"1", "7850.0", "2.0e11", "0.3"}) + "*ELEMENT_SPH\n" +
    row({"1", "1", "1.0e-3"}, {8, 8, 16}) + row({"2", "1", "1.0e-3"}, {8, 8, 16}) +
    row({"3", "1", "1.0e-3"}, {8, 8, 16});

// The IDs of the problem's history nodes, in its order.
std::vector<Id> history_ids(const solver::Problem& problem) {
  std::vector<Id> ids;
  for (const Index place : problem.history_nodes) ids.push_back(problem.nodes.id[problem.nodes.row_of(place)]);
  return ids;
}

TEST(keyword_history_nodes, NodesInTheCardsOrderEachOnce) {
  DeckFolder folder;
  // Node 2, then the set {3, 1}, then node 1 again and a blank field: 2, 3, 1.
  const auto model = read_deck(folder.write(
      "history.k", particle_deck + "*DATABASE_HISTORY_NODE\n" + row({"2"}) + "*DATABASE_HISTORY_NODE_SET\n" +
                       row({"7"}) + "*DATABASE_HISTORY_NODE\n" + row({"1", "", "0"}) + "*DATABASE_NODOUT\n" +
                       row({"2.5e-5", "3", "0", "0", "0", "0"})));
  ASSERT_EQ(model.history_nodes.size(), 3u);
  EXPECT_TRUE(model.history_nodes[1].sets);
  ASSERT_TRUE(model.nodout);
  EXPECT_EQ(model.nodout->dt, 2.5e-5);
  const solver::Problem problem = solver::build_problem(model);
  EXPECT_EQ(history_ids(problem), (std::vector<Id>{2, 3, 1}));
  EXPECT_EQ(problem.controls.nodout_dt, 2.5e-5);

  // Without *DATABASE_NODOUT the histories are written at the GLSTAT interval (ENDTIM / 1000).
  const auto glstat_interval =
      read_deck(folder.write("default.k", particle_deck + "*DATABASE_HISTORY_NODE\n" + row({"3"})));
  const solver::Problem defaulted = solver::build_problem(glstat_interval);
  EXPECT_EQ(history_ids(defaulted), std::vector<Id>{3});
  EXPECT_EQ(defaulted.controls.nodout_dt, defaulted.controls.glstat_dt);
}

TEST(keyword_history_nodes, BadInputAtItsLine) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*DATABASE_HISTORY_NODE\n" + row({"4", "-2"})),
            prefix(folder, 2, "*DATABASE_HISTORY_NODE") + "field ID2: '-2' is negative");
  EXPECT_EQ(read_error(folder, "*DATABASE_NODOUT\n" + row({"1.0e-5", "1", "0", "1", "1.0e-6"})),
            prefix(folder, 2, "*DATABASE_NODOUT") +
                "field DTHF: '1.0e-6': the high-frequency output is not written; give its interval as DT");
  // A node or a set that does not exist: at the card that names it (line 23 of bad.k).
  const auto missing_node =
      read_deck(folder.write("bad.k", particle_deck + "*DATABASE_HISTORY_NODE\n" + row({"1", "9"})));
  EXPECT_EQ(input_error_of([&] { solver::build_problem(missing_node); }),
            prefix(folder, 23, "*DATABASE_HISTORY_NODE") + "node 9 does not exist");
  const auto missing_set =
      read_deck(folder.write("bad.k", particle_deck + "*DATABASE_HISTORY_NODE_SET\n" + row({"8"})));
  EXPECT_EQ(input_error_of([&] { solver::build_problem(missing_set); }),
            prefix(folder, 23, "*DATABASE_HISTORY_NODE_SET") + "node set 8 does not exist");
  const auto no_interval = read_deck(folder.write("bad.k", particle_deck + "*DATABASE_NODOUT\n" + row({"0.0"})));
  EXPECT_EQ(input_error_of([&] { solver::build_problem(no_interval); }),
            prefix(folder, 23, "*DATABASE_NODOUT") + "DT: must be > 0 (or give LCUR)");
}

TEST(keyword_history_nodes, SolidElementsAndTheirInterval) {
  DeckFolder folder;
  const auto model = read_deck(folder.write(
      "bad.k", particle_deck + "*DATABASE_HISTORY_SOLID\n" + row({"4", "", "6"}) + "*DATABASE_ELOUT\n" +
                     row({"2.5e-5", "3", "0", "0", "0", "0"}) + row({"0", "0", "0", "0"})));
  ASSERT_EQ(model.history_solids.size(), 1u);
  EXPECT_EQ(model.history_solids[0].ids, (std::vector<Id>{4, 6}));
  ASSERT_TRUE(model.elout);
  EXPECT_EQ(model.elout->dt, 2.5e-5);
  // The particles are no solid elements: the first ID is an error at its card (line 23).
  EXPECT_EQ(input_error_of([&] { solver::build_problem(model); }),
            prefix(folder, 23, "*DATABASE_HISTORY_SOLID") + "solid element 4 does not exist");
  EXPECT_EQ(read_error(folder, "*DATABASE_ELOUT\n" + row({"1.0e-5"}) + row({"0", "2"})),
            prefix(folder, 3, "*DATABASE_ELOUT") +
                "field OPTION2: '2': elout.csv holds no history variables; leave it 0");
}

// *SET_SOLID (_TITLE) and *DATABASE_HISTORY_SOLID_SET: the set's elements in its order; a set that
// does not exist is an error at the history card, an element that does not exist at the set.
TEST(keyword_history_nodes, SolidSets) {
  DeckFolder folder;
  const auto model = read_deck(folder.write(
      "bad.k", particle_deck + "*SET_SOLID_TITLE\nlayer\n" + row({"5", "MECH"}) + row({"7", "0", "3"}) + row({"4"}) +
                     "*DATABASE_HISTORY_SOLID_SET\n" + row({"5", "8"})));
  ASSERT_EQ(model.solid_sets.count(5), 1u);
  EXPECT_EQ(model.solid_sets.at(5).elements, (std::vector<Id>{7, 3, 4}));
  ASSERT_EQ(model.history_solids.size(), 1u);
  EXPECT_TRUE(model.history_solids[0].sets);
  EXPECT_EQ(model.history_solids[0].ids, (std::vector<Id>{5, 8}));
  // The particle deck has no solid element 7.
  EXPECT_EQ(input_error_of([&] { validate(model); }),
            prefix(folder, 24, "*SET_SOLID") + "solid set 5: element 7 is not defined");
  const auto missing_set =
      read_deck(folder.write("bad.k", particle_deck + "*DATABASE_HISTORY_SOLID_SET\n" + row({"8"})));
  EXPECT_EQ(input_error_of([&] { solver::build_problem(missing_set); }),
            prefix(folder, 23, "*DATABASE_HISTORY_SOLID_SET") + "solid set 8 does not exist");
  EXPECT_EQ(read_error(folder, "*SET_SOLID\n" + row({"5"}) + "*SET_SOLID\n" + row({"5"})),
            prefix(folder, 4, "*SET_SOLID") + "solid set 5 is defined twice (first at " +
                (folder.path() / "bad.k").lexically_normal().string() + ":2)");
}

}  // namespace
}  // namespace spall::io::keyword
