// The SPH fluid from a deck: *DEFINE_SPH_MESH_BOX water and walls, *MAT_NULL with
// *EOS_MURNAGHAN, walls held by *BOUNDARY_SPC_SET, gravity by *LOAD_BODY_Y, plane strain by
// *CONTROL_SPH IDIM 2. A column of depth D = 0.2 m settles in 1 s (about 50 acoustic crossings);
// the pressure at depth d is rho0 g d (hydrostatics), compared over bands of two particle rows,
// tolerance 3 % below the top quarter (as tests/verification/test_sph_fluid.cpp). MAT_NULL PC is
// -1e20 (no cutoff): with PC = 0 the clipped rarefaction of the initial drop leaves the settled
// column 3 % under-pressured (docs/VALIDATION.md). Also what the deck path refuses for fluid
// parts, at the card.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "spall/sph/fluid.hpp"
#include "unit/keyword_test_decks.hpp"

using namespace spall;
using test::DeckFolder;
using test::row;

namespace {

constexpr Real g = 9.81, D = 0.2, dp = 0.01, rho0 = 1000;

// c0 = 10 sqrt(2 g D), K0 = rho0 c0^2 / 7.
std::string column_deck(const std::string& section_card = row({"1", "1.3", "1.0", "1.0"}),
                        const std::string& walls_part = row({"2", "1", "1", "1"}),
                        const std::string& control_sph = row({"", "", "", "2", "", "0"})) {
  const Real c0 = 10 * std::sqrt(2 * g * D);
  char k0[16];
  std::snprintf(k0, sizeof k0, "%.6g", rho0 * c0 * c0 / 7);
  // Walls: floor 3 layers under x in [-0.03, 0.13], side walls 3 layers up to y = 0.24; water
  // 10 x 20 particles. Wall particles come first: nodes 1 .. 48 + 72 + 72 = 192.
  return "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"1.0"}) + "*CONTROL_SPH\n" + control_sph +
         "*CONTROL_BULK_VISCOSITY\n" + row({"1.5", "0.1"}) + "*PART\nwater\n" +
         row({"1", "1", "1", "1"}) + "*PART\nwalls\n" + walls_part + "*SECTION_SPH\n" +
         section_card + "*MAT_NULL\n" + row({"1", "1000.0", "-1.0e20", "1.0e-3"}) +
         row({"2", "1000.0", "0.0", "2.0e-3"}) +
         "*EOS_MURNAGHAN\n" + row({"1", "7.0", k0}) + "*DEFINE_SPH_MESH_BOX\n" +
         row({"-0.03", "-0.03", "-0.5", "0.16", "0.03", "1.0"}) + row({"2", "16", "3", "1"}) +
         row({"-0.03", "0.0", "-0.5", "0.03", "0.24", "1.0"}) + row({"2", "3", "24", "1"}) +
         row({"0.1", "0.0", "-0.5", "0.03", "0.24", "1.0"}) + row({"2", "3", "24", "1"}) +
         "*DEFINE_SPH_MESH_BOX\n" + row({"0.0", "0.0", "-0.5", "0.1", "0.2", "1.0"}) +
         row({"1", "10", "20", "1"}) + "*SET_NODE_LIST_GENERATE\n" + row({"1"}) +
         row({"1", "192"}) + "*BOUNDARY_SPC_SET\n" + row({"1", "0", "1", "1", "1"}) +
         "*DEFINE_CURVE\n" + row({"1"}) + row({"0.0", "9.81"}, {20, 20}) +
         row({"10.0", "9.81"}, {20, 20}) + "*LOAD_BODY_Y\n" + row({"1"}) + "*END\n";
}

std::string build_error(const DeckFolder& folder, const std::string& deck) {
  const auto path = folder.write("column.k", deck);
  return test::input_error_of([&] { solver::build_problem(io::keyword::read_deck(path)); });
}

}  // namespace

