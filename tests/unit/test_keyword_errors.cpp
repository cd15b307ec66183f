// Bad input: every failure is an InputError `file:line: *KEYWORD: message` that names the field
// and the text found; validate() reports broken cross-references at the card that holds them.
#include <gtest/gtest.h>

#include <random>

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

const std::initializer_list<int> node_widths = {8, 16, 16, 16, 8, 8};


const std::string termination = "*CONTROL_TERMINATION\n" + row({"1.0"});

TEST(keyword_errors, BadNumberNamesFieldAndText) {
  DeckFolder folder;
  const std::string message = read_error(
      folder, "*KEYWORD\n*NODE\n" + row({"1", "0.0", "0.0", "0.0"}, node_widths) +
                  row({"2", "1.2.3", "0.0", "0.0"}, node_widths));
  EXPECT_EQ(message, prefix(folder, 4, "*NODE") + "field X: cannot read '1.2.3' as a number");
}

TEST(keyword_errors, IntegerFieldRejectsFraction) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*SECTION_SOLID\n" + row({"1", "1.5"})),
            prefix(folder, 2, "*SECTION_SOLID") + "field ELFORM: '1.5' is not an integer");
}

// A flag or count beyond 32 bits is refused, not cut to its low 32 bits (2^32 + 1 would read as 1).
TEST(keyword_errors, IntegerFieldBeyond32BitsIsRefused) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*SECTION_SOLID\n" + row({"1", "4294967297"})),
            prefix(folder, 2, "*SECTION_SOLID") +
                "field ELFORM: '4294967297' is beyond the range of this field (a 32-bit integer)");
  // An eight-column field cannot hold such a number; a free-format line can.
  EXPECT_EQ(read_error(folder, "*NODE\n1,0.0,0.0,0.0,-4294967295\n"),
            prefix(folder, 2, "*NODE") +
                "field TC: '-4294967295' is beyond the range of this field (a 32-bit integer)");
}

// A free-format line with more values than its card has fields (sixteen node IDs on one line of
// *SET_NODE_LIST, whose cards hold eight) is an error, not a set of its first eight nodes; blank
// fields after the last (a closing comma) are not.
TEST(keyword_errors, CommaLineBeyondTheCardIsRefused) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*SET_NODE_LIST\n1\n1,2,3,4,5,6,7,8,9,10,11,12,13,14,15,16\n"),
            prefix(folder, 3, "*SET_NODE_LIST") +
                "16 comma-separated values on a card of 8 fields; the values past its last field go on a card of "
                "their own");
  EXPECT_EQ(read_error(folder, "*NODE\n1,0.0,0.0,0.0,0,0,7\n"),
            prefix(folder, 2, "*NODE") +
                "7 comma-separated values on a card of 6 fields; the values past its last field go on a card of "
                "their own");
  EXPECT_EQ(read_error(folder, "*NODE\n1,0.0,0.0,0.5,0,0,,,\n"), "");
}

TEST(keyword_errors, MissingMandatoryEndtim) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"", "100"})),
            prefix(folder, 3, "*CONTROL_TERMINATION") +
                "field ENDTIM: is blank but has no default; a value is required");
  EXPECT_EQ(read_error(folder, "*KEYWORD\n*CONTROL_TERMINATION\n*END\n"),
            prefix(folder, 2, "*CONTROL_TERMINATION") +
                "missing card 1 (ENDTIM ENDCYC DTMIN ENDENG ENDMAS)");
}

TEST(keyword_errors, DuplicateIds) {
  DeckFolder folder;
  const std::string message =
      read_error(folder, "*MAT_ELASTIC\n" + row({"1", "1.0", "1.0"}) + "*MAT_ELASTIC\n" +
                             row({"1", "2.0", "2.0"}));
  EXPECT_EQ(message, prefix(folder, 4, "*MAT_ELASTIC") + "material 1 is defined twice (first at " +
                         (folder.path() / "bad.k").string() + ":2)");
  const std::string nodes = validate_error(
      folder, termination + "*NODE\n" + row({"5", "0", "0", "0"}, node_widths) +
                  row({"5", "1", "0", "0"}, node_widths));
  EXPECT_EQ(nodes.rfind(prefix(folder, 5, "*NODE") + "node 5 is defined twice", 0), 0u) << nodes;
}

