// The plastic materials, *MAT_NULL and the EOS cards: every field lands where it should, blank
// fields take their documented defaults (LS-DYNA keyword manual, keywords.md §5), and bad input
// is one `file:line: *KEYWORD: ...` error naming the field.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::row;
using test::prefix;
using test::read_error;
using test::validate_error;

model::Model read_text(const DeckFolder& folder, const std::string& text) {
  return read_deck(folder.write("deck.k", text));
}

// Taylor-bar steel in t-mm-s (keywords.md §10: ansys/pydyna examples/Taylor_Bar).
TEST(keyword_materials, PlasticKinematicFields) {
  DeckFolder folder;
  const auto model =
      read_text(folder, "*MAT_PLASTIC_KINEMATIC\n" +
                            row({"3", "7.85e-9", "150000", "0.34", "390", "90", "0.5"}) +
                            row({"40.0", "5.0", "0.8", "0"}) + "*MAT_003_TITLE\nno card 2\n" +
                            row({"4", "7.85e-9", "150000", "", "390"}));
  const auto& given = std::get<model::MatPlasticKinematic>(model.materials.at(3).params);
  EXPECT_EQ(model.materials.at(3).keyword, "*MAT_PLASTIC_KINEMATIC");
  EXPECT_EQ(model.materials.at(3).where.line, 2);
  EXPECT_EQ(given.ro, 7.85e-9);
  EXPECT_EQ(given.e, 150000.0);
  EXPECT_EQ(given.pr, 0.34);
  EXPECT_EQ(given.sigy, 390.0);
  EXPECT_EQ(given.etan, 90.0);
  EXPECT_EQ(given.beta, 0.5);
  EXPECT_EQ(given.src, 40.0);
  EXPECT_EQ(given.srp, 5.0);
  EXPECT_EQ(given.fs, 0.8);
  EXPECT_EQ(given.vp, 0);
  // Blank PR, ETAN, BETA and the whole card 2: 0 (BETA 0 is kinematic hardening).
  const auto& defaults = std::get<model::MatPlasticKinematic>(model.materials.at(4).params);
  EXPECT_EQ(model.materials.at(4).keyword, "*MAT_PLASTIC_KINEMATIC");
  EXPECT_EQ(defaults.pr, 0.0);
  EXPECT_EQ(defaults.etan, 0.0);
  EXPECT_EQ(defaults.beta, 0.0);
  EXPECT_EQ(defaults.src, 0.0);
  EXPECT_EQ(defaults.srp, 0.0);
  EXPECT_EQ(defaults.fs, 0.0);
  EXPECT_EQ(defaults.vp, 0);
}

TEST(keyword_materials, PlasticKinematicRefusesTheViscoplasticOption) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*MAT_003\n" + row({"3", "7.85e-9", "150000", "0.34", "390", "90"}) +
                                   row({"0", "0", "0", "1"})),
            prefix(folder, 3, "*MAT_003") +
                "field VP: 1 (viscoplastic rate formulation) is not implemented; use 0 (scale the "
                "yield stress)");
  EXPECT_EQ(
      read_error(folder, "*MAT_003\n" + row({"3", "7.85e-9", "150000", "0.34", "390", "150000"})),
      prefix(folder, 2, "*MAT_003") + "field ETAN: 150000 must be at least 0 and below E = 150000");
}

TEST(keyword_materials, PiecewiseLinearPlasticityFields) {
  DeckFolder folder;
  const auto model =
      read_text(folder, "*MAT_PIECEWISE_LINEAR_PLASTICITY\n" +
                            row({"5", "2.7e-9", "70000", "0.33", "200", "700", "0.4"}) +
                            row({"6500", "4", "0", "0", "-1"}) + row({"0.0", "0.1", "0.5"}) +
                            row({"200", "260", "300"}) + "*MAT_024\n" +
                            row({"6", "2.7e-9", "70000", "0.33", "200", "700"}) +
                            row({"", "", "9"}) + row({}) + row({}));
  const auto& given = std::get<model::MatPiecewiseLinearPlasticity>(model.materials.at(5).params);
  EXPECT_EQ(given.ro, 2.7e-9);
  EXPECT_EQ(given.e, 70000.0);
  EXPECT_EQ(given.pr, 0.33);
  EXPECT_EQ(given.sigy, 200.0);
  EXPECT_EQ(given.etan, 700.0);
  EXPECT_EQ(given.fail, 0.4);
  EXPECT_EQ(given.tdel, 0.0);
  EXPECT_EQ(given.c, 6500.0);
  EXPECT_EQ(given.p, 4.0);
  EXPECT_EQ(given.lcss, 0);
  EXPECT_EQ(given.lcsr, 0);
  EXPECT_EQ(given.vp, -1);
  EXPECT_EQ(given.points, (std::vector<std::pair<Real, Real>>{{0.0, 200}, {0.1, 260}, {0.5, 300}}));
  // FAIL blank: 1e21 (no failure); C, P, VP 0; blank EPS/ES cards: no points.
  const auto& defaults =
      std::get<model::MatPiecewiseLinearPlasticity>(model.materials.at(6).params);
  EXPECT_EQ(model.materials.at(6).keyword, "*MAT_PIECEWISE_LINEAR_PLASTICITY");
  EXPECT_EQ(defaults.fail, 1.0e21);
  EXPECT_EQ(defaults.c, 0.0);
  EXPECT_EQ(defaults.p, 0.0);
  EXPECT_EQ(defaults.lcss, 9);
  EXPECT_EQ(defaults.vp, 0);
  EXPECT_TRUE(defaults.points.empty());
}

