// *DAMPING_GLOBAL: LCID VALDMP STX STY STZ SRX SRY SRZ (LS-DYNA manual: with all six scale
// factors 0, all default to 1).
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::row;

TEST(keyword_damping, FieldsAndDefaults) {
  DeckFolder folder;
  const auto m = read_deck(folder.write("d.k", "*DAMPING_GLOBAL\n" + row({"", "25.0"})));
  ASSERT_TRUE(m.damping_global.has_value());
  EXPECT_EQ(m.damping_global->lcid, 0);
  EXPECT_EQ(m.damping_global->valdmp, 25.0);
  EXPECT_EQ(m.damping_global->translation_scale, Vec3::Ones());
  EXPECT_EQ(m.damping_global->rotation_scale, Vec3::Ones());
  const auto g = read_deck(folder.write("g.k", "*DAMPING_GLOBAL\n" + row({"3", "0.0", "1.0", "0.5"})));
  EXPECT_EQ(g.damping_global->lcid, 3);
  EXPECT_EQ(g.damping_global->translation_scale, Vec3(1.0, 0.5, 0.0));
  EXPECT_EQ(g.damping_global->rotation_scale, Vec3::Zero());
}

TEST(keyword_damping, Errors) {
  DeckFolder folder;
  const auto path = folder.write("bad.k", "*DAMPING_GLOBAL\n" + row({"", "-1.0"}));
  EXPECT_NE(input_error_of([&] { read_deck(path); }).find("field VALDMP: '-1.0' is negative"), std::string::npos);
  const auto twice = folder.write("twice.k", "*DAMPING_GLOBAL\n" + row({"", "1.0"}) + "*DAMPING_GLOBAL\n" + row({"", "2.0"}));
  EXPECT_NE(input_error_of([&] { read_deck(twice); }), "");
}

}  // namespace
}  // namespace spall::io::keyword
