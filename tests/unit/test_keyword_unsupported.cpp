// Unsupported keywords (issue 33 item 4): one that defines physics (contacts, elements Spall does
// not have, constraints, loads, initial and boundary conditions, the analysis type) stops the check
// at its line unless the user skips it by name; output and tuning keywords stay warnings.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/io/keyword/unsupported.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::row;

TEST(keyword_unsupported, PhysicsKeywordsAreToldFromOutputAndTuning) {
  for (const char* physics : {"*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID", "*ELEMENT_SHELL", "*PART_INERTIA",
                              "*CONSTRAINED_RIGID_BODIES", "*BOUNDARY_SPC_SET_BIRTH_DEATH", "*LOAD_SEGMENT",
                              "*INITIAL_STRESS_SOLID", "*RIGIDWALL_GEOMETRIC_FLAT", "*CONTROL_IMPLICIT_GENERAL",
                              "*CASE", "*INCLUDE_TRANSFORM", "*DAMPING_PART_MASS", "*DEFINE_SPH_MESH_SURFACE",
                              "*DEFINE_SPH_INJECTION", "*DEFINE_ADAPTIVE_SOLID_TO_SPH",
                              "*MAT_ADD_THERMAL_EXPANSION", "*MAT_ADD_DAMAGE_GISSMO"})
    EXPECT_TRUE(defines_physics(physics)) << physics;
  for (const char* tuning : {"*DATABASE_BINARY_D3THDT", "*CONTROL_ENERGY", "*CONTROL_SOLID", "*TITLE",
                             "*DEFINE_BOX", "*SECTION_SHELL", "*MAT_SOIL_AND_FOAM", "*SET_SEGMENT", "*PARTITION",
                             "*CONTACTS", "*DEFINE_SPH_MASSFLOW_PLANE"})
    EXPECT_FALSE(defines_physics(tuning)) << tuning;
}

TEST(keyword_unsupported, SkipNamesAKeywordOrItsFamily) {
  EXPECT_TRUE(skip_matches("CONTACT", "*CONTACT_AUTOMATIC_SINGLE_SURFACE"));
  EXPECT_TRUE(skip_matches("*contact_automatic_single_surface", "*CONTACT_AUTOMATIC_SINGLE_SURFACE"));
  EXPECT_FALSE(skip_matches("CONTACT_AUTO", "*CONTACT_AUTOMATIC_SINGLE_SURFACE"));
  EXPECT_FALSE(skip_matches("ELEMENT", "*CONTACT_AUTOMATIC_SINGLE_SURFACE"));
}

TEST(keyword_unsupported, APhysicsKeywordStopsTheCheckAtItsLineUnlessSkipped) {
  DeckFolder folder;
  // A contact type Spall does not read (the four it reads are in test_keyword_contact).
  const auto path = folder.write("contact.k", "*KEYWORD\n*CONTROL_ENERGY\n" + row({"2"}) +
                                                  "*CONTACT_TIED_SURFACE_TO_SURFACE\n" + row({"1", "0", "2"}) +
                                                  row({"0.2"}) + row({}) + "*END\n");
  const model::Model model = read_deck(path);
  EXPECT_EQ(input_error_of([&] { refuse_unsupported_physics(model, {}); }),
            path.string() + ":4: *CONTACT_TIED_SURFACE_TO_SURFACE: not supported by Spall, and it defines physics: "
                            "running without it would solve another problem (`spall run --skip "
                            "CONTACT_TIED_SURFACE_TO_SURFACE` runs without it, knowingly)");
  EXPECT_EQ(input_error_of([&] { refuse_unsupported_physics(model, {"contact"}); }), "");
}

// A *MAT_ADD_ card that Spall does not read shares its material's ID, as the manual has it: it is not
// "material 1 defined twice" but an unsupported change to material 1, which stops the check unless
// skipped (*MAT_ADD_EROSION is read: test_keyword_add_erosion).
TEST(keyword_unsupported, AnUnreadMatAddCardStopsTheCheckAndIsNotASecondMaterial) {
  DeckFolder folder;
  const auto path = folder.write(
      "mat_add.k", "*KEYWORD\n*NODE\n" + row({"1", "0.", "0.", "0."}, {8, 16, 16, 16}) + "*PART\nblock\n" +
                       row({"1", "1", "1"}) + "*SECTION_SOLID\n" + row({"1", "1"}) + "*MAT_ELASTIC\n" +
                       row({"1", "7.85e-9", "2.1e5", "0.3"}) + "*MAT_ADD_THERMAL_EXPANSION\n" +
                       row({"1", "0", "1.2e-5"}) + "*CONTROL_TERMINATION\n" + row({"1.0e-5"}) + "*END\n");
  const model::Model model = read_deck(path);
  EXPECT_EQ(input_error_of([&] { refuse_unsupported_physics(model, {}); }),
            path.string() + ":11: *MAT_ADD_THERMAL_EXPANSION: not supported by Spall, and it defines physics: "
                            "running without it would solve another problem (`spall run --skip "
                            "MAT_ADD_THERMAL_EXPANSION` runs without it, knowingly)");
  EXPECT_EQ(input_error_of([&] { refuse_unsupported_physics(model, {"MAT_ADD_THERMAL_EXPANSION"}); }), "");
  EXPECT_EQ(input_error_of([&] { validate(model); }), "");
}

}  // namespace
}  // namespace spall::io::keyword
