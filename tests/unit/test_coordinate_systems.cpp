// *DEFINE_COORDINATE_SYSTEM, _VECTOR and _NODES: read, and accepted where a card names one with the
// global axes (the origin does not matter for directions); a turned or undefined system is refused
// at the card that names it, saying which.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/problem.hpp"
#include "support/sph_block.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::row;

// Systems 1-3 have the global axes (1 with its origin away from 0), 4 is turned 90 degrees about
// z, 5 follows its nodes (FLAG 1).
const std::string systems =
    "*DEFINE_COORDINATE_SYSTEM_TITLE\nglobal, moved\n" + row({"1", "5.0", "5.0", "5.0", "6.0", "5.0", "5.0"}) +
    row({"5.0", "7.0", "5.0"}) + "*DEFINE_COORDINATE_VECTOR\n" + row({"2", "2.0", "0.0", "0.0", "1.0", "3.0", "0.0"}) +
    "*DEFINE_COORDINATE_NODES\n" + row({"3", "101", "102", "103", "0", "X"}) +
    "*DEFINE_COORDINATE_VECTOR\n" + row({"4", "0.0", "1.0", "0.0", "-1.0", "0.0", "0.0"}) +
    "*DEFINE_COORDINATE_NODES\n" + row({"5", "101", "102", "103", "1"}) + "*NODE\n" +
    row({"101", "1.0", "1.0", "1.0"}, {8, 16, 16, 16}) + row({"102", "2.0", "1.0", "1.0"}, {8, 16, 16, 16}) +
    row({"103", "1.0", "4.0", "1.0"}, {8, 16, 16, 16});

// The error message of reading `text` as bad.k, from the file name on.
std::string read_error_text(const DeckFolder& folder, const std::string& text) {
  const std::string message = test::read_error(folder, text);
  return message.substr(message.rfind('/') + 1);
}

TEST(coordinate_systems, TheThreeKeywordsAreRead) {
  DeckFolder folder;
  const auto model = read_deck(folder.write("cs.k", "*KEYWORD\n" + systems + "*END\n"));
  ASSERT_EQ(model.coordinate_systems.size(), 5u);
  EXPECT_TRUE(model.unsupported.empty());
  const auto& moved = model.coordinate_systems.at(1);
  EXPECT_EQ(moved.keyword, "*DEFINE_COORDINATE_SYSTEM_TITLE");
  EXPECT_EQ(moved.axis, Vec3(1, 0, 0));
  EXPECT_EQ(moved.in_plane, Vec3(0, 2, 0));
  EXPECT_EQ(model.coordinate_systems.at(4).axis, Vec3(0, 1, 0));
  EXPECT_EQ(model.coordinate_systems.at(3).nodes, (std::array<Id, 3>{101, 102, 103}));
  EXPECT_TRUE(model.coordinate_systems.at(5).follows_nodes);
  EXPECT_EQ(read_error_text(folder, "*DEFINE_COORDINATE_NODES\n" + row({"6", "1", "2", "3", "0", "W"})),
            "bad.k:2: *DEFINE_COORDINATE_NODES: field DIR: 'W' is not X, Y or Z");
}

model::Model block_with(Id icid, Id spc_cid) {
  DeckFolder folder;
  model::Model block = test_support::elastic_block_model({Vec3(0.1, 0.1, 0.1), 0.025});
  const auto read = read_deck(folder.write("cs.k", "*KEYWORD\n" + systems + "*END\n"));
  block.coordinate_systems = read.coordinate_systems;
  block.nodes.insert(block.nodes.end(), read.nodes.begin(), read.nodes.end());
  model::InitialVelocityGeneration generation;
  generation.id = 1;
  generation.v = Vec3(1, 0, 0);
  generation.icid = icid;
  block.initial_velocity_generations.push_back(generation);
  model::Spc spc;
  spc.target = model::Target::node;
  spc.id = 1;
  spc.cid = spc_cid;
  spc.dof[0] = true;
  block.spcs.push_back(spc);
  return block;
}

TEST(coordinate_systems, GlobalAxesAreAcceptedTurnedOrUndefinedOnesRefused) {
  for (const Id global : {1, 2, 3}) EXPECT_NO_THROW(solver::build_problem(block_with(global, global))) << global;
  // FLAG 1 at t = 0 is the nodes' axes: fine for an initial velocity, not for a constraint.
  EXPECT_NO_THROW(solver::build_problem(block_with(5, 0)));
  const auto error = [](Id icid, Id cid) { return input_error_of([&] { solver::build_problem(block_with(icid, cid)); }); };
  EXPECT_NE(error(4, 0).find("*INITIAL_VELOCITY_GENERATION: ICID: coordinate system 4 (*DEFINE_COORDINATE_VECTOR at "),
            std::string::npos)
      << error(4, 0);
  EXPECT_NE(error(4, 0).find("has local x axis (0, 1, 0), not the global one"), std::string::npos) << error(4, 0);
  EXPECT_NE(error(0, 5).find("*BOUNDARY_SPC_NODE: CID: coordinate system 5 (*DEFINE_COORDINATE_NODES at "),
            std::string::npos)
      << error(0, 5);
  EXPECT_NE(error(0, 5).find("turns with its nodes during the run (FLAG 1)"), std::string::npos) << error(0, 5);
  EXPECT_NE(error(9, 0).find("*INITIAL_VELOCITY_GENERATION: ICID: coordinate system 9 is not defined"),
            std::string::npos)
      << error(9, 0);
}

}  // namespace
}  // namespace spall::io::keyword