TEST(keyword_errors, CurveAbscissaMustIncrease) {
  DeckFolder folder;
  const std::string message =
      read_error(folder, "*DEFINE_CURVE\n" + row({"1"}) + row({"0.0", "0.0"}, {20, 20}) +
                             row({"0.0", "1.0"}, {20, 20}));
  EXPECT_EQ(message.rfind(prefix(folder, 4, "*DEFINE_CURVE") + "field A1: abscissa '0.0' does not increase", 0),
            0u)
      << message;
}

TEST(keyword_errors, SphParticleNeedsMassOrVolume) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*ELEMENT_SPH\n" + row({"1", "1"}, {8, 8})),
            prefix(folder, 2, "*ELEMENT_SPH") +
                "field MASS: particle 1 has no mass: give a mass (> 0) or a volume (< 0)");
}

TEST(keyword_errors, MissingIncludeAndUndefinedParameter) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*KEYWORD\n*INCLUDE\nnowhere.k\n").rfind(prefix(folder, 3, "*INCLUDE") + "cannot open 'nowhere.k'", 0),
            0u);
  EXPECT_EQ(read_error(folder, "*SECTION_SOLID\n" + row({"&secid"})),
            prefix(folder, 2, "*SECTION_SOLID") +
                "field SECID: parameter 'secid' is not defined (or not visible here)");
  EXPECT_EQ(read_error(folder, "*PARAMETER_EXPRESSION\nR x       2*(3+\n")
                .rfind(prefix(folder, 2, "*PARAMETER_EXPRESSION") + "field EXPRESSION:", 0),
            0u);
  EXPECT_EQ(read_error(folder, "*PARAMETER_EXPRESSION\nR x       sqrt(1,2)\n"),
            prefix(folder, 2, "*PARAMETER_EXPRESSION") + "field EXPRESSION: 'sqrt(1,2)': sqrt takes one argument");
  EXPECT_EQ(read_error(folder, "*PARAMETER_EXPRESSION\nR x       2 * pie\n"),
            prefix(folder, 2, "*PARAMETER_EXPRESSION") + "field EXPRESSION: '2 * pie': parameter 'pie' is not defined");
  EXPECT_EQ(read_error(folder, "*PARAMETER_EXPRESSION\n          1 + 2\n"),
            prefix(folder, 2, "*PARAMETER_EXPRESSION") + "field PRMR: is blank");
}

TEST(keyword_errors, SelfIncludeStopsAtADepthLimit) {
  DeckFolder folder;
  const std::string message = read_error(folder, "*INCLUDE\nbad.k\n");
  EXPECT_NE(message.find("includes nest deeper than"), std::string::npos) << message;
}

TEST(keyword_errors, ValidateNeedsTermination) {
  DeckFolder folder;
  EXPECT_EQ(validate_error(folder, "*KEYWORD\n*END\n"),
            (folder.path() / "bad.k").lexically_normal().string() +
                ": *CONTROL_TERMINATION is missing; its ENDTIM says when the run ends");
}

TEST(keyword_errors, ValidateRefusesAPartWithAnUnsupportedSection) {
  DeckFolder folder;
  const std::string message = validate_error(
      folder, termination + "*NODE\n" + row({"1", "0", "0", "0"}, node_widths) +
                  "*SECTION_BEAM\n" + row({"3", "2"}) + "*MAT_ELASTIC\n" + row({"1", "1.0", "1.0"}) +
                  "*PART\nskin\n" + row({"3", "3", "1"}) + "*ELEMENT_SPH\n" +
                  row({"1", "3", "1.0"}, {8, 8, 16}));
  EXPECT_EQ(message, prefix(folder, 11, "*PART") + "part 3 uses *SECTION_BEAM (" +
                         (folder.path() / "bad.k").lexically_normal().string() +
                         ":5), which Spall does not support");
}

