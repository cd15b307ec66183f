// *RIGIDWALL_PLANAR (_MOVING, _FINITE, _FINITE_MOVING, _ID) and *DATABASE_RWFORC: values,
// documented defaults (LS-DYNA manual), bad input at its line, and what the solver refuses.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/problem.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::row;
using test::prefix;
using test::read_error;

const std::initializer_list<int> node_widths = {8, 16, 16, 16, 8, 8};

// One SPH particle and the controls: a deck the solver can build.
const std::string particle_deck =
    "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"1.0e-3"}) + "*NODE\n" +
    row({"1", "0.0", "0.0", "0.5"}, node_widths) + row({"2", "0.0", "0.0", "0.7"}, node_widths) +
    "*SET_NODE_LIST\n" + row({"1"}) + row({"1", "2"}) + "*SET_NODE_LIST\n" + row({"2"}) + row({"2"}) +
    "*PART\nblock\n" + row({"1", "1", "1"}) + "*SECTION_SPH\n" + row({"1", "1.2", "1.0", "1.0"}) +
    "*MAT_ELASTIC\n" + row({"1", "7850.0", "2.0e11", "0.3"}) + "*ELEMENT_SPH\n" +
    row({"1", "1", "1.0e-3"}, {8, 8, 16}) + row({"2", "1", "1.0e-3"}, {8, 8, 16});


TEST(keyword_rigid_walls, DefaultsOfEveryField) {
  DeckFolder folder;
  // Card 1 blank; DEATH and RWKSF 0 take their defaults 1e20 and 1 (blank and 0 read alike).
  const auto model = read_deck(folder.write(
      "wall.k", particle_deck + "*RIGIDWALL_PLANAR\n" + row({}) +
                    row({"", "", "", "", "", "1.0"}) + "*RIGIDWALL_PLANAR\n" +
                    row({"", "", "", "", "", "0.0", "0.0"}) + row({"1.0", "", "", "2.0"}) + "*END\n"));
  EXPECT_NO_THROW(validate(model));
  ASSERT_EQ(model.rigid_walls.size(), 2u);
  const auto& wall = model.rigid_walls[0];
  EXPECT_EQ(wall.id, 0);
  EXPECT_EQ(wall.nsid, 0);
  EXPECT_EQ(wall.nsidex, 0);
  EXPECT_EQ(wall.boxid, 0);
  EXPECT_EQ(wall.offset, 0.0);
  EXPECT_EQ(wall.birth, 0.0);
  EXPECT_EQ(wall.death, 1.0e20);
  EXPECT_EQ(wall.rwksf, 1.0);
  EXPECT_EQ(wall.tail, Vec3::Zero());
  EXPECT_EQ(wall.head, Vec3(0, 0, 1));
  EXPECT_EQ(wall.fric, 0.0);
  EXPECT_EQ(wall.wvel, 0.0);
  EXPECT_FALSE(wall.finite);
  EXPECT_FALSE(wall.moving);
  EXPECT_EQ(wall.keyword, "*RIGIDWALL_PLANAR");
  EXPECT_EQ(wall.where.line, 24);  // card 1, after the 22 lines of particle_deck
  EXPECT_EQ(model.rigid_walls[1].death, 1.0e20);
  EXPECT_EQ(model.rigid_walls[1].rwksf, 1.0);
  EXPECT_EQ(model.rigid_walls[1].tail, Vec3(1, 0, 0));
  EXPECT_FALSE(model.rwforc.has_value());
}

TEST(keyword_rigid_walls, EveryOptionWithItsCards) {
  DeckFolder folder;
  const auto model = read_deck(folder.write(
      "wall.k",
      particle_deck + "*RIGIDWALL_PLANAR_FINITE_MOVING_ID\n" + row({"7"}, {10}).substr(0, 10) +
          "upper plate\n" + row({"1", "2", "0", "0.25", "1.0e-4", "2.0e-3", "2.0"}) +
          row({"0.0", "0.0", "1.0", "0.0", "0.0", "0.0", "0.35", "3.0"}) +
          row({"1.0", "0.0", "1.0", "0.4", "0.3"}) + row({"12.5", "-4.0"}) +
          "*RIGIDWALL_PLANAR_MOVING\n" + row({}) + row({"", "", "", "", "1.0"}) + row({"3.0"}) +
          "*DATABASE_RWFORC\n" + row({"1.0e-5", "1", "", ""}) + "*END\n"));
  EXPECT_NO_THROW(validate(model));
  ASSERT_EQ(model.rigid_walls.size(), 2u);
  const auto& wall = model.rigid_walls[0];
  EXPECT_EQ(wall.keyword, "*RIGIDWALL_PLANAR_FINITE_MOVING_ID");
  EXPECT_EQ(wall.id, 7);
  EXPECT_EQ(wall.title, "upper plate");
  EXPECT_EQ(wall.nsid, 1);
  EXPECT_EQ(wall.nsidex, 2);
  EXPECT_EQ(wall.offset, 0.25);
  EXPECT_EQ(wall.birth, 1.0e-4);
  EXPECT_EQ(wall.death, 2.0e-3);
  EXPECT_EQ(wall.rwksf, 2.0);
  EXPECT_EQ(wall.tail, Vec3(0, 0, 1));
  EXPECT_EQ(wall.head, Vec3(0, 0, 0));  // the normal points down, towards the nodes below
  EXPECT_EQ(wall.fric, 0.35);
  EXPECT_EQ(wall.wvel, 3.0);
  EXPECT_TRUE(wall.finite);
  EXPECT_EQ(wall.edge_head, Vec3(1, 0, 1));
  EXPECT_EQ(wall.lenl, 0.4);
  EXPECT_EQ(wall.lenm, 0.3);
  EXPECT_TRUE(wall.moving);
  EXPECT_EQ(wall.mass, 12.5);
  EXPECT_EQ(wall.v0, -4.0);
  const auto& moving = model.rigid_walls[1];
  EXPECT_TRUE(moving.moving);
  EXPECT_FALSE(moving.finite);
  EXPECT_EQ(moving.mass, 3.0);
  EXPECT_EQ(moving.v0, 0.0);
  ASSERT_TRUE(model.rwforc.has_value());
  EXPECT_EQ(model.rwforc->dt, 1.0e-5);
  EXPECT_EQ(model.rwforc->lcdt, 0);
  EXPECT_EQ(model.rwforc->ioopt, 1);  // blank -> 1
}

