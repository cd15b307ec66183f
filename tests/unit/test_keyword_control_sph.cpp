// *CONTROL_SPH and Spall's SPH keywords (*SPALL_SPH_ARTIFICIAL_STRESS, *SPALL_SPH_COLOUR_FIELD,
// *SPALL_SPH_TIMESTEP, *SPALL_RESIDUAL_STRESS): every field lands where it should, blank fields
// take LS-DYNA's defaults (FORM: Spall's renormalized default), and options Spall does not run
// stop at their card with the field named.
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

TEST(control_sph, ReadsEveryFieldOfTheThreeCards) {
  DeckFolder folder;
  const auto model = read_deck(folder.write(
      "sph.k", "*KEYWORD\n*CONTROL_SPH\n" +
                   row({"5", "0", "2.5e-3", "2", "90", "0", "1e-4", "1e18"}) +
                   row({"0", "0", "0", "1", "0", "0", "0", "80"}) +
                   row({"0", "0", "0.02", "", "0", "0"}) + "*END\n"));
  ASSERT_TRUE(model.control_sph);
  const auto& c = *model.control_sph;
  EXPECT_EQ(c.ncbs, 5);
  EXPECT_EQ(c.dt, 2.5e-3);
  EXPECT_EQ(c.idim, 2);
  EXPECT_EQ(c.nmneigh, 90);
  EXPECT_EQ(c.form, 0);  // written explicitly: plain SPH
  EXPECT_EQ(c.start, 1e-4);
  EXPECT_EQ(c.maxv, 1e18);
  EXPECT_EQ(c.ishow, 1);
  EXPECT_EQ(c.isymp, 80);
  EXPECT_EQ(c.ql, 0.02);
  EXPECT_EQ(c.card_where[2].line, 5);
}

TEST(control_sph, BlankFieldsTakeTheDefaults) {
  DeckFolder folder;
  const auto model = read_deck(folder.write("sph.k", "*KEYWORD\n*CONTROL_SPH\n\n*END\n"));
  ASSERT_TRUE(model.control_sph);
  const auto& c = *model.control_sph;
  EXPECT_EQ(c.ncbs, 1);
  EXPECT_EQ(c.dt, 1e20);
  EXPECT_EQ(c.idim, 3);
  EXPECT_EQ(c.form, 1);  // Spall's default: renormalized (docs/KEYWORDS.md says why)
  EXPECT_EQ(c.maxv, 1e15);
  EXPECT_EQ(c.isymp, 100);
}

TEST(control_sph, BadIdimNamesTheField) {
  DeckFolder folder;
  const auto path = folder.write("sph.k", "*KEYWORD\n*CONTROL_SPH\n" + row({"1", "0", "0", "5"}) + "*END\n");
  const std::string message = input_error_of([&] { read_deck(path); });
  EXPECT_NE(message.find("sph.k:3: *CONTROL_SPH: field IDIM"), std::string::npos) << "got: " << message;
}

TEST(control_sph, ArtificialStressKeywordAloneSwitchesItOnWithGrayMonaghanSwiftDefaults) {
  DeckFolder folder;
  const auto model = read_deck(folder.write("s.k", "*KEYWORD\n*SPALL_SPH_ARTIFICIAL_STRESS\n*END\n"));
  ASSERT_TRUE(model.sph_artificial_stress);
  EXPECT_EQ(model.sph_artificial_stress->epsilon, 0.3);  // Gray, Monaghan & Swift 2001
  EXPECT_EQ(model.sph_artificial_stress->exponent, 4.0);
  const auto model2 = read_deck(folder.write(
      "s2.k", "*KEYWORD\n*SPALL_SPH_ARTIFICIAL_STRESS\n" + row({"0.2", "3"}) + "*END\n"));
  EXPECT_EQ(model2.sph_artificial_stress->epsilon, 0.2);
  EXPECT_EQ(model2.sph_artificial_stress->exponent, 3.0);
}

// An option the solver does not implement stops the run at its card, naming the field.
TEST(control_sph, UnimplementedOptionsStopAtTheirCard) {
  struct Case {
    std::string cards;
    std::string expected;
  };
  const Case cases[] = {
      {row({"1", "0", "0", "3", "150", "13"}), ":3: *CONTROL_SPH: FORM 13"},
      {row({"1", "0", "0", "-2"}), ":3: *CONTROL_SPH: IDIM -2"},
      {row({"1", "7"}), ":3: *CONTROL_SPH: BOXID 7"},
      {row({"1"}) + row({"0", "0", "0", "0", "1"}), ":4: *CONTROL_SPH: IEROD 1"},
      {row({"1"}) + row({}) + row({"0", "0", "0", "", "0", "1"}), ":5: *CONTROL_SPH: ISHIFT 1"},
  };
  for (const auto& c : cases) {
    DeckFolder folder;
    const auto model = read_deck(folder.write("sph.k", "*KEYWORD\n*CONTROL_SPH\n" + c.cards + "*END\n"));
    model::Model block = test_support::elastic_block_model({Vec3(0.1, 0.1, 0.1), 0.025});
    block.control_sph = model.control_sph;
    const std::string message = input_error_of([&] { solver::build_problem(block); });
    EXPECT_NE(message.find(c.expected), std::string::npos) << message;
  }
}