TEST(keyword_errors, ShellCardsAndDeformableShells) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*SECTION_SHELL\n" + row({"3", "2"}) + row({"0.0"})),
            prefix(folder, 3, "*SECTION_SHELL") +
                "field T1: '0.0': a shell needs a thickness > 0 (its mass and contact surface)");
  EXPECT_EQ(read_error(folder, "*SECTION_SHELL\n" + row({"3", "2"}) + row({"1.0", "", "", "", "1"})),
            prefix(folder, 3, "*SECTION_SHELL") +
                "field NLOC: '1': a reference surface off the mid-surface is not implemented (0)");
  EXPECT_EQ(read_error(folder, "*SECTION_SHELL\n" + row({"3", "101"}) + row({"1.0"})),
            prefix(folder, 2, "*SECTION_SHELL") +
                "field ELFORM: '101': this shell formulation's extra cards are not read");
  EXPECT_EQ(read_error(folder, "*ELEMENT_SHELL\n" + row({"1", "3", "1", "2", "3", "4", "5"}, {8, 8, 8, 8, 8, 8, 8})),
            prefix(folder, 2, "*ELEMENT_SHELL") +
                "field N5: element 1: eight-node (quadratic) shells are not supported");
  EXPECT_EQ(read_error(folder, "*ELEMENT_SHELL\n" + row({"1", "3", "1", "2"}, {8, 8, 8, 8})),
            prefix(folder, 2, "*ELEMENT_SHELL") +
                "field N3: element 1: N3 is blank or not a node ID; a shell needs N1-N3, and N4 (or N3 repeated)");
  // Spall runs shells as rigid geometry only: a deformable shell part stops the check.
  const std::string nodes = "*NODE\n" + row({"1", "0", "0", "0"}, node_widths) +
                            row({"2", "1", "0", "0"}, node_widths) + row({"3", "1", "1", "0"}, node_widths);
  EXPECT_EQ(validate_error(folder, termination + nodes + "*SECTION_SHELL\n" + row({"3", "2"}) + row({"1.0"}) +
                                       "*MAT_ELASTIC\n" + row({"1", "1.0", "1.0"}) + "*PART\nskin\n" +
                                       row({"3", "3", "1"}) + "*ELEMENT_SHELL\n" +
                                       row({"1", "3", "1", "2", "3"}, {8, 8, 8, 8, 8})),
            prefix(folder, 14, "*PART") + "part 3 has *ELEMENT_SHELL elements (" +
                (folder.path() / "bad.k").lexically_normal().string() +
                ":16) but material 1 is not *MAT_RIGID: Spall runs shells only as rigid geometry (deformable shells "
                "are not implemented)");
}

TEST(keyword_errors, DefineVector) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*DEFINE_VECTOR_TITLE\naxis\n" + row({"3", "1.0", "2.0", "3.0", "1.0", "2.0", "3.0"})),
            prefix(folder, 3, "*DEFINE_VECTOR_TITLE") + "field XH: the head is the tail: the vector has no direction");
  const auto model = read_deck(folder.write("ok.k", "*DEFINE_VECTOR\n" + row({"3", "1.0", "2.0", "3.0", "1.0", "2.0",
                                                                              "4.0", "7"})));
  EXPECT_EQ(model.vectors.at(3).head - model.vectors.at(3).tail, Vec3(0, 0, 1));
  EXPECT_EQ(model.vectors.at(3).cid, 7);
}

