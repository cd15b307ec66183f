// make_material: from the cards of a part to the library's Material. Moduli from E and PR
// (K = E / (3 (1 - 2 nu)), G = E / (2 (1 + nu))), Ep = E ETAN / (E - ETAN) (LS-DYNA keyword
// manual, *MAT_PLASTIC_KINEMATIC), the LCSS curve with *DEFINE_CURVE's scaling, E0 / rho0 from
// the EOS card, and the combinations that cannot run refused at the card's line.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/materials/make_material.hpp"

namespace spall::materials {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::row;

model::Model read_text(const DeckFolder& folder, const std::string& text) {
  return io::keyword::read_deck(folder.write("deck.k", text));
}

TEST(materials_make_material, ModuliHardeningAndCurves) {
  DeckFolder folder;
  const auto model = read_text(
      folder, "*MAT_PLASTIC_KINEMATIC\n" +
                  row({"1", "7.85e-9", "150000", "0.34", "390", "90", "1"}) +
                  row({"40", "5", "0.8"}) + "*MAT_PIECEWISE_LINEAR_PLASTICITY\n" +
                  row({"2", "2.7e-9", "70000", "0.33"}) + row({"", "", "5"}) + "*DEFINE_CURVE\n" +
                  row({"5", "0", "1.0", "1.5", "0.0", "10.0"}) + row({"0.0", "200"}, {20, 20}) +
                  row({"0.1", "240"}, {20, 20}) + "*PART\nbar\n" + row({"1", "1", "1"}) +
                  "*PART\nplate\n" + row({"2", "1", "2"}));
  const Material steel = make_material(model, model.parts[0]);
  EXPECT_EQ(steel.density, 7.85e-9);
  EXPECT_DOUBLE_EQ(steel.shear_modulus, 150000 / (2 * 1.34));
  EXPECT_DOUBLE_EQ(std::get<LinearBulk>(steel.eos).bulk_modulus, 150000 / (3 * (1 - 0.68)));
  const auto& kinematic = std::get<PlasticKinematic>(steel.strength);
  EXPECT_EQ(kinematic.yield_stress, 390.0);
  EXPECT_DOUBLE_EQ(kinematic.hardening_modulus, 150000.0 * 90 / (150000 - 90));
  EXPECT_EQ(kinematic.beta, 1.0);
  EXPECT_EQ(kinematic.rate.c, 40.0);
  EXPECT_EQ(kinematic.rate.p, 5.0);
  EXPECT_EQ(kinematic.failure_strain, 0.8);
  EXPECT_EQ(steel.tensile_limit, TensileLimit::none);

  // sigma_y = SFO o + OFFO = 1.5 o + 10: 310 at eps_p = 0, 370 at 0.1, slope 600 beyond.
  const Material aluminium = make_material(model, model.parts[1]);
  const auto& curve = std::get<PiecewiseLinear>(aluminium.strength).curve;
  EXPECT_DOUBLE_EQ(curve.at(0).stress, 310.0);
  EXPECT_DOUBLE_EQ(curve.at(0.05).stress, 340.0);
  EXPECT_DOUBLE_EQ(curve.at(0.3).stress, 490.0);
  EXPECT_DOUBLE_EQ(curve.at(0.3).slope, 600.0);
}

TEST(materials_make_material, JohnsonCookWithAndWithoutEquationOfState) {
  DeckFolder folder;
  const std::string jc = row({"90e6", "292e6", "0.31", "0.025", "1.09", "1356", "298", "1.0"}) +
                         row({"383", "-1.2e9", "1"});
  const auto model = read_text(
      folder, "*MAT_JOHNSON_COOK\n" + row({"1", "8960", "46.3e9", "124e9", "0.34"}) + jc +
                  "*MAT_JOHNSON_COOK\n" + row({"2", "8960", "46.3e9"}) + jc + "*EOS_GRUNEISEN\n" +
                  row({"3", "3940", "1.49", "", "", "2.02", "0.47", "8.96e9"}) + "*PART\nno eos\n" +
                  row({"1", "1", "1"}) + "*PART\ngruneisen\n" + row({"2", "1", "2", "3"}));
  // Without EOS: K from E and PR (LS-DYNA reads them for shells; Spall's stated choice).
  const Material linear = make_material(model, model.parts[0]);
  EXPECT_DOUBLE_EQ(std::get<LinearBulk>(linear.eos).bulk_modulus, 124e9 / (3 * (1 - 0.68)));
  EXPECT_EQ(linear.shear_modulus, 46.3e9);
  EXPECT_EQ(linear.tensile_limit, TensileLimit::pressure_cutoff);  // SPALL 1
  EXPECT_EQ(linear.pressure_cutoff, -1.2e9);
  EXPECT_EQ(linear.initial_temperature, 298.0);
  EXPECT_EQ(initial_state(linear).temperature, 298.0);
  // With *EOS_GRUNEISEN: E0 is per unit reference volume, e0 = E0 / rho0 = 1e6 J/kg.
  const Material shock = make_material(model, model.parts[1]);
  EXPECT_TRUE(std::holds_alternative<Gruneisen>(shock.eos));
  EXPECT_DOUBLE_EQ(shock.initial_specific_energy, 8.96e9 / 8960);
}

TEST(materials_make_material, RefusesWhatCannotRun) {
  DeckFolder folder;
  const auto model = read_text(
      folder, "*MAT_PLASTIC_KINEMATIC\n" + row({"1", "7.85e-9", "150000", "0.34", "390"}) +
                  "*MAT_RIGID\n" + row({"2", "7.85e-9", "2e5", "0.3"}) + row({}) +
                  "*EOS_MURNAGHAN\n" + row({"3", "7", "3.1e8"}) + "*PART\nbar\n" +
                  row({"1", "1", "1", "3"}) + "*PART\ntool\n" + row({"2", "1", "2"}) +
                  "*PART\nmissing\n" + row({"3", "1", "9"}));
  const std::string file = (folder.path() / "deck.k").lexically_normal().string();
  EXPECT_EQ(input_error_of([&] { make_material(model, model.parts[0]); }),
            file +
                ":10: *PART: part 1: EOSID 3: *MAT_PLASTIC_KINEMATIC computes its own pressure "
                "(K = E / (3 (1 - 2 PR))) and takes no equation of state");
  EXPECT_EQ(
      input_error_of([&] { make_material(model, model.parts[1]); }),
      file + ":4: *MAT_RIGID: material 2 is a rigid body, not a deformable material (part 2)");
  EXPECT_EQ(input_error_of([&] { make_material(model, model.parts[2]); }),
            file + ":16: *PART: part 3: MID: material 9 is not defined");
}

}  // namespace
}  // namespace spall::materials