TEST(SphFluidDeck, SettledColumnPressureIsRhoGD) {
  log::set_quiet(true);
  DeckFolder folder;
  const model::Model model = io::keyword::read_deck(folder.write("column.k", column_deck()));
  solver::Problem problem = solver::build_problem(model);
  ASSERT_EQ(problem.formulations.size(), 1u);
  const auto& fluid = dynamic_cast<const sph::FluidFormulation&>(*problem.formulations.front());
  EXPECT_EQ(fluid.particle_count(), 192 + 200);
  EXPECT_NEAR(fluid.parameters().smoothing_length, 1.3 * dp, 1e-12);  // CSLH x spacing
  // c0 = sqrt(GAMMA K0 / RO), K0 written with 6 digits
  EXPECT_NEAR(fluid.parameters().material.reference_sound_speed(), 10 * std::sqrt(2 * g * D), 1e-5);
  EXPECT_EQ(fluid.parameters().material.pressure_cutoff, -1.0e20);  // MAT_NULL PC
  EXPECT_EQ(fluid.parameters().viscosity.alpha, 0.1);            // *CONTROL_BULK_VISCOSITY Q2
  EXPECT_EQ(fluid.parameters().dimension, 2);
  std::vector<Index> water;
  for (Index i = 0; i < problem.nodes.size(); ++i) {
    if (problem.nodes.part[i] != 1) {
      EXPECT_EQ(problem.nodes.fixed[i], 7) << "wall node " << problem.nodes.id[i];
      continue;
    }
    water.push_back(i);
    EXPECT_NEAR(problem.nodes.mass[i], rho0 * dp * dp, 1e-12);  // RO x cell area
  }
  ASSERT_EQ(water.size(), 200u);

  solver::run(problem, {});
  discretization::FieldSet field_set(problem.nodes.size());
  fluid.write_fields(field_set, problem.nodes);
  const auto& fields = field_set.node_fields();
  ASSERT_EQ(fields.front().name, "pressure");
  const auto& pressure = std::get<std::vector<double>>(fields.front().values);
  for (Real depth : {0.25 * D, 0.5 * D, 0.75 * D, D - dp}) {
    Real sum = 0, d_sum = 0;
    int count = 0;
    for (Index i : water) {
      const Real d0 = D - problem.nodes.x0[i].y();
      if (d0 < depth - dp || d0 >= depth + dp) continue;
      sum += pressure[i];
      d_sum += D - problem.nodes.x[i].y();
      ++count;
    }
    ASSERT_EQ(count, 20);
    const Real expected = rho0 * g * d_sum / count;
    EXPECT_NEAR(sum / count, expected, 0.03 * expected) << "depth " << depth;
  }
}

TEST(SphFluidDeck, RefusesWhatTheFluidCannotRun) {
  log::set_quiet(true);
  DeckFolder folder;
  const auto at = [&](int line, const std::string& keyword) {
    return (folder.path() / "column.k").lexically_normal().string() + ":" + std::to_string(line) +
           ": " + keyword + ": ";
  };
  EXPECT_EQ(build_error(folder, column_deck(row({"1", "1.3", "1.0", "1.0", "", "", "", "2"}))),
            at(15, "*SECTION_SPH") + "SPHKERN 2: not implemented (0 cubic spline, 1 quintic spline, 4 Wendland C2)");
  // The water (part 1, section 1) with the cubic spline, its walls (part 2, section 2) with the quintic.
  EXPECT_EQ(build_error(folder, column_deck(row({"1", "1.3", "1.0", "1.0"}) + "*SECTION_SPH\n" +
                                                row({"2", "1.3", "1.0", "1.0", "", "", "", "1"}),
                                            row({"2", "2", "1", "1"}))),
            at(15, "*SECTION_SPH") +
                "part 1: SPHKERN 0, but SPH fluid part 2 has SPHKERN 1: the SPH fluid's particles interact "
                "through one kernel");
  EXPECT_EQ(build_error(folder, column_deck(row({"1", "1.3", "1.0", "1.0"}), row({"2", "1", "2", "1"}))),
            at(10, "*PART") +
                "part 1: MID 1 EOSID 1, but SPH fluid part 2 has MID 2 EOSID 1: the SPH fluid takes "
                "one liquid (one MID and EOSID for all its parts)");
  EXPECT_EQ(build_error(folder, column_deck(row({"1", "1.3", "1.0", "1.0"}), row({"2", "1", "1", "1"}),
                                            row({"", "", "", "2", "", "0", "0.1"}))),
            at(5, "*CONTROL_SPH") + "START 0.1 / DT 1e+20: the SPH fluid has no start or death time");
}

// In plane strain the fluid's particles lie in one plane; one off it is refused at its card (it
// was an internal error, an exception from the formulation).
TEST(SphFluidDeck, PlaneStrainParticleOffThePlaneIsRefusedAtItsCard) {
  log::set_quiet(true);
  DeckFolder folder;
  const std::initializer_list<int> node_widths = {8, 16, 16, 16};
  const std::initializer_list<int> sph_widths = {8, 8, 16};
  const std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"1.0"}) + "*CONTROL_SPH\n" +
                           row({"", "", "", "2", "", "0"}) + "*PART\nwater\n" + row({"1", "1", "1", "1"}) +
                           "*SECTION_SPH\n" + row({"1", "1.3", "1.0", "1.0"}) + "*MAT_NULL\n" +
                           row({"1", "1000.0", "-1.0e20", "1.0e-3"}) + "*EOS_MURNAGHAN\n" +
                           row({"1", "7.0", "1.0e5"}) + "*NODE\n" + row({"1", "0.0", "0.0", "0.0"}, node_widths) +
                           row({"2", "0.01", "0.0", "0.005"}, node_widths) + "*ELEMENT_SPH\n" +
                           row({"1", "1", "-1.0e-4"}, sph_widths) + row({"2", "1", "-1.0e-4"}, sph_widths);
  EXPECT_EQ(build_error(folder, deck),
            (folder.path() / "column.k").lexically_normal().string() +
                ":20: *ELEMENT_SPH: particle 2 lies at z = 0.005, off the plane z = 0 of particle 1: in plane "
                "strain (*CONTROL_SPH IDIM 2) every particle of the SPH fluid lies in one plane");
}