TEST(keyword_errors, ValidateCrossReferences) {
  DeckFolder folder;
  const std::string base = termination + "*NODE\n" + row({"1", "0", "0", "0"}, node_widths) +
                           "*SECTION_SOLID\n" + row({"1"}) + "*SECTION_SPH\n" + row({"2"}) +
                           "*MAT_ELASTIC\n" + row({"1", "1.0", "1.0"}) + "*PART\nblock\n" +
                           row({"1", "1", "1"});
  // Lines 1-13 are `base` (the part card on 13); the card under test is on line 15.
  EXPECT_EQ(validate_error(folder, base + "*ELEMENT_SPH\n" + row({"1", "1", "1.0"}, {8, 8, 16})),
            prefix(folder, 13, "*PART") + "part 1 has *ELEMENT_SPH particles (" +
                (folder.path() / "bad.k").lexically_normal().string() +
                ":15) but its section 1 is not a *SECTION_SPH");
  EXPECT_EQ(validate_error(folder, base + "*ELEMENT_SOLID\n" +
                                       row({"1", "1", "1", "1", "1", "1", "9", "1", "1", "1"},
                                           {8, 8, 8, 8, 8, 8, 8, 8, 8, 8})),
            prefix(folder, 15, "*ELEMENT_SOLID") + "element 1: node N5 = 9 is not defined");
  EXPECT_EQ(validate_error(folder, base + "*SET_NODE_LIST\n" + row({"1"}) + row({"1", "2"})),
            prefix(folder, 15, "*SET_NODE_LIST") + "node set 1: node 2 is not defined");
  EXPECT_EQ(validate_error(folder, base + "*LOAD_BODY_Z\n" + row({"4"})),
            prefix(folder, 15, "*LOAD_BODY_Z") + "LCID: curve 4 is not defined");
  EXPECT_EQ(validate_error(folder, base + "*BOUNDARY_SPC_SET\n" + row({"7", "0", "1"})),
            prefix(folder, 15, "*BOUNDARY_SPC_SET") + "node set 7 is not defined");
  EXPECT_EQ(validate_error(folder, base + "*PART\nother\n" + row({"2", "1", "8"})),
            prefix(folder, 16, "*PART") + "part 2: material 8 is not defined");
}

// A set or curve that a keyword Spall does not read defines is named with that keyword, not
// called undefined; a set of another kind with the same ID does not count (own ID space).
TEST(keyword_errors, ASetOrCurveOfAnUnreadKeywordIsNamed) {
  DeckFolder folder;
  const std::string base = termination + "*NODE\n" + row({"1", "0", "0", "0"}, node_widths) +
                           "*SECTION_SOLID\n" + row({"1"}) + "*SECTION_SPH\n" + row({"2"}) +
                           "*MAT_ELASTIC\n" + row({"1", "1.0", "1.0"}) + "*PART\nblock\n" +
                           row({"1", "1", "1"});
  const std::string deck = (folder.path() / "bad.k").lexically_normal().string();
  EXPECT_EQ(validate_error(folder, base + "*SET_NODE_ADD\n" + row({"7"}) + row({"1", "2"}) +
                                       "*BOUNDARY_SPC_SET\n" + row({"7", "0", "1"})),
            prefix(folder, 18, "*BOUNDARY_SPC_SET") + "node set 7 is defined by *SET_NODE_ADD (" + deck +
                ":14), which Spall does not read");
  EXPECT_EQ(validate_error(folder, base + "*SET_SHELL_LIST\n" + row({"7"}) + row({"1"}) + "*BOUNDARY_SPC_SET\n" +
                                       row({"7", "0", "1"})),
            prefix(folder, 18, "*BOUNDARY_SPC_SET") + "node set 7 is not defined");
  EXPECT_EQ(validate_error(folder, base + "*DEFINE_CURVE_FUNCTION_TITLE\ngravity\n" + row({"4"}) + "9.81\n" +
                                       "*LOAD_BODY_Z\n" + row({"4"})),
            prefix(folder, 19, "*LOAD_BODY_Z") + "LCID: curve 4 is defined by *DEFINE_CURVE_FUNCTION_TITLE (" + deck +
                ":14), which Spall does not read");
}

