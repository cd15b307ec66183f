// Field cutting and number reading: fixed columns (incl. run-together fields), free format,
// long format, Fortran numbers, blank defaults, integer fields, &parameters.
#include <gtest/gtest.h>

#include <array>

#include "spall/io/keyword/card.hpp"
#include "spall/io/keyword/numbers.hpp"

namespace spall::io::keyword {
namespace {

TEST(keyword_numbers, ReadsPlainAndFortranForms) {
  EXPECT_EQ(parse_real("1.5"), 1.5);
  EXPECT_EQ(parse_real("-2"), -2.0);
  EXPECT_EQ(parse_real("+3.25"), 3.25);
  EXPECT_EQ(parse_real(".5"), 0.5);
  EXPECT_EQ(parse_real("1."), 1.0);
  EXPECT_EQ(parse_real("1.5E+4"), 1.5e4);
  EXPECT_EQ(parse_real("1.0+4"), 1.0e4);   // Fortran: exponent without E
  EXPECT_EQ(parse_real("3.5-10"), 3.5e-10);
  EXPECT_EQ(parse_real("-3.5-10"), -3.5e-10);
  EXPECT_EQ(parse_real("1.0D4"), 1.0e4);   // double-precision exponent letter
  EXPECT_EQ(parse_real("1.0d-2"), 1.0e-2);
  EXPECT_EQ(parse_real("1.0D+4"), 1.0e4);
}

TEST(keyword_numbers, RejectsWhatIsNotANumber) {
  EXPECT_FALSE(parse_real("1.2.3"));
  EXPECT_FALSE(parse_real("abc"));
  EXPECT_FALSE(parse_real("inf"));
  EXPECT_FALSE(parse_real("nan"));
  EXPECT_FALSE(parse_real("1e"));
  EXPECT_FALSE(parse_real("-"));
  EXPECT_FALSE(parse_real(""));
}

TEST(keyword_numbers, IntegersAcceptIntegralRealsOnly) {
  std::int64_t value = 0;
  EXPECT_EQ(parse_integer("42", value), IntegerParse::ok);
  EXPECT_EQ(value, 42);
  EXPECT_EQ(parse_integer("-7", value), IntegerParse::ok);
  EXPECT_EQ(value, -7);
  EXPECT_EQ(parse_integer("2.0", value), IntegerParse::ok);
  EXPECT_EQ(value, 2);
  EXPECT_EQ(parse_integer("1.0+3", value), IntegerParse::ok);
  EXPECT_EQ(value, 1000);
  EXPECT_EQ(parse_integer("1.5", value), IntegerParse::not_integral);
  EXPECT_EQ(parse_integer("MECH", value), IntegerParse::not_a_number);
}

// A card context over one line, for cutting tests without a file.
struct OneLine {
  explicit OneLine(std::string text, bool long_format = false)
      : text_(std::move(text)), context{block, "*TEST", parameters, long_format} {
    block.file = "deck.k";
    block.line = 1;
    block.data.push_back({text_, 2});
  }
  Card card(std::span<const int> widths) const { return Card(context, block.data[0], widths); }

