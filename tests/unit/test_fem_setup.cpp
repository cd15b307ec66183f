// Solid finite elements from a deck (issue 32): *HOURGLASS and *CONTROL_HOURGLASS as LS-DYNA
// documents them (fem-contact.md §1.2: QM 0.1, IHQ 0 -> the global type, else type 2 for explicit
// solids), the lumped mass rho0 V, tetrahedra written as hexahedron cards, and one clear error
// naming the card and field for what Spall does not run.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/core/log.hpp"
#include "spall/fem/solid_elements.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/problem.hpp"
#include "support/spg_block.hpp"

using namespace spall;
using test::DeckFolder;
using test::input_error_of;
using test::row;

namespace {

test_support::SpgBlock cube(int elform) {
  test_support::SpgBlock b;
  b.elements = {2, 2, 2};
  b.size = Vec3(0.2, 0.2, 0.2);
  b.fem = test_support::FiniteElements{elform, {}};
  return b;
}

std::string build_error(const model::Model& m) {
  return input_error_of([&] { solver::build_problem(m); });
}

const fem::SolidElements& solid_elements(const solver::Problem& p) {
  for (const auto& f : p.formulations)
    if (const auto* s = dynamic_cast<const fem::SolidElements*>(f.get())) return *s;
  throw std::logic_error("no solid elements");
}

}  // namespace

TEST(FemSetup, HourglassCardsAreRead) {
  DeckFolder folder;
  const model::Model m = io::keyword::read_deck(folder.write(
      "hourglass.k", "*HOURGLASS_TITLE\nstiff\n" + row({"7", "4", "0.05", "", "2.0", "0.1"}) + "*HOURGLASS\n" +
                         row({"8"}) + "*CONTROL_HOURGLASS\n" + row({"1", "0.08"}) + "*END\n"));
  const auto& stiff = m.hourglasses.at(7);
  EXPECT_EQ(stiff.ihq, 4);
  EXPECT_EQ(stiff.qm, 0.05);
  EXPECT_EQ(stiff.q1, 2.0);
  EXPECT_EQ(stiff.q2, 0.1);
  const auto& blank = m.hourglasses.at(8);
  EXPECT_EQ(blank.ihq, 0);
  EXPECT_EQ(blank.qm, 0.1);  // the manual's default
  EXPECT_EQ(blank.q1, 0.0);  // 0: *CONTROL_BULK_VISCOSITY's value
  ASSERT_TRUE(m.control_hourglass);
  EXPECT_EQ(m.control_hourglass->ihq, 1);
  EXPECT_EQ(m.control_hourglass->qh, 0.08);
}

TEST(FemSetup, HourglassTypesSpallDoesNotHaveAreRefusedAtTheCard) {
  DeckFolder folder;
  const auto path = folder.write("ihq6.k", "*HOURGLASS\n" + row({"1", "6"}) + "*END\n");
  EXPECT_EQ(input_error_of([&] { io::keyword::read_deck(path); }),
            path.string() + ":2: *HOURGLASS: field IHQ: '6': not implemented (Spall has 1 viscous, 2-3 "
                            "Flanagan-Belytschko viscous and 4-5 Flanagan-Belytschko stiffness forms)");
  const auto control = folder.write("control.k", "*CONTROL_HOURGLASS\n" + row({"11"}) + "*END\n");
  EXPECT_NE(input_error_of([&] { io::keyword::read_deck(control); }).find("is not an hourglass type"),
            std::string::npos);
}

TEST(FemSetup, HourglassTypeIsTheCardsThenTheGlobalOneThenType2) {
  log::set_quiet(true);
  const auto form_of = [](const model::Model& m) {
    return solid_elements(solver::build_problem(m)).parts().at(0).hourglass;
  };
  model::Model m = test_support::spg_block_model(cube(1));
  EXPECT_EQ(form_of(m).form, fem::HourglassForm::viscous);  // IHQ 0 everywhere: type 2
  EXPECT_EQ(form_of(m).coefficient, 0.1);
  m.control_hourglass = model::ControlHourglass{5, 0.03, {}};
  EXPECT_EQ(form_of(m).form, fem::HourglassForm::stiffness);
  EXPECT_EQ(form_of(m).coefficient, 0.03);
  m.hourglasses[1] = model::Hourglass{1, 1, 0.07, 0, 0, {}};
  m.parts[0].hgid = 1;
  EXPECT_EQ(form_of(m).form, fem::HourglassForm::viscous_base);
  EXPECT_EQ(form_of(m).coefficient, 0.07);
  m.hourglasses[1].ihq = 0;  // the card's IHQ 0: the global type
  EXPECT_EQ(form_of(m).form, fem::HourglassForm::stiffness);
  // Fully integrated elements have no hourglass modes to control.
  model::Model full = test_support::spg_block_model(cube(2));
  full.control_hourglass = model::ControlHourglass{4, 0.1, {}};
  EXPECT_EQ(form_of(full).form, fem::HourglassForm::none);
}