// Thermal materials have their own ID space (LS-DYNA): thermal material 1 beside material 1 is no
// repeat, and *PART TMID names one of them. A thermal or coupled solution cannot be run.
TEST(keyword_errors, ThermalMaterialsHaveTheirOwnIdsAndAThermalSolutionIsRefused) {
  DeckFolder folder;
  const std::string base = termination + "*NODE\n" + row({"1", "0", "0", "0"}, node_widths) +
                           "*SECTION_SPH\n" + row({"1"}) + "*MAT_ELASTIC\n" + row({"1", "1.0", "1.0"}) +
                           "*MAT_THERMAL_ISOTROPIC_TITLE\nsteel\n" + row({"1", "7850", "", "", "0.0"}) +
                           row({"460", "45"});
  // Lines 1-12 are `base`; the *PART card is on line 15.
  const std::string part = "*PART\nblock\n" + row({"1", "1", "1", "", "", "", "", "1"});
  const auto model = read_deck(folder.write("good.k", base + part));
  EXPECT_NO_THROW(validate(model));
  ASSERT_TRUE(model.thermal_materials.contains(1));
  EXPECT_EQ(model.thermal_materials.at(1).keyword, "*MAT_THERMAL_ISOTROPIC_TITLE");
  EXPECT_EQ(model.parts.at(0).tmid, 1);
  EXPECT_TRUE(model.unsupported.empty());
  EXPECT_EQ(validate_error(folder, base + "*PART\nblock\n" + row({"1", "1", "1", "", "", "", "", "2"})),
            prefix(folder, 15, "*PART") + "part 1: TMID: thermal material 2 is not defined");
  EXPECT_EQ(read_error(folder, base + "*MAT_T01\n" + row({"1", "7850"}) + row({"460", "45"})),
            prefix(folder, 14, "*MAT_T01") + "thermal material 1 is defined twice (first at " +
                (folder.path() / "bad.k").lexically_normal().string() + ":11)");
  EXPECT_NO_THROW(read_deck(folder.write("soln0.k", base + part + "*CONTROL_SOLUTION\n" + row({"0"}))));
  EXPECT_EQ(read_error(folder, base + part + "*CONTROL_SOLUTION\n" + row({"2"})),
            prefix(folder, 17, "*CONTROL_SOLUTION") +
                "field SOLN: 2 (coupled thermal-structural): Spall solves no heat equation and cannot run a thermal "
                "analysis; SOLN 0 is the structural one");
}

// Whatever the bytes, reading ends in a model or an InputError, never another exception or a crash.
TEST(keyword_errors, MangledDecksFailOnlyWithInputError) {
  DeckFolder folder;
  const std::string original =
      "*KEYWORD\n*PARAMETER\nR a       2.0\n" + termination + "*NODE\n" +
      row({"1", "0", "0", "0"}, node_widths) + row({"2", "1", "0", "0"}, node_widths) +
      "*SECTION_SPH\n" + row({"1", "&a"}) + "*PART\np\n" + row({"1", "1", "1"}) +
      "*ELEMENT_SPH\n" + row({"1", "1", "-1.0", "2"}, {8, 8, 16, 8}) + "*SET_NODE_LIST_GENERATE\n" +
      row({"1"}) + row({"1", "2"}) + "*DEFINE_CURVE\n" + row({"1"}) + row({"0", "0"}, {20, 20}) +
      "*INCLUDE\nbad.k\n*END\n";
  std::mt19937 random(12345);
  const std::string alphabet = "*$&,.-+ 0123456789EeDd\nABZ_()";
  for (int trial = 0; trial < 300; ++trial) {
    std::string text = original;
    const int edits = 1 + static_cast<int>(random() % 6);
    for (int e = 0; e < edits; ++e)
      text[random() % text.size()] = alphabet[random() % alphabet.size()];
    const auto path = folder.write("mangled.k", text);
    try {
      const auto model = read_deck(path);
      validate(model);
    } catch (const InputError&) {
    } catch (const std::exception& other) {
      ADD_FAILURE() << "trial " << trial << ": " << other.what() << "\n" << text;
    }
  }
}