TEST(keyword_materials, PiecewiseLinearPlasticityRefusesARateCurveAndBadPoints) {
  DeckFolder folder;
  const std::string card1 = row({"5", "2.7e-9", "70000", "0.33", "200", "700"});
  EXPECT_EQ(read_error(folder, "*MAT_024\n" + card1 + row({"0", "0", "3", "4"})),
            prefix(folder, 3, "*MAT_024") +
                "field LCSR: a strain-rate scaling curve is not implemented; use C and P "
                "(Cowper-Symonds)");
  EXPECT_EQ(read_error(folder, "*MAT_024\n" + card1 + row({}) + row({"0.0", "0.2", "0.1"}) +
                                   row({"200", "260", "300"})),
            prefix(folder, 4, "*MAT_024") +
                "field EPS3: 0.1 does not increase (the previous point is at 0.2)");
}

// LS-PrePost writes cards 3-4 all zero when LCSS gives the curve (or when SIGY and ETAN do), and
// pads a shorter table with zero pairs: LS-DYNA ends the table after the last nonzero point.
TEST(keyword_materials, PiecewiseLinearPlasticityZeroPairsEndTheTable) {
  DeckFolder folder;
  const std::string zeros = row({"0.0", "0.0", "0.0", "0.0", "0.0", "0.0", "0.0", "0.0"});
  const auto model = read_text(
      folder, "*MAT_024\n" + row({"5", "2.7e-9", "70000", "0.33", "0.0", "0.0"}) + row({"0", "0", "9"}) + zeros +
                  zeros + "*MAT_024\n" + row({"6", "2.7e-9", "70000", "0.33", "200", "700"}) + row({}) + zeros +
                  zeros + "*MAT_024\n" + row({"7", "2.7e-9", "70000", "0.33"}) + row({}) +
                  row({"0.0", "0.1", "0.5", "0.0", "0.0", "0.0", "0.0", "0.0"}) +
                  row({"200", "260", "300", "0.0", "0.0", "0.0", "0.0", "0.0"}));
  EXPECT_TRUE(std::get<model::MatPiecewiseLinearPlasticity>(model.materials.at(5).params).points.empty());
  EXPECT_TRUE(std::get<model::MatPiecewiseLinearPlasticity>(model.materials.at(6).params).points.empty());
  EXPECT_EQ(std::get<model::MatPiecewiseLinearPlasticity>(model.materials.at(7).params).points,
            (std::vector<std::pair<Real, Real>>{{0.0, 200}, {0.1, 260}, {0.5, 300}}));
  // A zero pair inside the table is still a point that does not increase.
  EXPECT_EQ(read_error(folder, "*MAT_024\n" + row({"5", "2.7e-9", "70000", "0.33"}) + row({}) +
                                   row({"0.0", "0.1", "0.0", "0.5"}) + row({"200", "260", "0.0", "300"})),
            prefix(folder, 4, "*MAT_024") + "field EPS3: 0 does not increase (the previous point is at 0.1)");
}