TEST(FemSetup, BulkViscosityComesFromTheHourglassCardWhereItGivesIt) {
  log::set_quiet(true);
  model::Model m = test_support::spg_block_model(cube(2));
  m.bulk_viscosity.q1 = 1.2;
  m.bulk_viscosity.q2 = 0.05;
  m.hourglasses[1] = model::Hourglass{1, 0, 0.1, 2.0, 0, {}};
  m.parts[0].hgid = 1;
  // The problem is kept: a reference into a temporary one would dangle (AddressSanitizer found it).
  const solver::Problem problem = solver::build_problem(m);
  const auto& part = solid_elements(problem).parts().at(0);
  EXPECT_EQ(part.bulk_quadratic, 2.0);
  EXPECT_EQ(part.bulk_linear, 0.05);
}

TEST(FemSetup, NodalMassesAddUpToTheBodysMass) {
  log::set_quiet(true);
  for (int elform : {1, 2}) {
    auto b = cube(elform);
    b.jitter = 0.2;
    const solver::Problem p = solver::build_problem(test_support::spg_block_model(b));
    Real mass = 0;
    for (Real m : p.nodes.mass) mass += m;
    EXPECT_NEAR(mass, b.density * b.size.prod(), 1e-12 * mass);
  }
}

TEST(FemSetup, WhatSpallDoesNotRunIsRefusedNamingTheField) {
  log::set_quiet(true);
  model::Model m = test_support::spg_block_model(cube(3));
  EXPECT_NE(build_error(m).find("*SECTION_SOLID: ELFORM 3: not implemented"), std::string::npos) << build_error(m);
  m.sections[1] = model::SectionSolid{1, -2, 0, {}};
  EXPECT_NE(build_error(m).find("ELFORM -2: the fully integrated hexahedra for poor aspect ratios"), std::string::npos);
  m.sections[1] = model::SectionSolid{1, 1, 1, {}};
  EXPECT_NE(build_error(m).find("AET 1"), std::string::npos);
  m.sections[1] = model::SectionSolid{1, 10, 0, {}};
  EXPECT_NE(build_error(m).find("element 1: part 1 has ELFORM 10 (tetrahedra) but the element is not written as one"),
            std::string::npos);
  model::Model missing = test_support::spg_block_model(cube(1));
  missing.parts[0].hgid = 9;
  EXPECT_NE(build_error(missing).find("*PART: part 1: HGID 9: no *HOURGLASS has that ID"), std::string::npos);
  model::Model inverted = test_support::spg_block_model(cube(1));
  auto& n = inverted.solid_elements[0].n;
  std::swap(n[0], n[4]), std::swap(n[1], n[5]), std::swap(n[2], n[6]), std::swap(n[3], n[7]);
  EXPECT_NE(build_error(inverted).find("*ELEMENT_SOLID: element 1: volume -"), std::string::npos);
}

TEST(FemSetup, TetrahedraAreWrittenAsHexahedronCards) {
  log::set_quiet(true);
  model::Model m = test_support::spg_block_model(cube(10));
  // Each hexahedron as five tetrahedra, N4 repeated to N8.
  std::vector<model::ElementSolid> tetrahedra;
  static constexpr int five[5][4] = {{0, 1, 3, 4}, {1, 2, 3, 6}, {1, 4, 5, 6}, {3, 6, 7, 4}, {1, 3, 4, 6}};
  Id eid = 1;
  std::map<Id, Vec3> x;
  for (const auto& node : m.nodes) x[node.id] = node.x;
  for (const auto& hex : m.solid_elements)
    for (const auto& t : five) {
      model::ElementSolid e = hex;
      e.eid = eid++;
      std::array<Id, 4> c = {hex.n[t[0]], hex.n[t[1]], hex.n[t[2]], hex.n[t[3]]};
      if ((x[c[1]] - x[c[0]]).dot((x[c[2]] - x[c[0]]).cross(x[c[3]] - x[c[0]])) < 0) std::swap(c[1], c[2]);
      e.n = {c[0], c[1], c[2], c[3], c[3], c[3], c[3], c[3]};
      tetrahedra.push_back(e);
    }
  m.solid_elements = tetrahedra;
  const solver::Problem p = solver::build_problem(m);
  EXPECT_EQ(solid_elements(p).element_count(), 40);
  Real mass = 0;
  for (Real value : p.nodes.mass) mass += value;
  EXPECT_NEAR(mass, 7850 * 0.008, 1e-12);
}