// What the keyword fuzz target found (fuzz/regressions/ holds each as a deck): a stack overflow, an
// exception other than InputError, undefined behaviour, a read without end or a giant allocation.
// Each is now one line naming the field.
TEST(keyword_errors, DeeplyNestedExpressionsAreRefusedBeforeTheStackOverflows) {
  DeckFolder folder;
  const std::string tail = ": nests deeper than 256 levels (parentheses, signs, powers)";
  std::string tower = "1";
  for (int level = 0; level < 300; ++level) tower += "**1";
  for (const std::string& expression :
       {std::string(100'000, '(') + "1" + std::string(100'000, ')'), std::string(100'000, '-') + "1", tower}) {
    const std::string message = read_error(folder, "*PARAMETER_EXPRESSION\nR deep    " + expression + "\n");
    EXPECT_EQ(message.rfind(prefix(folder, 2, "*PARAMETER_EXPRESSION") + "field EXPRESSION: '", 0), 0u) << message;
    EXPECT_TRUE(message.ends_with(tail)) << message.substr(message.size() - std::min<std::size_t>(200, message.size()));
  }
  // 256 levels are still read.
  const std::string deepest = std::string(255, '(') + "1" + std::string(255, ')');
  EXPECT_EQ(read_error(folder, "*PARAMETER_EXPRESSION\nR deep    " + deepest + "\n"), "");
}

TEST(keyword_errors, ExpressionsWhoseValueIsNotFiniteAreRefused) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*PARAMETER_EXPRESSION\nR x       1.0/0.0\n"),
            prefix(folder, 2, "*PARAMETER_EXPRESSION") + "field EXPRESSION: '1.0/0.0': the value is not finite (inf)");
  EXPECT_EQ(read_error(folder, "*PARAMETER_EXPRESSION\nI x       10**400\n"),
            prefix(folder, 2, "*PARAMETER_EXPRESSION") + "field EXPRESSION: '10**400': the value is not finite (inf)");
  EXPECT_EQ(read_error(folder, "*PARAMETER_EXPRESSION\nR x       log(0) - log(0)\n"),
            prefix(folder, 2, "*PARAMETER_EXPRESSION") +
                "field EXPRESSION: 'log(0) - log(0)': the value is not finite (-nan)");
}

TEST(keyword_errors, AParameterValueWithoutANameIsRefused) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*PARAMETER\n" + row({"", "1.0", "R b", "2.0"})),
            prefix(folder, 2, "*PARAMETER") +
                "field PRMR1: is blank, but VAL1 is '1.0': a value needs a type letter and a name");
}

TEST(keyword_errors, NodeSetRangesLongerThanTheDeckHasNodesAreRefused) {
  DeckFolder folder;
  const std::string nodes = "*NODE\n" + row({"1", "0", "0", "0"}, node_widths) + row({"2", "1", "0", "0"}, node_widths);
  EXPECT_EQ(read_error(folder, nodes + "*SET_NODE_LIST_GENERATE\n" + row({"1"}) + row({"1", "1000000000"})),
            prefix(folder, 6, "*SET_NODE_LIST_GENERATE") +
                "field B1BEG: range 1..1000000000 holds 1000000000 node IDs, more than the 2 nodes the deck defines");
  EXPECT_EQ(read_error(folder, "*SET_NODE_LIST_GENERATE\n" + row({"1"}) + "1,9223372036854775807\n"),
            prefix(folder, 3, "*SET_NODE_LIST_GENERATE") +
                "field B1BEG: range 1..9223372036854775807 is not a range of node IDs");
  // A range is read before the nodes it names, as LS-DYNA allows.
  const auto model =
      read_deck(folder.write("later.k", "*SET_NODE_LIST_GENERATE\n" + row({"1"}) + row({"1", "2"}) + nodes));
  EXPECT_EQ(model.node_sets.at(1).nodes, (std::vector<Id>{1, 2}));
}