// ANSYS Workbench writes *CONTROL_BULK_VISCOSITY TYPE -1 or -2: the standard viscosity, also on
// shells (manual); on SPH particles they are TYPE 1. TYPE 2 (Richards-Wilkins) is refused.
TEST(control_sph, BulkViscosityTypesMinusOneAndMinusTwoAreTheStandardOne) {
  for (const int type : {1, -1, -2}) {
    model::Model block = test_support::elastic_block_model({Vec3(0.1, 0.1, 0.1), 0.025});
    block.bulk_viscosity.type = type;
    EXPECT_NO_THROW(solver::build_problem(block)) << "TYPE " << type;
  }
  model::Model block = test_support::elastic_block_model({Vec3(0.1, 0.1, 0.1), 0.025});
  block.bulk_viscosity.type = 2;
  const std::string message = input_error_of([&] { solver::build_problem(block); });
  EXPECT_NE(message.find("*CONTROL_BULK_VISCOSITY: TYPE 2 (Richards-Wilkins)"), std::string::npos) << message;
}

// The solid's pair terms are single precision: a smoothing length whose h^-5 or h^4 leaves float's
// range is refused at its *SECTION_SPH, with the way out named.
TEST(section_sph, SmoothingLengthOutsideSinglePrecisionRangeIsRefused) {
  for (const Real sphini : {1e-7, 1e7}) {
    model::Model block = test_support::elastic_block_model({Vec3(0.1, 0.1, 0.1), 0.025});
    std::get<model::SectionSph>(block.sections.at(1)).sphini = sphini;
    const std::string message = input_error_of([&] { solver::build_problem(block); });
    EXPECT_NE(message.find("*SECTION_SPH: smoothing length"), std::string::npos) << message;
    EXPECT_NE(message.find("use units"), std::string::npos) << message;
  }
  model::Model fine = test_support::elastic_block_model({Vec3(0.1, 0.1, 0.1), 0.025});
  std::get<model::SectionSph>(fine.sections.at(1)).sphini = 2e-6;  // inside: builds
  EXPECT_NO_THROW(solver::build_problem(fine));
}

TEST(spall_sph_keywords, ColourFieldCardsPerPartWithDefaults) {
  DeckFolder folder;
  const auto model = read_deck(folder.write(
      "c.k", "*KEYWORD\n*SPALL_SPH_COLOUR_FIELD\n" + row({"0"}) + row({"3", "1", "0.7", "0.25", "2", "5", "2", "7.5"}) + "*END\n"));
  ASSERT_EQ(model.sph_colour_fields.size(), 2u);
  const auto& all = model.sph_colour_fields[0];
  EXPECT_EQ(all.pid, 0);
  EXPECT_EQ(all.treat, 0);
  EXPECT_EQ(all.neighbour_fraction, 0.8);  // calibrated defaults (tests/unit/test_sph_colour_field.cpp)
  EXPECT_EQ(all.normal_threshold, 0.3);
  EXPECT_EQ(all.layers, 1);
  EXPECT_EQ(all.interval, 1);
  EXPECT_EQ(all.form, 1);  // the relaxed treatment (docs/VALIDATION.md: the literal one is unstable)
  EXPECT_EQ(all.relaxation, 100.0);
  const auto& three = model.sph_colour_fields[1];
  EXPECT_EQ(three.pid, 3);
  EXPECT_EQ(three.treat, 1);
  EXPECT_EQ(three.neighbour_fraction, 0.7);
  EXPECT_EQ(three.normal_threshold, 0.25);
  EXPECT_EQ(three.layers, 2);
  EXPECT_EQ(three.interval, 5);
  EXPECT_EQ(three.form, 2);
  EXPECT_EQ(three.relaxation, 7.5);
}

