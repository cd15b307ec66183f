// *SECTION_SOLID_SPG (keywords.md §4, spg.md §3-4): both card layouts, the public card texts, the
// KERNEL-dependent defaults of the manual (DX 1.6 / 1.8 / 1.5, SMSTEP 15 / 5 / 30, ITB 1 / 1 / 2),
// and field errors naming the field.
#include <gtest/gtest.h>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"

namespace spall::io::keyword {
namespace {

using test::DeckFolder;
using test::input_error_of;
using test::row;

const model::SectionSolidSpg& spg_section(const model::Model& m, Id id) {
  return std::get<model::SectionSolidSpg>(m.sections.at(id));
}

// Seed 001 Fig. 2, the R9-R11 layout: card 2 ends LSCALE SMSTEP SWTIME, card 3 IDAM FS STRETCH ITB.
TEST(keyword_spg, Seed001Figure2OldLayout) {
  DeckFolder folder;
  const auto path = folder.write(
      "seed.k", "*SECTION_SOLID_SPG\n" + row({"1", "47", "0"}) +
                    row({"1.5", "1.5", "1.5", "0", "1", "0.0", "5", "0.0"}) +
                    row({"1", "0.45", "1.25", "1"}) + "*END\n");
  const model::Model m = read_deck(path);
  const auto& s = spg_section(m, 1);
  EXPECT_EQ(s.elform, 47);
  EXPECT_EQ(s.aet, 0);
  EXPECT_EQ(s.dx, 1.5);
  EXPECT_EQ(s.dy, 1.5);
  EXPECT_EQ(s.dz, 1.5);
  EXPECT_EQ(s.ispline, 0);
  EXPECT_EQ(s.kernel, 1);
  EXPECT_EQ(s.lscale, 0.0);
  EXPECT_EQ(s.smstep, 5);
  EXPECT_EQ(s.column8, 0.0);
  EXPECT_EQ(s.idam, 1);
  EXPECT_EQ(s.fs, 0.45);
  EXPECT_EQ(s.stretch, 1.25);
  EXPECT_EQ(s.itb, 1);
  // Fields the old layout does not have take the current manual's defaults.
  EXPECT_EQ(s.msfac, 0.0);
  EXPECT_EQ(s.isc, 0);
  EXPECT_EQ(s.boxid, 0);
  EXPECT_EQ(s.pdamp, -0.001);
  EXPECT_EQ(s.where.line, 2);
  EXPECT_EQ(s.where_card2.line, 3);
  EXPECT_EQ(s.where_card3.line, 4);
}

// The current layout with every field, as written by a public deck tool (spg.md §4), and the
// comma-separated form of the GlukRazor metal-cutting card, with a title.
TEST(keyword_spg, CurrentLayoutAndFreeFormat) {
  DeckFolder folder;
  const auto path = folder.write(
      "new.k", "*SECTION_SOLID_SPG\n" + row({"2", "47", "0", "", "", "", "0.0", "0.0"}) +
                   row({"1.8", "1.7", "1.6", "2", "1", "", "5", "1.0"}) +
                   row({"5", "0.02", "1.2", "3", "0.75", "1", "4", "-0.005"}) +
                   "*SECTION_SOLID_SPG_TITLE\ncutting demo\n1,47,0\n1.5,1.5,1.5,0,1,0.0,10,0.0\n1,0.3,1.1,1\n");
  const model::Model m = read_deck(path);
  const auto& s = spg_section(m, 2);
  EXPECT_EQ(s.dx, 1.8);
  EXPECT_EQ(s.dy, 1.7);
  EXPECT_EQ(s.dz, 1.6);
  EXPECT_EQ(s.ispline, 2);
  EXPECT_EQ(s.kernel, 1);
  EXPECT_EQ(s.smstep, 5);
  EXPECT_EQ(s.column8, 1.0);  // MSC with ITB 3
  EXPECT_EQ(s.idam, 5);
  EXPECT_EQ(s.fs, 0.02);
  EXPECT_EQ(s.stretch, 1.2);
  EXPECT_EQ(s.itb, 3);
  EXPECT_EQ(s.msfac, 0.75);
  EXPECT_EQ(s.isc, 1);
  EXPECT_EQ(s.boxid, 4);
  EXPECT_EQ(s.pdamp, -0.005);
  const auto& g = spg_section(m, 1);
  EXPECT_EQ(g.dx, 1.5);
  EXPECT_EQ(g.kernel, 1);
  EXPECT_EQ(g.smstep, 10);
  EXPECT_EQ(g.fs, 0.3);
  EXPECT_EQ(g.stretch, 1.1);
  EXPECT_EQ(g.itb, 1);
}

// Blank (or zero) fields: the manual's defaults, DX DY DZ SMSTEP ITB by KERNEL (pydyna
// section_solid_spg.py docstrings); FS 1e10 (no failure), STRETCH 1 (Spall's reading of blank,
// docs/KEYWORDS.md), PDAMP -0.001. Two sections in one block.
TEST(keyword_spg, KernelDependentDefaults) {
  DeckFolder folder;
  std::string text = "*SECTION_SOLID_SPG\n";
  for (int kernel = 0; kernel < 3; ++kernel)
    text += row({std::to_string(10 + kernel), "47"}) + row({"", "", "", "", std::to_string(kernel)}) + row({});
  const model::Model m = read_deck(folder.write("defaults.k", text));
  const Real dilation[3] = {1.6, 1.8, 1.5};
  const int smstep[3] = {15, 5, 30};
  const int itb[3] = {1, 1, 2};
  for (int kernel = 0; kernel < 3; ++kernel) {
    const auto& s = spg_section(m, 10 + kernel);
    EXPECT_EQ(s.kernel, kernel);
    EXPECT_EQ(s.dx, dilation[kernel]);
    EXPECT_EQ(s.dy, dilation[kernel]);
    EXPECT_EQ(s.dz, dilation[kernel]);
    EXPECT_EQ(s.smstep, smstep[kernel]);
    EXPECT_EQ(s.itb, itb[kernel]);
    EXPECT_EQ(s.ispline, 0);
    EXPECT_EQ(s.idam, 1);
    EXPECT_EQ(s.fs, 1.0e10);
    EXPECT_EQ(s.stretch, 1.0);
    EXPECT_EQ(s.pdamp, -0.001);
  }
}

TEST(keyword_spg, BadFieldsNameTheFieldAndLine) {
  DeckFolder folder;
  const std::string card1 = row({"1", "47"});
  const std::string card2 = row({"1.6", "1.6", "1.6"});
  const std::string card3 = row({"1"});
  auto error = [&](const std::string& cards) {
    return input_error_of([&] { read_deck(folder.write("bad.k", "*SECTION_SOLID_SPG\n" + cards)); });
  };
  auto at = [&](int line) {
    return (folder.path() / "bad.k").lexically_normal().string() + ":" + std::to_string(line) +
           ": *SECTION_SOLID_SPG: ";
  };
  EXPECT_EQ(error(row({"1", "2"}) + card2 + card3),
            at(2) + "field ELFORM: '2': *SECTION_SOLID_SPG needs ELFORM 47 (SPG)");
  EXPECT_EQ(error(row({"1"}) + card2 + card3),
            at(2) + "field ELFORM: blank: *SECTION_SOLID_SPG needs ELFORM 47 (SPG)");
  EXPECT_EQ(error(card1 + row({"1.6", "0.9"}) + card3),
            at(3) + "field DY: '0.9' is below 1.0, which LS-DYNA does not allow (1.4 to 1.8 are recommended)");
  EXPECT_NE(error(card1 + row({"", "", "", "", "3"}) + card3).find(at(3) + "field KERNEL: '3'"), std::string::npos);
  EXPECT_NE(error(card1 + row({"", "", "", "4"}) + card3).find(at(3) + "field ISPLINE: '4'"), std::string::npos);
  EXPECT_NE(error(card1 + row({"", "", "", "", "", "", "-5"}) + card3).find(at(3) + "field SMSTEP"), std::string::npos);
  EXPECT_NE(error(card1 + card2 + row({"6"})).find(at(4) + "field IDAM: '6'"), std::string::npos);
  EXPECT_NE(error(card1 + card2 + row({"1", "", "", "4"})).find(at(4) + "field ITB: '4'"), std::string::npos);
  EXPECT_NE(error(card1 + card2 + row({"1", "", "-1.0"})).find(at(4) + "field STRETCH"), std::string::npos);
  EXPECT_NE(error(card1 + card2 + row({"1", "", "", "", "", "2"})).find(at(4) + "field ISC: '2'"), std::string::npos);
  EXPECT_EQ(error(card1 + card2), at(3) + "missing card 3 (IDAM FS STRETCH ITB ...)");
}

}  // namespace
}  // namespace spall::io::keyword
