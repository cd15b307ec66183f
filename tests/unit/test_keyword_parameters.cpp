// *PARAMETER scoping across *INCLUDE files, on pydyna's expand_parameters decks
// (shared/decks/public/pydyna_expand_parameters/, behaviour as their README section states).
#include <gtest/gtest.h>

#include <filesystem>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"

namespace spall::io::keyword {
namespace {

const std::filesystem::path decks =
    std::filesystem::path(SPALL_SHARED_DIR) / "decks" / "public" / "pydyna_expand_parameters";

// The public decks live in shared/ beside the checkout, which a user's clone does not have: the
// tests skip, saying so, when it is absent.
class keyword_parameters : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::is_directory(decks))
      GTEST_SKIP() << decks.string() << " is absent (a clone without ../shared): skipped";
  }
};

int elform(const model::Model& model, Id secid) {
  return std::get<model::SectionSolid>(model.sections.at(secid)).elform;
}

TEST_F(keyword_parameters, CollisionLastGlobalDefinitionWins) {
  const auto model = read_deck(decks / "collision" / "main.k");
  EXPECT_EQ(elform(model, 100), 1);  // module A, read while Rscale = 1.0
  EXPECT_EQ(elform(model, 200), 2);  // module B redefined it to 2.0
  const auto consumer = read_deck(decks / "collision" / "main_with_consumer.k");
  EXPECT_EQ(elform(consumer, 300), 2);  // module C sees the last value
}

TEST_F(keyword_parameters, CollisionLocalIsolatesModules) {
  const auto model = read_deck(decks / "collision_local" / "main.k");
  EXPECT_EQ(elform(model, 100), 1);
  EXPECT_EQ(elform(model, 200), 2);
}

TEST_F(keyword_parameters, LocalIsNotVisibleToTheIncludingFile) {
  const std::string message =
      test::input_error_of([] { read_deck(decks / "local" / "top.k"); });
  // Sections 10, 20 (local 999) and 30 (global) read; section 40 in top.k uses the include's local.
  EXPECT_NE(message.find("top.k:15: *SECTION_SOLID_TITLE: field ELFORM: parameter 'loc' is not defined"),
            std::string::npos)
      << message;
}

TEST_F(keyword_parameters, LocalIsNotVisibleToASiblingButGlobalsAre) {
  const std::string message =
      test::input_error_of([] { read_deck(decks / "local" / "sibling_test_top.k"); });
  EXPECT_NE(message.find("sibling_b.k:6: *SECTION_SOLID_TITLE: field ELFORM: parameter 'aloc'"),
            std::string::npos)
      << message;
}

TEST_F(keyword_parameters, LocalAndGlobalValuesInsideTheInclude) {
  // The same include, read from a parent that defines the global but does not misuse the local.
  test::DeckFolder folder;
  std::filesystem::copy_file(decks / "local" / "include_with_local.k",
                             folder.path() / "include_with_local.k");
  const auto model = read_deck(folder.write("top.k", "*KEYWORD\n*PARAMETER\nRgbl          200.0\n"
                                                     "*INCLUDE\ninclude_with_local.k\n*END\n"));
  EXPECT_EQ(elform(model, 20), 999);
  EXPECT_EQ(elform(model, 30), 200);
}

TEST_F(keyword_parameters, NonlocalGlobalReachesTwoIncludeLevelsDown) {
  const auto model = read_deck(decks / "nonlocal" / "top.k");
  EXPECT_EQ(elform(model, 10), 100);
  EXPECT_EQ(elform(model, 20), 1);
  EXPECT_EQ(elform(model, 30), 100);
}

TEST_F(keyword_parameters, SiblingIncludeSeesParametersOfAnEarlierOne) {
  const auto model = read_deck(decks / "sibling" / "main.k");
  ASSERT_TRUE(model.sections.contains(1234));
  EXPECT_EQ(elform(model, 1234), 5678);
}

TEST_F(keyword_parameters, LocalParameterShadowsGlobalInItsFileOnly) {
  test::DeckFolder folder;
  folder.write("inner.k", "*PARAMETER_LOCAL\nIform     2\n*SECTION_SOLID\n         2     &form\n");
  const auto model = read_deck(
      folder.write("outer.k", "*PARAMETER\nIform     1\n*INCLUDE\ninner.k\n"
                              "*SECTION_SOLID\n         1     &form\n"));
  EXPECT_EQ(elform(model, 2), 2);
  EXPECT_EQ(elform(model, 1), 1);
}

}  // namespace
}  // namespace spall::io::keyword