TEST(spall_sph_keywords, ColourFieldBadInputNamesTheField) {
  DeckFolder folder;
  const auto bad_treat = folder.write("t.k", "*KEYWORD\n*SPALL_SPH_COLOUR_FIELD\n" + row({"0", "2"}) + "*END\n");
  EXPECT_NE(input_error_of([&] { read_deck(bad_treat); }).find("t.k:3: *SPALL_SPH_COLOUR_FIELD: field TREAT"),
            std::string::npos);
  const auto bad_form = folder.write("f.k", "*KEYWORD\n*SPALL_SPH_COLOUR_FIELD\n" + row({"0", "1", "", "", "", "", "3"}) + "*END\n");
  EXPECT_NE(input_error_of([&] { read_deck(bad_form); }).find("f.k:3: *SPALL_SPH_COLOUR_FIELD: field TFORM"),
            std::string::npos);
  const auto bad_tau = folder.write("u.k", "*KEYWORD\n*SPALL_SPH_COLOUR_FIELD\n" + row({"0", "1", "", "", "", "", "1", "-1"}) + "*END\n");
  EXPECT_NE(input_error_of([&] { read_deck(bad_tau); }).find("u.k:3: *SPALL_SPH_COLOUR_FIELD: field TAU"),
            std::string::npos);
  const auto twice = folder.write("d.k", "*KEYWORD\n*SPALL_SPH_COLOUR_FIELD\n" + row({"4"}) + row({"4"}) + "*END\n");
  EXPECT_NE(input_error_of([&] { read_deck(twice); }).find("d.k:4: *SPALL_SPH_COLOUR_FIELD: field PID"),
            std::string::npos);
  // A card for a part without SPH particles stops the run at the card.
  model::Model block = test_support::elastic_block_model({Vec3(0.1, 0.1, 0.1), 0.025});
  model::SphColourField colour;
  colour.pid = 9;
  colour.where = {"deck.k", 7};
  block.sph_colour_fields.push_back(colour);
  const std::string message = input_error_of([&] { solver::build_problem(block); });
  EXPECT_NE(message.find("deck.k:7: *SPALL_SPH_COLOUR_FIELD: PID: part 9 has no SPH particles"), std::string::npos)
      << message;
}

TEST(spall_sph_keywords, TimestepRule) {
  DeckFolder folder;
  const auto plain = read_deck(folder.write("p.k", "*KEYWORD\n*SPALL_SPH_TIMESTEP\n" + row({"1"}) + "*END\n"));
  ASSERT_TRUE(plain.sph_timestep);
  EXPECT_EQ(plain.sph_timestep->rule, 1);
  const auto blank = read_deck(folder.write("b.k", "*KEYWORD\n*SPALL_SPH_TIMESTEP\n" + row({""}) + "*END\n"));
  EXPECT_EQ(blank.sph_timestep->rule, 0);  // the correction-aware step
  const auto bad = folder.write("r.k", "*KEYWORD\n*SPALL_SPH_TIMESTEP\n" + row({"2"}) + "*END\n");
  EXPECT_NE(input_error_of([&] { read_deck(bad); }).find("r.k:3: *SPALL_SPH_TIMESTEP: field RULE"), std::string::npos);
  const auto twice = folder.write("t.k", "*KEYWORD\n*SPALL_SPH_TIMESTEP\n" + row({"1"}) + "*SPALL_SPH_TIMESTEP\n" + row({"0"}) + "*END\n");
  EXPECT_NE(input_error_of([&] { read_deck(twice); }).find("t.k:4: *SPALL_SPH_TIMESTEP"), std::string::npos);
  // Without SPH solid particles the rule would set nothing: refused at its card.
  model::Model empty;
  empty.sph_timestep = model::SphTimestep{1, {"deck.k", 5}};
  const std::string message = input_error_of([&] { solver::build_problem(empty); });
  EXPECT_NE(message.find("deck.k:5: *SPALL_SPH_TIMESTEP: RULE"), std::string::npos) << message;
}

TEST(spall_sph_keywords, ResidualStressCard) {
  DeckFolder folder;
  const auto model = read_deck(folder.write("r.k", "*KEYWORD\n*SPALL_RESIDUAL_STRESS\n" + row({"0.3", "1e-2", "1"}) + "*END\n"));
  ASSERT_TRUE(model.sph_residual_stress);
  EXPECT_EQ(model.sph_residual_stress->yield_fraction, 0.3);
  EXPECT_EQ(model.sph_residual_stress->strain_rate, 1e-2);
  EXPECT_EQ(model.sph_residual_stress->at_output, 1);
  const auto defaults = read_deck(folder.write("r2.k", "*KEYWORD\n*SPALL_RESIDUAL_STRESS\n*END\n"));
  EXPECT_EQ(defaults.sph_residual_stress->yield_fraction, 0.5);
  EXPECT_EQ(defaults.sph_residual_stress->strain_rate, 0.0);
  const auto bad = folder.write("r3.k", "*KEYWORD\n*SPALL_RESIDUAL_STRESS\n" + row({"0.5", "-1"}) + "*END\n");
  EXPECT_NE(input_error_of([&] { read_deck(bad); }).find("r3.k:3: *SPALL_RESIDUAL_STRESS: field RATE"),
            std::string::npos);
}

}  // namespace
}  // namespace spall::io::keyword