// OFHC copper (validation.md §1(b)) in kg-m-s with the Johnson & Cook 1985 damage constants
// D1..D5 = 0.54 4.89 -3.03 0.014 1.12 [memory].
TEST(keyword_materials, JohnsonCookFields) {
  DeckFolder folder;
  const auto model = read_text(
      folder, "*MAT_JOHNSON_COOK\n" + row({"7", "8960", "46.3e9", "124e9", "0.34", "0", "0", "0"}) +
                  row({"90e6", "292e6", "0.31", "0.025", "1.09", "1356", "298", "1.0"}) +
                  row({"383", "-1.2e9", "3", "1", "0.54", "4.89", "-3.03", "0.014"}) +
                  row({"1.12", "0", "1", "0.01", "0"}) + "*MAT_015\n" +
                  row({"8", "8960", "46.3e9"}) + row({"90e6", "", "", "", "1.09", "1356", "298"}) +
                  row({"383", "-1.2e9"}));
  const auto& given = std::get<model::MatJohnsonCook>(model.materials.at(7).params);
  EXPECT_EQ(given.ro, 8960.0);
  EXPECT_EQ(given.g, 46.3e9);
  EXPECT_EQ(given.e, 124e9);
  EXPECT_EQ(given.pr, 0.34);
  EXPECT_EQ(given.a, 90e6);
  EXPECT_EQ(given.b, 292e6);
  EXPECT_EQ(given.n, 0.31);
  EXPECT_EQ(given.c, 0.025);
  EXPECT_EQ(given.m, 1.09);
  EXPECT_EQ(given.tm, 1356.0);
  EXPECT_EQ(given.tr, 298.0);
  EXPECT_EQ(given.epso, 1.0);
  EXPECT_EQ(given.cp, 383.0);
  EXPECT_EQ(given.pc, -1.2e9);
  EXPECT_EQ(given.spall, 3);
  EXPECT_EQ(given.it, 1);
  EXPECT_EQ(given.d1, 0.54);
  EXPECT_EQ(given.d2, 4.89);
  EXPECT_EQ(given.d3, -3.03);
  EXPECT_EQ(given.d4, 0.014);
  EXPECT_EQ(given.d5, 1.12);
  EXPECT_EQ(given.erod, 1.0);
  EXPECT_EQ(given.efmin, 0.01);
  // Blank SPALL: 2; blank card 4: D5 0, EFMIN 1e-6; VP and RATEOP 0.
  const auto& defaults = std::get<model::MatJohnsonCook>(model.materials.at(8).params);
  EXPECT_EQ(model.materials.at(8).keyword, "*MAT_JOHNSON_COOK");
  EXPECT_EQ(defaults.e, 0.0);
  EXPECT_EQ(defaults.b, 0.0);
  EXPECT_EQ(defaults.c, 0.0);
  EXPECT_EQ(defaults.epso, 0.0);
  EXPECT_EQ(defaults.spall, 2);
  EXPECT_EQ(defaults.it, 0);
  EXPECT_EQ(defaults.d1, 0.0);
  EXPECT_EQ(defaults.d5, 0.0);
  EXPECT_EQ(defaults.efmin, 1.0e-6);
  EXPECT_EQ(defaults.vp, 0);
  EXPECT_EQ(defaults.rateop, 0);
}

TEST(keyword_materials, JohnsonCookRefusesOtherRateFormsAndAZeroSpallStrength) {
  DeckFolder folder;
  const std::string cards23 =
      row({"90e6", "292e6", "0.31", "0.025", "1.09", "1356", "298", "1.0"}) +
      row({"383", "-1.2e9"});
  EXPECT_EQ(read_error(folder, "*MAT_JOHNSON_COOK\n" +
                                   row({"7", "8960", "46.3e9", "", "", "", "", "3"}) + cards23),
            prefix(folder, 2, "*MAT_JOHNSON_COOK") +
                "field RATEOP: 3: only 0 (log-linear Johnson-Cook rate term) is implemented");
  EXPECT_EQ(
      read_error(folder, "*MAT_JOHNSON_COOK\n" + row({"7", "8960", "46.3e9"}) +
                             row({"90e6", "292e6", "0.31", "0.025", "1.09", "1356", "298", "1.0"}) +
                             row({"383"})),
      prefix(folder, 4, "*MAT_JOHNSON_COOK") +
          "field PC: 0 with SPALL 2 would spall at any tension; give PC < 0 (the spall "
          "strength)");
  // One keyword, one material: a line after card 4 is refused, not dropped.
  EXPECT_EQ(read_error(folder, "*MAT_JOHNSON_COOK\n" + row({"7", "8960", "46.3e9"}) + cards23 + row({"0"}) +
                                   row({"8", "8960", "46.3e9"})),
            prefix(folder, 6, "*MAT_JOHNSON_COOK") +
                "unexpected data line after card 4; one *MAT_JOHNSON_COOK defines one material");
}