TEST(keyword_rigid_walls, BadCardsFailAtTheirLine) {
  DeckFolder folder;
  const std::string card1 = row({});
  EXPECT_EQ(read_error(folder, "*RIGIDWALL_PLANAR\n" + card1 + row({"1.0", "2.0", "3.0", "1.0", "2.0", "3.0"})),
            prefix(folder, 3, "*RIGIDWALL_PLANAR") +
                "the head XH YH ZH (1, 2, 3) equals the tail XT YT ZT: the wall has no normal");
  EXPECT_EQ(read_error(folder, "*RIGIDWALL_PLANAR_FINITE\n" + card1 + row({"", "", "", "", "", "1.0"}) +
                                   row({"1.0", "", "", "-1.0", "1.0"})),
            prefix(folder, 4, "*RIGIDWALL_PLANAR_FINITE") +
                "field LENL: '-1.0' is negative (0 = unbounded along l)");
  EXPECT_EQ(read_error(folder, "*RIGIDWALL_PLANAR_FINITE\n" + card1 + row({"", "", "", "", "", "1.0"}) +
                                   row({"", "", "5.0", "1.0", "1.0"})),
            prefix(folder, 4, "*RIGIDWALL_PLANAR_FINITE") +
                "the edge vector from XT YT ZT to XHEV YHEV ZHEV (0, 0, 5) is parallel to the wall "
                "normal");
  EXPECT_EQ(read_error(folder, "*RIGIDWALL_PLANAR\n" + card1 +
                                   row({"", "", "", "", "", "1.0", "1.5"})),
            prefix(folder, 3, "*RIGIDWALL_PLANAR") +
                "field FRIC: '1.5' is not 0 (frictionless), between 0 and 1 (Coulomb), 1 (no "
                "sliding), 2 or 3 (welding)");
  EXPECT_EQ(read_error(folder, "*RIGIDWALL_PLANAR_MOVING\n" + card1 + row({"", "", "", "", "", "1.0"}) +
                                   row({"", "5.0"})),
            prefix(folder, 4, "*RIGIDWALL_PLANAR_MOVING") +
                "field MASS: is blank but has no default; a value is required");
  EXPECT_EQ(read_error(folder, "*RIGIDWALL_PLANAR_MOVING\n" + card1 + row({"", "", "", "", "", "1.0"}) +
                                   row({"0.0"})),
            prefix(folder, 4, "*RIGIDWALL_PLANAR_MOVING") + "field MASS: '0.0' must be greater than 0");
  EXPECT_EQ(read_error(folder, "*RIGIDWALL_PLANAR\n" + card1 + row({"", "", "", "", "", "1.0"}) + row({"1"})),
            prefix(folder, 4, "*RIGIDWALL_PLANAR") +
                "unexpected data line; one *RIGIDWALL_PLANAR defines one wall");
  EXPECT_EQ(read_error(folder, "*RIGIDWALL_PLANAR\n" + card1),
            prefix(folder, 2, "*RIGIDWALL_PLANAR") + "missing card 2 (XT YT ZT XH YH ZH FRIC WVEL)");
  EXPECT_EQ(read_error(folder, "*DATABASE_RWFORC\n" + row({"1.0e-5", "1", "0", "4"})),
            prefix(folder, 2, "*DATABASE_RWFORC") + "field IOOPT: '4' is not 1, 2 or 3");
}