  std::string text_;
  KeywordBlock block;
  Parameters parameters;
  CardContext context;
};

TEST(keyword_card, CutsFixedFieldsByColumnEvenWhenRunTogether) {
  // *CONTROL_TERMINATION of pydyna_mech.k: ENDENG 0.0 and ENDMAS 1.0E8 touch.
  OneLine line("      0.03         0       0.0       0.01.000000E8         0");
  const Card card = line.card(standard_fields);
  EXPECT_EQ(card.real(0, "ENDTIM", -1), 0.03);
  EXPECT_EQ(card.integer(1, "ENDCYC", -1), 0);
  EXPECT_EQ(card.real(3, "ENDENG", -1), 0.0);
  EXPECT_EQ(card.real(4, "ENDMAS", -1), 1.0e8);
  EXPECT_EQ(card.integer(5, "NOSOL", -1), 0);
  EXPECT_EQ(card.real(6, "unused", -1), -1);  // beyond the line's end: blank, the default
}

TEST(keyword_card, CutsNodeColumns) {
  constexpr std::array<int, 6> node = {8, 16, 16, 16, 8, 8};
  OneLine line("     101        1.723924         39.0625       -2.303499       1       7");
  const Card card = line.card(node);
  EXPECT_EQ(card.integer(0, "NID", 0), 101);
  EXPECT_EQ(card.real(1, "X", 0), 1.723924);
  EXPECT_EQ(card.real(2, "Y", 0), 39.0625);
  EXPECT_EQ(card.real(3, "Z", 0), -2.303499);
  EXPECT_EQ(card.integer(4, "TC", 0), 1);
  EXPECT_EQ(card.integer(5, "RC", 0), 7);
}

TEST(keyword_card, BlankFieldsTakeDefaults) {
  OneLine line("         5" "          " "          " "       3.0");
  const Card card = line.card(standard_fields);
  EXPECT_TRUE(card.blank(1));
  EXPECT_EQ(card.real(1, "SF", 1.0), 1.0);
  EXPECT_EQ(card.real(3, "X", 0), 3.0);
  EXPECT_EQ(card.integer(7, "LAST", 9), 9);
}

TEST(keyword_card, FreeFormatSplitsAtCommas) {
  OneLine line("5, ,1.0+4,  -2 ,abc");
  const Card card = line.card(standard_fields);
  EXPECT_EQ(card.integer(0, "ID", 0), 5);
  EXPECT_EQ(card.real(1, "A", 7.0), 7.0);  // empty between commas = default
  EXPECT_EQ(card.real(2, "B", 0), 1.0e4);
  EXPECT_EQ(card.integer(3, "C", 0), -2);
  EXPECT_EQ(card.text(4), "abc");
  EXPECT_EQ(card.real(5, "D", 0.5), 0.5);  // omitted trailing field
}

TEST(keyword_card, LongFormatUsesTwentyCharacterFields) {
  OneLine line("                   1             2.5e3                 -4", true);
  const Card card = line.card(standard_fields);
  EXPECT_EQ(card.integer(0, "ID", 0), 1);
  EXPECT_EQ(card.real(1, "A", 0), 2500.0);
  EXPECT_EQ(card.integer(2, "B", 0), -4);
}

TEST(keyword_card, IntegerFieldsRejectFractionsAndText) {
  OneLine line("       1.5      MECH");
  const Card card = line.card(standard_fields);
  try {
    card.integer(0, "ELFORM", 0);
    FAIL() << "1.5 accepted as an integer";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "deck.k:2: *TEST: field ELFORM: '1.5' is not an integer");
  }
  try {
    card.integer(1, "SID", 0);
    FAIL() << "text accepted as an integer";
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "deck.k:2: *TEST: field SID: cannot read 'MECH' as an integer");
  }
}

TEST(keyword_card, BadNumberNamesTheFieldAndTheText) {
  OneLine line("     1.2.3");
  try {
    line.card(standard_fields).real(0, "X", 0);
    FAIL();
  } catch (const InputError& error) {
    EXPECT_STREQ(error.what(), "deck.k:2: *TEST: field X: cannot read '1.2.3' as a number");
    EXPECT_EQ(error.where().line, 2);
    EXPECT_EQ(error.keyword(), "*TEST");
  }
}

TEST(keyword_card, ParameterReferencesAndNegation) {
  OneLine line("    &scale   -&scale     &cnt");
  line.parameters.define("scale", {'R', 2.5, ""}, false);
  line.parameters.define("CNT", {'I', 3, ""}, false);
  const Card card = line.card(standard_fields);
  EXPECT_EQ(card.real(0, "A", 0), 2.5);
  EXPECT_EQ(card.real(1, "B", 0), -2.5);
  EXPECT_EQ(card.integer(2, "C", 0), 3);  // names are case-insensitive
  EXPECT_THROW(card.integer(0, "D", 0), InputError);  // 2.5 is no integer
}

TEST(keyword_card, RequiredFieldsMustBeGiven) {
  OneLine line("");
  try {
    line.card(standard_fields).required_real(0, "ENDTIM");
    FAIL();
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find("field ENDTIM"), std::string::npos);
  }
}

}  // namespace
}  // namespace spall::io::keyword