TEST(keyword_materials, NullFields) {
  DeckFolder folder;
  const auto model = read_text(
      folder, "*MAT_NULL\n" + row({"6", "1.0e-9", "-0.1", "8.9e-10", "", "", "2000", "0.3"}) +
                  "*MAT_009_TITLE\nwater\n" + row({"9", "1.0e-9"}));
  const auto& given = std::get<model::MatNull>(model.materials.at(6).params);
  EXPECT_EQ(given.ro, 1.0e-9);
  EXPECT_EQ(given.pc, -0.1);
  EXPECT_EQ(given.mu, 8.9e-10);
  EXPECT_EQ(given.terod, 0.0);
  EXPECT_EQ(given.cerod, 0.0);
  EXPECT_EQ(given.ym, 2000.0);
  EXPECT_EQ(given.pr, 0.3);
  const auto& defaults = std::get<model::MatNull>(model.materials.at(9).params);
  EXPECT_EQ(model.materials.at(9).keyword, "*MAT_NULL");
  EXPECT_EQ(defaults.pc, 0.0);
  EXPECT_EQ(defaults.mu, 0.0);
  EXPECT_EQ(defaults.ym, 0.0);
}

TEST(keyword_materials, NullRefusesErosion) {
  DeckFolder folder;
  EXPECT_EQ(
      read_error(folder, "*MAT_NULL\n" + row({"6", "1.0e-9", "0", "0", "1.5"})),
      prefix(folder, 2, "*MAT_NULL") +
          "field TEROD: erosion by relative volume is not implemented; leave TEROD and CEROD 0");
}

TEST(keyword_materials, EquationOfStateFields) {
  DeckFolder folder;
  const auto model = read_text(
      folder, "*EOS_LINEAR_POLYNOMIAL\n" +
                  row({"1", "0.1", "1.7e5", "3.1e5", "4.0e5", "0.5", "0.6", "0.7"}) +
                  row({"2.5", "1.0"}) + "*EOS_LINEAR_POLYNOMIAL_TITLE\nbulk only\n" +
                  row({"2", "", "1.7e5"}) + "*EOS_GRUNEISEN\n" +
                  row({"3", "3940", "1.49", "0.1", "0.2", "2.02", "0.47", "1.0e5"}) + row({"1.0"}) +
                  "*EOS_GRUNEISEN\n" + row({"4", "1483000", "1.75", "", "", "0.28"}) +
                  "*EOS_MURNAGHAN\n" + row({"5", "7.0", "3.2e8", "0"}));
  const auto& polynomial = std::get<model::EosLinearPolynomial>(model.eos.at(1).params);
  EXPECT_EQ(model.eos.at(1).keyword, "*EOS_LINEAR_POLYNOMIAL");
  EXPECT_EQ(model.eos.at(1).where.line, 2);
  EXPECT_EQ(polynomial.c, (std::array<Real, 7>{0.1, 1.7e5, 3.1e5, 4.0e5, 0.5, 0.6, 0.7}));
  EXPECT_EQ(polynomial.e0, 2.5);
  EXPECT_EQ(polynomial.v0, 1.0);
  const auto& bulk = std::get<model::EosLinearPolynomial>(model.eos.at(2).params);
  EXPECT_EQ(bulk.c, (std::array<Real, 7>{0, 1.7e5, 0, 0, 0, 0, 0}));
  EXPECT_EQ(bulk.e0, 0.0);
  EXPECT_EQ(bulk.v0, 1.0);  // no card 2
  const auto& copper = std::get<model::EosGruneisen>(model.eos.at(3).params);
  EXPECT_EQ(copper.c, 3940.0);
  EXPECT_EQ(copper.s1, 1.49);
  EXPECT_EQ(copper.s2, 0.1);
  EXPECT_EQ(copper.s3, 0.2);
  EXPECT_EQ(copper.gamma0, 2.02);
  EXPECT_EQ(copper.a, 0.47);
  EXPECT_EQ(copper.e0, 1.0e5);
  EXPECT_EQ(copper.v0, 1.0);
  EXPECT_EQ(copper.lcid, 0);
  const auto& water = std::get<model::EosGruneisen>(model.eos.at(4).params);
  EXPECT_EQ(water.s2, 0.0);
  EXPECT_EQ(water.a, 0.0);
  EXPECT_EQ(water.e0, 0.0);
  const auto& tait = std::get<model::EosMurnaghan>(model.eos.at(5).params);
  EXPECT_EQ(model.eos.at(5).keyword, "*EOS_MURNAGHAN");
  EXPECT_EQ(tait.gamma, 7.0);
  EXPECT_EQ(tait.k0, 3.2e8);
  EXPECT_EQ(tait.v0, 1.0);  // 0 -> 1
}