TEST(keyword_rigid_walls, ValidateNamesTheMissingSet) {
  DeckFolder folder;
  const auto path = folder.write(
      "bad.k", particle_deck + "*RIGIDWALL_PLANAR_ID\n" + row({"3"}) + row({"9"}) +
                   row({"", "", "", "", "", "1.0"}));
  const auto model = read_deck(path);
  EXPECT_EQ(input_error_of([&] { validate(model); }),
            prefix(folder, 25, "*RIGIDWALL_PLANAR_ID") + "NSID: node set 9 is not defined");
  const auto exempt = read_deck(folder.write(
      "bad.k", particle_deck + "*RIGIDWALL_PLANAR\n" + row({"1", "8"}) + row({"", "", "", "", "", "1.0"})));
  EXPECT_EQ(input_error_of([&] { validate(exempt); }),
            prefix(folder, 24, "*RIGIDWALL_PLANAR") + "NSIDEX: node set 8 is not defined");
}

TEST(keyword_rigid_walls, SolverRefusesBoxesAndBuildsTheTrackedNodes) {
  log::set_quiet(true);
  DeckFolder folder;
  const std::string normal_up = row({"", "", "", "", "", "1.0"});
  const auto boxed = read_deck(
      folder.write("bad.k", particle_deck + "*RIGIDWALL_PLANAR\n" + row({"0", "0", "4"}) + normal_up));
  EXPECT_EQ(input_error_of([&] { solver::build_problem(boxed); }),
            prefix(folder, 24, "*RIGIDWALL_PLANAR") + "BOXID 4: *DEFINE_BOX is not supported yet");
  const auto curve_output = read_deck(folder.write(
      "bad.k", particle_deck + "*DEFINE_CURVE\n" + row({"5"}) + row({"0.0", "1.0e-5"}, {20, 20}) +
                   "*DATABASE_RWFORC\n" + row({"0.0", "1", "5", "2"})));
  EXPECT_EQ(input_error_of([&] { solver::build_problem(curve_output); }),
            prefix(folder, 27, "*DATABASE_RWFORC") +
                "IOOPT 2: only 1 (next output at LCUR of the current time) is supported");
  const auto no_interval =
      read_deck(folder.write("bad.k", particle_deck + "*DATABASE_RWFORC\n" + row({"0.0"})));
  EXPECT_EQ(input_error_of([&] { solver::build_problem(no_interval); }),
            prefix(folder, 24, "*DATABASE_RWFORC") + "DT: must be > 0 (or give LCUR)");

  // NSID 1 = nodes 1, 2; NSIDEX 2 = node 2: node 1 only. OFFSET 0.3 about z = 0.3: node 1
  // (z = 0.5) only. NSID 0: every node with mass.
  const auto model = read_deck(folder.write(
      "walls.k", particle_deck + "*RIGIDWALL_PLANAR\n" + row({"1", "2"}) + normal_up +
                     "*RIGIDWALL_PLANAR\n" + row({"0", "0", "0", "0.3"}) +
                     row({"", "", "0.3", "", "", "1.0"}) + "*RIGIDWALL_PLANAR_ID\n" + row({"42"}) +
                     row({}) + normal_up));
  const solver::Problem problem = solver::build_problem(model);
  ASSERT_EQ(problem.rigid_walls.size(), 3u);
  auto tracked_ids = [&](const contact::RigidWall& wall) {
    std::vector<Id> ids;
    for (Index i : wall.tracked()) ids.push_back(problem.nodes.id[i]);
    std::sort(ids.begin(), ids.end());
    return ids;
  };
  EXPECT_EQ(tracked_ids(problem.rigid_walls[0]), std::vector<Id>{1});
  EXPECT_EQ(tracked_ids(problem.rigid_walls[1]), std::vector<Id>{1});
  EXPECT_EQ(tracked_ids(problem.rigid_walls[2]), (std::vector<Id>{1, 2}));
  // Walls without _ID are numbered in deck order, as LS-DYNA does.
  EXPECT_EQ(problem.rigid_walls[0].definition().id, 1);
  EXPECT_EQ(problem.rigid_walls[1].definition().id, 2);
  EXPECT_EQ(problem.rigid_walls[2].definition().id, 42);
  // Without *DATABASE_RWFORC the forces are written at the GLSTAT interval.
  EXPECT_EQ(problem.controls.rwforc_dt, problem.controls.glstat_dt);
}

// Fields with no effect on a kinematic wall are said so, once per wall, not dropped silently.
TEST(keyword_rigid_walls, FieldsWithoutEffectAreWarnings) {
  DeckFolder folder;
  const auto model = read_deck(folder.write(
      "warn.k", particle_deck + "*RIGIDWALL_PLANAR\n" + row({"", "", "", "", "", "", "2.5"}) +
                    row({"", "", "", "", "", "1.0", "0.2", "4.0"})));
  ::testing::internal::CaptureStderr();
  solver::build_problem(model);
  const std::string warnings = ::testing::internal::GetCapturedStderr();
  const std::string at = (folder.path() / "warn.k").lexically_normal().string() + ":24: *RIGIDWALL_PLANAR: ";
  EXPECT_NE(warnings.find(at + "RWKSF 2.5: scales a penalty stiffness that the kinematic wall does "
                               "not have; no effect"),
            std::string::npos)
      << warnings;
  EXPECT_NE(warnings.find(at + "WVEL 4: the welding speed applies only with FRIC 2 or 3; no effect "
                               "with FRIC 0.2"),
            std::string::npos)
      << warnings;
}

}  // namespace
}  // namespace spall::io::keyword