TEST(keyword_errors, ANegativeTssfacIsAWholeCurveId) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*CONTROL_TIMESTEP\n" + row({"0.0", "-1.5"})),
            prefix(folder, 2, "*CONTROL_TIMESTEP") +
                "field TSSFAC: '-1.5': a negative TSSFAC is a curve ID, a whole number");
  EXPECT_EQ(read_error(folder, "*CONTROL_TIMESTEP\n" + row({"0.0", "-1.0e300"})),
            prefix(folder, 2, "*CONTROL_TIMESTEP") +
                "field TSSFAC: '-1.0e300': a negative TSSFAC is a curve ID, a whole number");
}

TEST(keyword_errors, ErosionCountsBeyondAnIntAreRefused) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*MAT_ADD_EROSION\n" + row({"1", "", "", "", "", "", "1.0e300"})),
            prefix(folder, 2, "*MAT_ADD_EROSION") +
                "field NUMFIP: '1.0e300': only a number of integration points (>= 1) is implemented for solids");
  EXPECT_EQ(read_error(folder, "*MAT_ADD_EROSION\n" + row({"1", "", "", "", "", "", "", "1.0e20"})),
            prefix(folder, 2, "*MAT_ADD_EROSION") + "field NCS: '1.0e20' is not a number of criteria (>= 1)");
}

TEST(keyword_errors, NodeIdsAndCoordinatesOutOfRangeAreRefused) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*NODE\n1152921504606846976,0.0,0.0,0.0\n"),
            prefix(folder, 2, "*NODE") + "field NID: 1152921504606846976 is not a node ID (1 to 2^53)");
  EXPECT_EQ(read_error(folder, "*NODE\n" + row({"0", "0", "0", "0"}, node_widths)),
            prefix(folder, 2, "*NODE") + "field NID: 0 is not a node ID (1 to 2^53)");
  EXPECT_EQ(read_error(folder, "*NODE\n" + row({"1", "-inf", "0", "0"}, node_widths)),
            prefix(folder, 2, "*NODE") + "field X: cannot read '-inf' as a number");
  EXPECT_EQ(read_error(folder, "*NODE\n" + row({"1", "1.0e400", "0", "0"}, node_widths)),
            prefix(folder, 2, "*NODE") + "field X: cannot read '1.0e400' as a number");
  EXPECT_EQ(read_error(folder, "*ELEMENT_SPH\n-9000000000000000000,1,1.0,9000000000000000000\n"),
            prefix(folder, 2, "*ELEMENT_SPH") + "field NID: -9000000000000000000 is not a node ID (1 to 2^53)");
  EXPECT_EQ(read_error(folder, "*ELEMENT_SPH\n1,1,1.0,9000000000000000000\n"),
            prefix(folder, 2, "*ELEMENT_SPH") + "field NEND: 9000000000000000000 is not a node ID (1 to 2^53)");
}

TEST(keyword_errors, AnIncludeThatIsNotAFileIsRefused) {
  DeckFolder folder;
  EXPECT_EQ(read_error(folder, "*INCLUDE\n.\n"),
            prefix(folder, 2, "*INCLUDE") + "'.' is a directory, not a keyword file");
  EXPECT_EQ(read_error(folder, "*INCLUDE\n/dev/zero\n"),
            prefix(folder, 2, "*INCLUDE") +
                "'/dev/zero' is not a regular file (a device or a pipe), not a keyword file");
}

}  // namespace
}  // namespace spall::io::keyword