TEST(FemSetup, AddErosionCardsAreReadAndWhatSpallLacksIsRefused) {
  DeckFolder folder;
  const model::Model m = io::keyword::read_deck(folder.write(
      "erosion.k", "*MAT_ADD_EROSION\n" + row({"1", "", "2.0e9", "", "0.3", "", "", "2"}) +
                       row({"-1.0e9", "1.5e9", "", "0.4", "", "", "", "1.0e-3"}) + "*CONTROL_TIMESTEP\n" +
                       row({"", "0.8", "", "", "", "", "1"}) + "*END\n"));
  const auto& e = m.add_erosions.at(1);
  EXPECT_EQ(e.mxpres, 2.0e9);
  EXPECT_EQ(e.effeps, 0.3);
  EXPECT_EQ(e.ncs, 2);
  EXPECT_EQ(e.numfip, 1);  // the default
  EXPECT_EQ(e.mnpres, -1.0e9);
  EXPECT_EQ(e.sigp1, 1.5e9);
  EXPECT_EQ(e.mxeps, 0.4);
  EXPECT_EQ(e.failtm, 1.0e-3);
  EXPECT_EQ(m.timestep.erode, 1);
  EXPECT_EQ(m.timestep.tssfac, 0.8);
  const auto refused = [&](const std::string& cards) {
    return input_error_of([&] { io::keyword::read_deck(folder.write("bad.k", cards + "*END\n")); });
  };
  EXPECT_NE(refused("*MAT_ADD_EROSION\n" + row({"1"}) + row({"", "", "", "", "", "5.0e8"})).find("field SIGTH"),
            std::string::npos);
  EXPECT_NE(refused("*MAT_ADD_EROSION\n" + row({"1"}) + row({}) + row({"1"})).find("field IDAM"), std::string::npos);
  EXPECT_NE(refused("*MAT_ADD_EROSION\n" + row({"1"}) + row({"", "", "", "-5"})).find("field MXEPS"), std::string::npos);
  EXPECT_NE(refused("*CONTROL_TIMESTEP\n" + row({"", "", "", "", "", "", "2"})).find("field ERODE"), std::string::npos);
}

TEST(FemSetup, AddErosionOnParticlesOrAMissingMaterialIsRefused) {
  log::set_quiet(true);
  test_support::SpgBlock b;
  b.elements = {2, 2, 2};
  b.size = Vec3(0.2, 0.2, 0.2);
  model::Model spg = test_support::spg_block_model(b);
  spg.add_erosions[1].mid = 1;
  EXPECT_NE(build_error(spg).find("*MAT_ADD_EROSION: MID 1: part 1 uses it and is not meshed with solid finite elements"),
            std::string::npos) << build_error(spg);
  model::Model missing = test_support::spg_block_model(cube(1));
  missing.add_erosions[7].mid = 7;
  EXPECT_NE(build_error(missing).find("MID 7: no material has that ID"), std::string::npos);
  // The criteria a part gets: each value that is not EXCL.
  model::Model m = test_support::spg_block_model(cube(1));
  model::MatAddErosion card;
  card.mid = 1;
  card.excl = 99;
  card.mxpres = 99;  // excluded
  card.sigvm = 0;    // a criterion at 0 once EXCL is not 0
  card.failtm = 99;
  card.mneps = card.effeps = card.voleps = card.mnpres = card.sigp1 = card.mxeps = 99;
  m.add_erosions[1] = card;
  const solver::Problem problem = solver::build_problem(m);
  const auto& erosion = solid_elements(problem).parts().at(0).erosion;
  EXPECT_FALSE(erosion.max_pressure);
  ASSERT_TRUE(erosion.von_mises);
  EXPECT_EQ(*erosion.von_mises, 0.0);
  EXPECT_FALSE(erosion.failure_time);
}