TEST(keyword_materials, EquationOfStateErrors) {
  DeckFolder folder;
  EXPECT_EQ(
      read_error(folder, "*EOS_LINEAR_POLYNOMIAL\n" + row({"1", "0", "1.7e5"}) + row({"0", "0.9"})),
      prefix(folder, 3, "*EOS_LINEAR_POLYNOMIAL") +
          "field V0: 0.9: an initial relative volume other than 1 is not implemented");
  EXPECT_EQ(
      read_error(folder, "*EOS_GRUNEISEN\n" + row({"4", "1483000", "1.75"}) + row({"0", "", "3"})),
      prefix(folder, 3, "*EOS_GRUNEISEN") +
          "field LCID: an energy deposition curve is not implemented; leave LCID 0");
  EXPECT_EQ(read_error(folder, "*EOS_MURNAGHAN\n" + row({"5", "7.0", "-3.2e8"})),
            prefix(folder, 2, "*EOS_MURNAGHAN") + "field K0: -3.2e+08 must be positive");
  // One keyword, one equation of state: a further data line is refused, not read as a second.
  EXPECT_EQ(read_error(folder, "*EOS_MURNAGHAN\n" + row({"5", "7.0", "3.2e8"}) + "\n" + row({"6", "7.0", "3.2e8"})),
            prefix(folder, 4, "*EOS_MURNAGHAN") +
                "unexpected data line after card 1; one *EOS_MURNAGHAN defines one equation of state");
  EXPECT_EQ(read_error(folder, "*EOS_MURNAGHAN\n" + row({"5", "7.0", "3.2e8"}) +
                                   "*EOS_GRUNEISEN\n" + row({"5", "1483000"})),
            prefix(folder, 4, "*EOS_GRUNEISEN") +
                "equation of state 5 is defined twice (first at " +
                (folder.path() / "bad.k").lexically_normal().string() + ":2)");
}

// validate(): a part's EOSID must name an EOS; MAT_NULL, and MAT_015 without E, need one; LCSS
// must name a *DEFINE_CURVE.
TEST(keyword_materials, ValidateEquationOfStateAndCurveReferences) {
  DeckFolder folder;
  const std::string base = "*CONTROL_TERMINATION\n" + row({"1.0"}) + "*SECTION_SPH\n" + row({"1"}) +
                           "*MAT_NULL\n" + row({"1", "1.0e-9"}) + "*MAT_JOHNSON_COOK\n" +
                           row({"2", "8960", "46.3e9"}) +
                           row({"90e6", "292e6", "0.31", "0", "1.09", "1356", "298"}) +
                           row({"383", "-1.2e9"}) + "*EOS_GRUNEISEN\n" + row({"3", "1483000"});
  // Lines 1-12 are `base`; the *PART card under test is on line 15.
  const std::string file = (folder.path() / "bad.k").lexically_normal().string();
  EXPECT_EQ(validate_error(folder, base + "*PART\nwater\n" + row({"1", "1", "1", "4"})),
            prefix(folder, 15, "*PART") + "part 1: equation of state 4 is not defined");
  EXPECT_EQ(
      validate_error(folder, base + "*PART\nwater\n" + row({"1", "1", "1"})),
      prefix(folder, 15, "*PART") + "part 1: material 1 (" + file +
          ":6) needs an equation of state, but EOSID is 0: *MAT_NULL has no pressure of its own");
  EXPECT_EQ(validate_error(folder, base + "*PART\ncopper\n" + row({"1", "1", "2"})),
            prefix(folder, 15, "*PART") + "part 1: material 2 (" + file +
                ":8) needs an equation of state, but EOSID is 0: *MAT_JOHNSON_COOK with E = 0 has "
                "no bulk modulus");
  EXPECT_EQ(validate_error(folder, base + "*PART\nwater\n" + row({"1", "1", "1", "3"})), "");
  const std::string piecewise = "*MAT_PIECEWISE_LINEAR_PLASTICITY\n" +
                                row({"4", "2.7e-9", "70000", "0.33"}) + row({"", "", "7"});
  EXPECT_EQ(
      validate_error(folder, base + piecewise),
      prefix(folder, 14, "*MAT_PIECEWISE_LINEAR_PLASTICITY") + "LCSS: curve 7 is not defined");
  EXPECT_EQ(validate_error(folder, base + piecewise + "*DEFINE_TABLE\n" + row({"7"}) +
                                       row({"100.0", "8"}, {20, 20})),
            prefix(folder, 14, "*MAT_PIECEWISE_LINEAR_PLASTICITY") +
                "LCSS: 7 is a *DEFINE_TABLE (" + file +
                ":16); tables of curves by strain rate are not read, give a *DEFINE_CURVE "
                "of yield stress versus plastic strain");
}

}  // namespace
}  // namespace spall::io::keyword
