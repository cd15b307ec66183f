// *CONTACT_NODES_TO_SURFACE, *CONTACT_AUTOMATIC_NODES_TO_SURFACE, *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE,
// *CONTACT_AUTOMATIC_SINGLE_SURFACE (_ID, _TITLE, _MPP), the *CONTACT_ERODING_ types, *CONTROL_CONTACT,
// *SET_SEGMENT and *DATABASE_RCFORC: option spellings, LS-DYNA's defaults, every refused field at its line, and the
// references validate() checks.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "keyword_test_decks.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/io/keyword/unsupported.hpp"

namespace spall::io::keyword {
namespace {

using model::Contact;
using model::ContactSurface;
using test::DeckFolder;
using test::input_error_of;
using test::row;
using test::prefix;
using test::read_error;
using test::validate_error;

const std::initializer_list<int> node_widths = {8, 16, 16, 16, 8, 8};

// Four SPH particles of part 1; node set 1 (nodes 1, 2), part set 3 (part 1), segment set 5 (a
// triangle): every kind of surface a contact may name.
const std::string base_deck =
    "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"1.0e-3"}) + "*NODE\n" +
    row({"1", "0.0", "0.0", "0.0"}, node_widths) + row({"2", "1.0", "0.0", "0.0"}, node_widths) +
    row({"3", "0.0", "1.0", "0.0"}, node_widths) + row({"4", "0.0", "0.0", "1.0"}, node_widths) +
    "*SET_NODE_LIST\n" + row({"1"}) + row({"1", "2"}) + "*SET_PART_LIST\n" + row({"3"}) + row({"1"}) +
    "*SET_SEGMENT\n" + row({"5"}) + row({"1", "2", "3"}) + "*PART\nblock\n" + row({"1", "1", "1"}) +
    "*SECTION_SPH\n" + row({"1", "1.2", "1.0", "1.0"}) + "*MAT_ELASTIC\n" + row({"1", "7850.0", "2.0e11", "0.3"}) +
    "*ELEMENT_SPH\n" + row({"1", "1", "1.0e-3"}, {8, 8, 16}) + row({"2", "1", "1.0e-3"}, {8, 8, 16}) +
    row({"3", "1", "1.0e-3"}, {8, 8, 16}) + row({"4", "1", "1.0e-3"}, {8, 8, 16});

// The line the next keyword of `text` has: one after its last.
int next_line(const std::string& text) { return static_cast<int>(std::count(text.begin(), text.end(), '\n')) + 1; }


TEST(keyword_contact, FourTypesAndTheirOptionSpellings) {
  DeckFolder folder;
  const std::string deck =
      base_deck + "*PARAMETER\n" + row({"I sa", "1"}) +
      // No option: card 1 only, the block ending there.
      "*CONTACT_NODES_TO_SURFACE\n" + row({"1", "5", "4", "0"}) +
      "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID\n" + row({"7"}).substr(0, 10) + "tool on plate\n" +
      row({"1", "1", "4", "3"}) +
      "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_TITLE\n" + row({"8"}).substr(0, 10) + "  two bodies  \n" +
      row({"3", "5", "2", "0"}) +
      // _MPP: card 1 only; then card 1 of the contact starts with a parameter, which is not the flag.
      "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MPP\n" + row({"0", "200", "", "3", "2", "1.0005", "", "0"}) +
      row({"&sa", "1", "3", "3"}) +
      // _MPP_ID with the `&` MPP card 2, and _ID_MPP without it: the options in either order.
      "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_MPP_ID\n" + row({"9"}) + row({"0", "100"}) +
      row({"&", "0", "1.0", "0"}) + row({"1", "3", "4", "2"}) +
      "*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID_MPP\n" + row({"10"}) + row({}) + row({"3", "", "2"}) + "*END\n";
  const auto model = read_deck(folder.write("contacts.k", deck));
  EXPECT_NO_THROW(validate(model));
  ASSERT_EQ(model.contacts.size(), 6u);
  const int first = next_line(base_deck) + 2;  // after the *PARAMETER block

  const auto& plain = model.contacts[0];
  EXPECT_EQ(plain.kind, Contact::Kind::nodes_to_surface);
  EXPECT_EQ(plain.keyword, "*CONTACT_NODES_TO_SURFACE");
  EXPECT_EQ(plain.id, 0);
  EXPECT_EQ(plain.a.type, ContactSurface::Type::node_set);
  EXPECT_EQ(plain.a.id, 1);
  EXPECT_EQ(plain.b.type, ContactSurface::Type::segment_set);
  EXPECT_EQ(plain.b.id, 5);
  EXPECT_EQ(plain.where.line, first + 1);
  EXPECT_EQ(plain.a.where.line, first + 1);

  const auto& with_id = model.contacts[1];
  EXPECT_EQ(with_id.kind, Contact::Kind::automatic_nodes_to_surface);
  EXPECT_EQ(with_id.keyword, "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID");
  EXPECT_EQ(with_id.id, 7);
  EXPECT_EQ(with_id.heading, "tool on plate");
  EXPECT_EQ(with_id.b.type, ContactSurface::Type::part);
  EXPECT_EQ(with_id.where.line, first + 4);

  const auto& titled = model.contacts[2];
  EXPECT_EQ(titled.kind, Contact::Kind::automatic_surface_to_surface);
  EXPECT_EQ(titled.id, 8);
  EXPECT_EQ(titled.heading, "two bodies");
  EXPECT_EQ(titled.a.type, ContactSurface::Type::part_set);
  EXPECT_EQ(titled.a.id, 3);

  const auto& mpp = model.contacts[3];
  EXPECT_EQ(mpp.keyword, "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE_MPP");
  EXPECT_EQ(mpp.id, 0);
  EXPECT_EQ(mpp.a.id, 1);  // &sa
  EXPECT_EQ(mpp.a.type, ContactSurface::Type::part);
  EXPECT_EQ(mpp.where.line, first + 10);

  const auto& mpp_id = model.contacts[4];
  EXPECT_EQ(mpp_id.kind, Contact::Kind::automatic_nodes_to_surface);
  EXPECT_EQ(mpp_id.id, 9);
  EXPECT_EQ(mpp_id.b.type, ContactSurface::Type::part_set);
  EXPECT_EQ(mpp_id.where.line, first + 15);

  const auto& single = model.contacts[5];
  EXPECT_EQ(single.kind, Contact::Kind::automatic_single_surface);
  EXPECT_EQ(single.keyword, "*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID_MPP");
  EXPECT_EQ(single.id, 10);
  EXPECT_EQ(single.a.type, ContactSurface::Type::part_set);
  EXPECT_EQ(single.a.id, 3);
  EXPECT_TRUE(model.unsupported.empty());
}

TEST(keyword_contact, BlankAndZeroTakeTheDefaults) {
  DeckFolder folder;
  const std::string zeros = row({"0", "0", "0", "0", "0", "0", "0", "0"});
  const std::string deck = base_deck + "*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n" + row({"1", "1", "4", "3"}) +
                           "*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n" + row({"1", "1", "4", "3"}) + zeros + zeros +
                           zeros + zeros + zeros + "\n\n\n\n\n";
  const auto model = read_deck(folder.write("defaults.k", deck));
  ASSERT_EQ(model.contacts.size(), 2u);
  for (const auto& contact : model.contacts) {
    EXPECT_EQ(contact.fs, 0.0);
    EXPECT_EQ(contact.fd, 0.0);
    EXPECT_EQ(contact.dc, 0.0);
    EXPECT_EQ(contact.vc, 0.0);
    EXPECT_EQ(contact.vdc, 0.0);
    EXPECT_EQ(contact.birth, 0.0);
    EXPECT_EQ(contact.death, 1.0e20);  // DT 0 -> 1e20
    EXPECT_EQ(contact.sfsa, 1.0);      // 0 -> 1
    EXPECT_EQ(contact.sfsb, 1.0);
    EXPECT_EQ(contact.fsf, 1.0);
    EXPECT_EQ(contact.vsf, 1.0);
    EXPECT_EQ(contact.soft, 0);
    EXPECT_EQ(contact.sofscl, 0.1);    // 0 -> 0.1
    EXPECT_EQ(contact.maxpar, 1.025);  // 0 -> 1.025
    EXPECT_EQ(contact.bsort, 0);
    EXPECT_EQ(contact.penmax, 0.0);
    EXPECT_EQ(contact.sldstf, 0.0);
    EXPECT_EQ(contact.dtstif, 0.0);
  }
  // Cards 2 and 3 left out: their locations are card 1's.
  const int line = next_line(base_deck) + 1;
  EXPECT_EQ(model.contacts[0].where.line, line);
  EXPECT_EQ(model.contacts[0].where_card2.line, line);
  EXPECT_EQ(model.contacts[0].where_card3.line, line);
  EXPECT_EQ(model.contacts[1].where_card2.line, line + 3);
  EXPECT_EQ(model.contacts[1].where_card3.line, line + 4);
}

TEST(keyword_contact, CardsTwoThreeAndOptionalCardsAToG) {
  DeckFolder folder;
  const std::string deck =
      base_deck + "*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE\n" + row({"3", "5", "2", "0"}) +
      row({"0.3", "0.2", "0.5", "100.0", "20.0", "0", "1.0e-4", "2.0e-3"}) +
      row({"0.5", "2.0", "0.0", "", "1.0", "", "0.8", "1.5"}) +
      row({"1", "0.3", "0", "1.2", "3", "5", "10", "1"}) +       // A
      row({"0.5", "0", "0", "1", "0", "0", "0.0", "2.0e11"}) +    // B
      row({"1", "0", "0.0", "1.0e-7", "0.0", "", "0.0", "0"}) +  // C
      row({}) + row({"", "", "", "", "1.0"}) + row({"", "", "", "2.0"}) + row({"", "0.0"}) +  // D E F G
      "*END\n";
  const auto model = read_deck(folder.write("cards.k", deck));
  ASSERT_EQ(model.contacts.size(), 1u);
  const auto& c = model.contacts[0];
  EXPECT_EQ(c.fs, 0.3);
  EXPECT_EQ(c.fd, 0.2);
  EXPECT_EQ(c.dc, 0.5);
  EXPECT_EQ(c.vc, 100.0);
  EXPECT_EQ(c.vdc, 20.0);
  EXPECT_EQ(c.birth, 1.0e-4);
  EXPECT_EQ(c.death, 2.0e-3);
  EXPECT_EQ(c.sfsa, 0.5);
  EXPECT_EQ(c.sfsb, 2.0);
  EXPECT_EQ(c.fsf, 0.8);
  EXPECT_EQ(c.vsf, 1.5);
  EXPECT_EQ(c.soft, 1);
  EXPECT_EQ(c.sofscl, 0.3);
  EXPECT_EQ(c.maxpar, 1.2);
  EXPECT_EQ(c.bsort, 10);
  EXPECT_EQ(c.penmax, 0.5);
  EXPECT_EQ(c.sldstf, 2.0e11);
  EXPECT_EQ(c.dtstif, 1.0e-7);
  const int line = next_line(base_deck) + 1;
  EXPECT_EQ(c.where_card2.line, line + 1);
  EXPECT_EQ(c.where_card3.line, line + 2);
}

// The eroding types: the automatic type of the same name, with card 4 (ISYM EROSOP IADJ) between
// card 3 and optional card A; without card 4 (the block ending after card 3) EROSOP and IADJ are 0.
TEST(keyword_contact, ErodingTypesReadCardFour) {
  DeckFolder folder;
  const std::string deck =
      base_deck + "*CONTACT_ERODING_NODES_TO_SURFACE_ID\n" + row({"4"}) + row({"1", "3", "4", "2"}) +
      row({"0.2"}) + row({}) + row({"0", "1", "1"}) + row({"1", "0.2"}) +  // card 4, then A
      "*CONTACT_ERODING_SURFACE_TO_SURFACE\n" + row({"3", "5", "2", "0"}) + row({}) + row({}) + row({"", "1"}) +
      "*CONTACT_ERODING_SINGLE_SURFACE_MPP\n" + row({"0", "200"}) + row({"3", "", "2"}) + row({}) + row({}) +
      "*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n" + row({"1", "3", "4", "2"}) + "*END\n";
  const auto model = read_deck(folder.write("eroding.k", deck));
  EXPECT_NO_THROW(validate(model));
  ASSERT_EQ(model.contacts.size(), 4u);
  const auto& n2s = model.contacts[0];
  EXPECT_EQ(n2s.kind, Contact::Kind::automatic_nodes_to_surface);
  EXPECT_TRUE(n2s.eroding);
  EXPECT_EQ(n2s.id, 4);
  EXPECT_EQ(n2s.fs, 0.2);
  EXPECT_EQ(n2s.isym, 0);
  EXPECT_EQ(n2s.erosop, 1);
  EXPECT_EQ(n2s.iadj, 1);
  EXPECT_EQ(n2s.soft, 1);  // optional card A after card 4
  EXPECT_EQ(n2s.sofscl, 0.2);
  EXPECT_EQ(model.contacts[1].kind, Contact::Kind::automatic_surface_to_surface);
  EXPECT_TRUE(model.contacts[1].eroding);
  EXPECT_EQ(model.contacts[1].erosop, 1);
  EXPECT_EQ(model.contacts[1].iadj, 0);
  EXPECT_EQ(model.contacts[2].kind, Contact::Kind::automatic_single_surface);
  EXPECT_TRUE(model.contacts[2].eroding);
  EXPECT_EQ(model.contacts[2].erosop, 0);
  EXPECT_FALSE(model.contacts[3].eroding);
  EXPECT_EQ(model.contacts[3].isym, -1);  // not given: *CONTROL_CONTACT's
  // Card 4's refusals, at its line.
  const std::string eroding = "*CONTACT_ERODING_NODES_TO_SURFACE";
  const std::string cards = row({"1", "1", "4", "3"}) + row({}) + row({});
  EXPECT_EQ(read_error(folder, eroding + "\n" + cards + row({"3"})),
            prefix(folder, 5, eroding) + "field ISYM: '3' is not 0 or 1");
  EXPECT_EQ(read_error(folder, eroding + "\n" + cards + row({"0", "2"})),
            prefix(folder, 5, eroding) + "field EROSOP: '2' is not 0 or 1");
  EXPECT_EQ(read_error(folder, eroding + "\n" + cards + row({"0", "0", "-1"})),
            prefix(folder, 5, eroding) + "field IADJ: '-1' is not 0 or 1");
}

TEST(keyword_contact, SingleSurfaceHasSideAOnlyAndSurfaZeroMeansAll) {
  DeckFolder folder;
  const std::string deck = base_deck + "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n" + row({"0", "0", "5"}) +
                           "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n" + row({"", "", "2"}) +
                           "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n" + row({"0"}) +
                           // SURFB, SURFBTYP, SBBOXID and SBPR are ignored for single surface.
                           "*CONTACT_AUTOMATIC_SINGLE_SURFACE\n" + row({"1", "9", "3", "1", "0", "7", "0", "1"}) +
                           row({"", "", "", "", "", "", "", ""}) + row({}) + row({"1", "0.5"});
  const auto model = read_deck(folder.write("single.k", deck));
  EXPECT_NO_THROW(validate(model));
  ASSERT_EQ(model.contacts.size(), 4u);
  for (int k = 0; k < 3; ++k) EXPECT_EQ(model.contacts[k].a.type, ContactSurface::Type::all) << k;
  EXPECT_EQ(model.contacts[3].a.type, ContactSurface::Type::part);
  EXPECT_EQ(model.contacts[3].a.id, 1);
  EXPECT_EQ(model.contacts[3].sofscl, 0.5);  // the largest SOFSCL single surface admits
}

// Each refused field: `file:line: *KEYWORD: field NAME: ...`, at the line of its card.
TEST(keyword_contact, RefusedFieldsNameTheirLineAndField) {
  DeckFolder folder;
  const std::string one_way = "*CONTACT_AUTOMATIC_NODES_TO_SURFACE";
  const std::string card1 = row({"1", "1", "4", "3"});
  const std::string blank = row({});
  const int first = 2;  // the line of card 1 in "*KEYWORD"-less decks below
  struct Case {
    std::string keyword;
    std::string cards;  // from card 1 on
    int card;           // 0-based card whose line fails
    std::string field;
  };
  const std::vector<Case> cases = {
      {one_way, row({"1", "1", "1", "3"}), 0, "SURFATYP"},
      {one_way, row({"1", "1", "7", "3"}), 0, "SURFATYP"},
      {one_way, row({"1", "1", "8", "3"}), 0, "SURFATYP"},
      {one_way, row({"1", "1", "4", "4"}), 0, "SURFBTYP"},
      {one_way, row({"1", "1", "4", "1"}), 0, "SURFBTYP"},
      {"*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", row({"1", "1", "4", "3"}), 0, "SURFATYP"},
      {"*CONTACT_AUTOMATIC_SINGLE_SURFACE", row({"1", "", "4"}), 0, "SURFATYP"},
      {one_way, row({"0", "1", "3", "3"}), 0, "SURFA"},
      {one_way, row({"", "1", "0", "3"}), 0, "SURFA"},
      {one_way, row({"1", "-2", "4", "3"}), 0, "SURFB"},
      {one_way, row({"1", "1", "4", "3", "1"}), 0, "SABOXID"},
      {one_way, row({"1", "1", "4", "3", "0", "2"}), 0, "SBBOXID"},
      {one_way, row({"1", "1", "4", "3", "0", "0", "1"}), 0, "SAPR"},
      {one_way, row({"1", "1", "4", "3", "0", "0", "0", "1"}), 0, "SBPR"},
      {one_way, card1 + row({"-1.0"}), 1, "FS"},
      {one_way, card1 + row({"2.0", "7"}), 1, "FS"},
      {one_way, card1 + row({"-2.0"}), 1, "FS"},
      {one_way, card1 + row({"0.2", "-0.1"}), 1, "FD"},
      {one_way, card1 + row({"0.2", "0.1", "-1"}), 1, "DC"},
      {one_way, card1 + row({"", "", "", "-5"}), 1, "VC"},
      {one_way, card1 + row({"", "", "", "", "120"}), 1, "VDC"},
      {one_way, card1 + row({"", "", "", "", "", "1"}), 1, "PENCHK"},
      {one_way, card1 + row({"", "", "", "", "", "", "-1.0e-3"}), 1, "BT"},
      {one_way, card1 + row({"", "", "", "", "", "", "", "-9999"}), 1, "DT"},
      {one_way, card1 + blank + row({"-1.0"}), 2, "SFSA"},
      {one_way, card1 + blank + row({"", "-1.0"}), 2, "SFSB"},
      {one_way, card1 + blank + row({"", "", "-0.1"}), 2, "SAST"},
      {one_way, card1 + blank + row({"", "", "", "-0.1"}), 2, "SBST"},
      {one_way, card1 + blank + row({"", "", "", "", "-2.0"}), 2, "SFSAT"},
      {one_way, card1 + blank + row({"", "", "", "", "", "-0.5"}), 2, "SFSBT"},
      {one_way, card1 + blank + row({"", "", "", "", "", "", "-1"}), 2, "FSF"},
      {one_way, card1 + blank + row({"", "", "", "", "", "", "", "-1"}), 2, "VSF"},
      {one_way, card1 + blank + blank + row({"2"}), 3, "SOFT"},
      {one_way, card1 + blank + blank + row({"4"}), 3, "SOFT"},
      {one_way, card1 + blank + blank + row({"1", "1.5"}), 3, "SOFSCL"},
      {one_way, card1 + blank + blank + row({"1", "-0.1"}), 3, "SOFSCL"},
      {"*CONTACT_AUTOMATIC_SINGLE_SURFACE", row({"0"}) + blank + blank + row({"1", "0.7"}), 3, "SOFSCL"},
      {"*CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", row({"1", "1", "3", "3"}) + blank + blank + row({"1", "0.7"}), 3,
       "SOFSCL"},
      {one_way, card1 + blank + blank + row({"", "", "3"}), 3, "LCIDAB"},
      {one_way, card1 + blank + blank + row({"", "", "", "0.9"}), 3, "MAXPAR"},
      {one_way, card1 + blank + blank + row({"", "", "", "", "", "", "-4"}), 3, "BSORT"},
      {one_way, card1 + blank + blank + row({"", "", "", "", "", "", "", "2"}), 3, "FRCFRQ"},
      {one_way, card1 + blank + blank + blank + row({"-0.1"}), 4, "PENMAX"},
      {one_way, card1 + blank + blank + blank + row({"", "1"}), 4, "THKOPT"},
      {one_way, card1 + blank + blank + blank + row({"", "", "3"}), 4, "SHLTHK"},
      {one_way, card1 + blank + blank + blank + row({"", "", "", "2"}), 4, "SNLOG"},
      {one_way, card1 + blank + blank + blank + row({"", "", "", "", "2"}), 4, "ISYM"},
      {one_way, card1 + blank + blank + blank + row({"", "", "", "", "", "1"}), 4, "I2D3D"},
      {one_way, card1 + blank + blank + blank + row({"", "", "", "", "", "", "0.5"}), 4, "SLDTHK"},
      {one_way, card1 + blank + blank + blank + row({"", "", "", "", "", "", "", "-1"}), 4, "SLDSTF"},
      {one_way, card1 + blank + blank + blank + blank + row({"", "1"}), 5, "IGNORE"},
      {one_way, card1 + blank + blank + blank + blank + row({"", "2"}), 5, "IGNORE"},
      {one_way, card1 + blank + blank + blank + blank + row({"", "", "0.5"}), 5, "DPRFAC"},
      {one_way, card1 + blank + blank + blank + blank + row({"", "", "", "-1"}), 5, "DTSTIF"},
      {one_way, card1 + blank + blank + blank + blank + row({"", "", "", "", "1"}), 5, "EDGEK"},
      {one_way, card1 + blank + blank + blank + blank + row({"", "", "", "", "", "", "0.3"}), 5, "FLANGL"},
      {one_way, card1 + blank + blank + blank + blank + row({"", "", "", "", "", "", "", "2"}), 5, "CID_RCF"},
      {one_way, card1 + blank + blank + blank + blank + blank + row({"1"}), 6, "Q2TRI"},
      {one_way, card1 + blank + blank + blank + blank + blank + row({"", "", "", "", "", "", "", "1"}), 6, "SHLEDG"},
      {one_way, card1 + blank + blank + blank + blank + blank + blank + row({"", "", "", "", "0.5"}), 7, "FRICSF"},
      {one_way, card1 + blank + blank + blank + blank + blank + blank + row({"", "", "", "", "", "1"}), 7, "ICOR"},
      {one_way, card1 + blank + blank + blank + blank + blank + blank + blank + row({"1"}), 8, "PSTIFF"},
      {one_way, card1 + blank + blank + blank + blank + blank + blank + blank + row({"", "", "", "1.0"}), 8, "FSTOL"},
      {one_way, card1 + blank + blank + blank + blank + blank + blank + blank + row({"", "", "", "", "", "", "", "3"}),
       8, "TETFAC"},
      {one_way, card1 + blank + blank + blank + blank + blank + blank + blank + blank + row({"", "0.1"}), 9,
       "SHLOFF"},
  };
  for (const auto& c : cases) {
    const std::string message = read_error(folder, c.keyword + "\n" + c.cards);
    EXPECT_EQ(message.rfind(prefix(folder, first + c.card, c.keyword) + "field " + c.field + ": ", 0), 0u)
        << c.keyword << " " << c.field << ": " << message;
  }

  // A few messages in full.
  EXPECT_EQ(read_error(folder, one_way + "\n" + row({"1", "1", "4", "3"}) + row({"-1"})),
            prefix(folder, 3, one_way) +
                "field FS: '-1' takes the coefficients of *PART_CONTACT, which is not supported; give FS and FD here");
  EXPECT_EQ(read_error(folder, one_way + "\n" + row({"0", "1", "3", "3"})),
            prefix(folder, 2, one_way) + "field SURFA: '0' is not an ID (> 0), and SURFATYP 3 names a part by its ID");
  EXPECT_EQ(read_error(folder, one_way + "\n" + row({"1", "1", "4", "3"}) + blank + blank + row({"2"})),
            prefix(folder, 5, one_way) +
                "field SOFT: '2' is not 0 (standard penalty) or 1 (soft constraint): segment-based contact (2) and "
                "the forming options (4, 6) are not implemented");
  EXPECT_EQ(read_error(folder, one_way + "\n" + card1 + blank + blank + blank + blank + row({"", "1"})),
            prefix(folder, 7, one_way) + "field IGNORE: '1': tracking initial penetrations is not implemented");
  EXPECT_EQ(read_error(folder, one_way + "\n" + card1 + blank + blank + blank + row({"", "", "3"})),
            prefix(folder, 6, one_way) + "field SHLTHK: '3' is not 0, 1 or 2");

  // Accepted at their defaults: FRICSF 1, FSTOL 2; SOFSCL up to 1.0 for the nodes-to-surface types.
  const std::string accepted = card1 + blank + blank + row({"1", "1.0"}) + blank + blank + blank +
                               row({"", "", "", "", "1"}) + row({"", "", "", "2"});
  EXPECT_EQ(read_error(folder, one_way + "\n" + accepted), "");
  // Past optional card G: an unexpected line.
  EXPECT_EQ(read_error(folder, one_way + "\n" + accepted + blank + row({"1"}) + "\n"),
            prefix(folder, 12, one_way) +
                "unexpected data line after optional card G; one *CONTACT_AUTOMATIC_NODES_TO_SURFACE defines one "
                "contact");
  EXPECT_EQ(read_error(folder, one_way + "\n"), prefix(folder, 1, one_way) +
                                                    "missing card 1 (SURFA SURFB SURFATYP SURFBTYP SABOXID SBBOXID "
                                                    "SAPR SBPR)");
}

TEST(keyword_contact, MppAndIdCards) {
  DeckFolder folder;
  const std::string card1 = row({"1", "1", "4", "3"});
  EXPECT_EQ(read_error(folder, "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_MPP\n" + row({"1"}) + card1),
            prefix(folder, 2, "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_MPP") +
                "field IGNORE: '1': tracking initial penetrations is not implemented");
  EXPECT_EQ(read_error(folder, "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_MPP\n" + row({"0", "abc"}) + card1),
            prefix(folder, 2, "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_MPP") +
                "field BCKT: cannot read 'abc' as an integer");
  EXPECT_EQ(read_error(folder, "*CONTACT_NODES_TO_SURFACE_ID\n" + row({"-3"}) + card1),
            prefix(folder, 2, "*CONTACT_NODES_TO_SURFACE_ID") + "field CID: '-3' is negative");
  const auto twice = read_error(folder, "*CONTACT_NODES_TO_SURFACE_ID\n" + row({"3"}) + card1 +
                                            "*CONTACT_AUTOMATIC_SINGLE_SURFACE_TITLE\n" + row({"3"}) + row({"0"}));
  EXPECT_EQ(twice, prefix(folder, 5, "*CONTACT_AUTOMATIC_SINGLE_SURFACE_TITLE") +
                       "field CID: contact 3 is defined twice (first at " +
                       (folder.path() / "bad.k").lexically_normal().string() + ":3)");
  // CID 0 (or blank) is allowed more than once: such contacts are numbered in deck order.
  EXPECT_EQ(read_error(folder, "*CONTACT_NODES_TO_SURFACE_ID\n" + row({"0"}) + card1 +
                                   "*CONTACT_NODES_TO_SURFACE_ID\n" + row({""}) + card1),
            "");
}

// Every other *CONTACT_ keyword, and spellings LS-DYNA does not have, stay unsupported: the check
// then refuses them as physics.
TEST(keyword_contact, OtherContactsStayUnsupported) {
  DeckFolder folder;
  std::string deck = "*KEYWORD\n";
  const std::vector<std::string> others = {
      "*CONTACT_TIED_SURFACE_TO_SURFACE", "*CONTACT_ERODING_NODES_TO_SURFACE_SMOOTH",
      "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_SMOOTH", "*CONTACT_FORCE_TRANSDUCER_PENALTY_ID",
      "*CONTACT_2D_AUTOMATIC_SINGLE_SURFACE", "*CONTACT_AUTOMATIC_ONE_WAY_SURFACE_TO_SURFACE",
      "*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID_ID", "*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID_TITLE",
      "*CONTACT_SURFACE_TO_SURFACE", "*CONTACT_AUTOMATIC_GENERAL"};
  for (const auto& keyword : others) deck += keyword + "\n" + row({"1", "2", "3", "3"}) + row({"0.2"}) + row({});
  const auto path = folder.write("others.k", deck + "*END\n");
  const auto model = read_deck(path);
  ASSERT_EQ(model.unsupported.size(), others.size());
  for (std::size_t k = 0; k < others.size(); ++k) EXPECT_EQ(model.unsupported[k].keyword, others[k]);
  EXPECT_TRUE(model.contacts.empty());
  EXPECT_EQ(input_error_of([&] { refuse_unsupported_physics(model, {}); }),
            path.string() + ":2: *CONTACT_TIED_SURFACE_TO_SURFACE: not supported by Spall, and it defines physics: "
                            "running without it would solve another problem (`spall run --skip "
                            "CONTACT_TIED_SURFACE_TO_SURFACE` runs without it, knowingly)");
}

TEST(keyword_contact, ValidateNamesTheMissingSurface) {
  DeckFolder folder;
  const int line = next_line(base_deck) + 1;
  const std::string n2s = "*CONTACT_AUTOMATIC_NODES_TO_SURFACE";
  EXPECT_EQ(validate_error(folder, base_deck + n2s + "\n" + row({"9", "1", "4", "3"})),
            prefix(folder, line, n2s) + "SURFA: node set 9 is not defined");
  EXPECT_EQ(validate_error(folder, base_deck + n2s + "\n" + row({"1", "6", "4", "0"})),
            prefix(folder, line, n2s) + "SURFB: segment set 6 is not defined");
  EXPECT_EQ(validate_error(folder, base_deck + n2s + "\n" + row({"1", "4", "4", "2"})),
            prefix(folder, line, n2s) + "SURFB: part set 4 is not defined");
  EXPECT_EQ(validate_error(folder, base_deck + n2s + "\n" + row({"1", "2", "4", "3"})),
            prefix(folder, line, n2s) + "SURFB: part 2 is not defined");
  EXPECT_EQ(validate_error(folder, base_deck + n2s + "\n" + row({"1", "8", "4", "6"})),
            prefix(folder, line, n2s) + "SURFB: part set 8 is not defined");
  EXPECT_EQ(validate_error(folder, base_deck + "*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID\n" + row({"4"}) +
                                       row({"12", "", "2"})),
            prefix(folder, line + 1, "*CONTACT_AUTOMATIC_SINGLE_SURFACE_ID") + "SURFA: part set 12 is not defined");
  // Side A "all" and side B a part that exists: valid.
  EXPECT_EQ(validate_error(folder, base_deck + n2s + "\n" + row({"", "1", "5", "3"})), "");
}

TEST(keyword_contact, ControlContactDefaultsValuesAndRefusals) {
  DeckFolder folder;
  {
    const auto model = read_deck(folder.write("control.k", "*CONTROL_CONTACT\n" + row({})));
    ASSERT_TRUE(model.control_contact);
    EXPECT_EQ(model.control_contact->slsfac, 0.1);
    EXPECT_EQ(model.control_contact->penopt, 1);
    EXPECT_EQ(model.control_contact->xpene, 4.0);
    EXPECT_EQ(model.control_contact->ignore, 0);
    EXPECT_EQ(model.control_contact->where.line, 2);
  }
  {
    // Every card, with the accepted fields set: rigid-wall penalty, initial check, shell options,
    // reorientation, search interval, *PART_CONTACT defaults, friction energy, cards 5-7.
    const auto model = read_deck(folder.write(
        "control.k", "*CONTROL_CONTACT\n" + row({"0.05", "1.0", "2", "1", "3", "1", "2", "0"}) +
                         row({"0", "0", "10", "1", "6.0", "1", "1", "1"}) +
                         row({"0.1", "0.1", "1", "1", "1", "1", "1", "1"}) + row({"0", "1", "1", "1", "1", "1"}) +
                         row({"0", "1", "1", "1.0", "1.0"}) + row({"1", "1", "1", "1", "1"}) + row({"1"})));
    ASSERT_TRUE(model.control_contact);
    EXPECT_EQ(model.control_contact->slsfac, 0.05);
    EXPECT_EQ(model.control_contact->penopt, 3);
    EXPECT_EQ(model.control_contact->xpene, 6.0);
  }
  const std::string keyword = "*CONTROL_CONTACT";
  const std::string blank = row({});
  EXPECT_EQ(read_error(folder, keyword + "\n" + row({"-0.1"})),
            prefix(folder, 2, keyword) + "field SLSFAC: '-0.1' is negative");
  EXPECT_EQ(read_error(folder, keyword + "\n" + row({"", "", "", "", "4"})),
            prefix(folder, 2, keyword) +
                "field PENOPT: '4': the area- or mass-weighted node stiffness (for metal forming) is not implemented");
  EXPECT_EQ(read_error(folder, keyword + "\n" + row({"", "", "", "", "6"})),
            prefix(folder, 2, keyword) + "field PENOPT: '6' is not 0 to 5");
  EXPECT_EQ(read_error(folder, keyword + "\n" + row({"", "", "", "", "", "", "", "1"})),
            prefix(folder, 2, keyword) +
                "field ENMASS: '1': eroded nodes always leave the contact in Spall (ENMASS 0)");
  EXPECT_EQ(read_error(folder, keyword + "\n" + blank + row({"4"})),
            prefix(folder, 3, keyword) + "field USRSTR: '4': user contact subroutines are not supported");
  EXPECT_EQ(read_error(folder, keyword + "\n" + blank + row({"", "4"})),
            prefix(folder, 3, keyword) + "field USRFRC: '4': user friction subroutines are not supported");
  EXPECT_EQ(read_error(folder, keyword + "\n" + blank + row({"", "", "", "", "-1"})),
            prefix(folder, 3, keyword) + "field XPENE: '-1' is negative");
  EXPECT_EQ(read_error(folder, keyword + "\n" + blank + blank + blank + blank + row({"-1"})),
            prefix(folder, 6, keyword) + "field ISYM: '-1' is not 0 or 1");
  EXPECT_EQ(read_error(folder, keyword + "\n" + blank + blank + blank + blank + blank + blank + blank + row({"1"})),
            prefix(folder, 9, keyword) + "unexpected data line after card 7");
  EXPECT_EQ(read_error(folder, keyword + "\n" + blank + keyword + "\n" + blank),
            prefix(folder, 4, keyword) + "given twice (first at " +
                (folder.path() / "bad.k").lexically_normal().string() + ":2)");

  // IGNORE (card 4) is kept: harmless without a contact, refused by validate() with one.
  const std::string ignoring = "*CONTROL_CONTACT\n" + blank + blank + blank + row({"1"});
  EXPECT_EQ(validate_error(folder, base_deck + ignoring), "");
  EXPECT_EQ(validate_error(folder, base_deck + ignoring + "*CONTACT_NODES_TO_SURFACE\n" + row({"1", "1", "4", "3"})),
            prefix(folder, next_line(base_deck) + 1, keyword) +
                "IGNORE (card 4) = 1 would make *CONTACT_NODES_TO_SURFACE (" +
                (folder.path() / "bad.k").lexically_normal().string() + ":" +
                std::to_string(next_line(base_deck) + 6) +
                ") track initial penetrations, which is not implemented; leave it 0");
}

TEST(keyword_contact, SetSegment) {
  DeckFolder folder;
  const auto model = read_deck(folder.write(
      "segments.k", "*SET_SEGMENT\n" + row({"5", "0.0", "0.0", "0.0", "0.0", "MECH"}) + row({"1", "2", "3", "4"}) +
                        row({"4", "3", "6"}) + "\n" + row({"1", "7", "8", "0", "1.0", "2.0"}) +
                        row({"9", "8", "7", "7"}) + "*SET_SEGMENT_TITLE\nskin of the plate\n" + row({"6"}) +
                        row({"11", "12", "13", "14"})));
  ASSERT_EQ(model.segment_sets.size(), 2u);
  const auto& set = model.segment_sets.at(5);
  EXPECT_EQ(set.id, 5);
  EXPECT_EQ(set.where.line, 2);
  ASSERT_EQ(set.segments.size(), 4u);
  EXPECT_EQ(set.segments[0], (std::array<Id, 4>{1, 2, 3, 4}));
  EXPECT_EQ(set.segments[1], (std::array<Id, 4>{4, 3, 6, 6}));  // N4 blank: a triangle
  EXPECT_EQ(set.segments[2], (std::array<Id, 4>{1, 7, 8, 8}));  // N4 0
  EXPECT_EQ(set.segments[3], (std::array<Id, 4>{9, 8, 7, 7}));  // N4 = N3
  EXPECT_EQ(model.segment_sets.at(6).segments.at(0), (std::array<Id, 4>{11, 12, 13, 14}));
  EXPECT_EQ(model.segment_sets.at(6).where.line, 10);

  const std::string keyword = "*SET_SEGMENT";
  const std::string header = keyword + "\n" + row({"5"});
  EXPECT_EQ(read_error(folder, header + row({"1", "0", "3"})),
            prefix(folder, 3, keyword) + "field N2: '0' is not a node ID (> 0)");
  EXPECT_EQ(read_error(folder, header + row({"1", "", "3"})),
            prefix(folder, 3, keyword) + "field N2: is blank but has no default; a value is required");
  EXPECT_EQ(read_error(folder, header + row({"1", "2", "3", "-4"})),
            prefix(folder, 3, keyword) + "field N4: '-4' is not a node ID (> 0)");
  EXPECT_EQ(read_error(folder, header + row({"1", "2", "1", "4"})),
            prefix(folder, 3, keyword) +
                "field N3: '1' repeats N1: a segment has 3 or 4 different nodes (a triangle repeats N3 as N4, or "
                "leaves N4 blank)");
  EXPECT_EQ(read_error(folder, header + row({"1", "2", "3", "2"})).rfind(
                prefix(folder, 3, keyword) + "field N4: '2' repeats N2", 0),
            0u);
  EXPECT_EQ(read_error(folder, header), prefix(folder, 2, keyword) + "segment set 5 has no segment");
  EXPECT_EQ(read_error(folder, header + row({"1", "2", "3"}) + header + row({"1", "2", "3"})),
            prefix(folder, 5, keyword) + "segment set 5 is defined twice (first at " +
                (folder.path() / "bad.k").lexically_normal().string() + ":2)");
  // validate: the nodes exist.
  EXPECT_EQ(validate_error(folder, base_deck + "*SET_SEGMENT_TITLE\nskin\n" + row({"6"}) + row({"1", "2", "17"})),
            prefix(folder, next_line(base_deck) + 2, keyword) + "segment set 6: node 17 is not defined");
}

TEST(keyword_contact, DatabaseRcforc) {
  DeckFolder folder;
  const auto model = read_deck(folder.write("rcforc.k", "*DATABASE_RCFORC\n" + row({"1.0e-5", "1", "", ""})));
  ASSERT_TRUE(model.rcforc);
  EXPECT_EQ(model.rcforc->dt, 1.0e-5);
  EXPECT_EQ(model.rcforc->lcdt, 0);
  EXPECT_EQ(model.rcforc->ioopt, 1);  // blank -> 1
  EXPECT_EQ(model.rcforc->where.line, 2);
  EXPECT_FALSE(model.rwforc);
  EXPECT_EQ(read_error(folder, "*DATABASE_RCFORC\n" + row({"-1.0"})),
            prefix(folder, 2, "*DATABASE_RCFORC") + "field DT: '-1.0' is negative");
  EXPECT_EQ(read_error(folder, "*DATABASE_RCFORC\n" + row({"1.0e-5", "1", "0", "4"})),
            prefix(folder, 2, "*DATABASE_RCFORC") + "field IOOPT: '4' is not 1, 2 or 3");
  EXPECT_EQ(validate_error(folder, base_deck + "*DATABASE_RCFORC\n" + row({"0.0", "1", "7", "1"})),
            prefix(folder, next_line(base_deck) + 1, "*DATABASE_RCFORC") + "LCUR: curve 7 is not defined");
}

TEST(keyword_contact, DatabaseRcforcMoment) {
  // CID NODESA NODESB, one card per contact; the nodes are resolved, and the contact found, when
  // the problem is built (test_examples runs a deck with it and reads the point from rcforc.csv).
  DeckFolder folder;
  const auto model =
      read_deck(folder.write("moment.k", "*DATABASE_RCFORC_MOMENT\n" + row({"1", "0", "12"}) + row({"4", "3"})));
  ASSERT_EQ(model.rcforc_moments.size(), 2u);
  EXPECT_EQ(model.rcforc_moments[0].cid, 1);
  EXPECT_EQ(model.rcforc_moments[0].nodes_a, 0);
  EXPECT_EQ(model.rcforc_moments[0].nodes_b, 12);
  EXPECT_EQ(model.rcforc_moments[1].nodes_a, 3);
  EXPECT_EQ(model.rcforc_moments[1].nodes_b, 0);  // blank
  EXPECT_EQ(model.rcforc_moments[1].where.line, 3);
  EXPECT_EQ(read_error(folder, "*DATABASE_RCFORC_MOMENT\n" + row({"0", "1"})),
            prefix(folder, 2, "*DATABASE_RCFORC_MOMENT") + "field CID: '0' must be greater than 0");
  EXPECT_EQ(read_error(folder, "*DATABASE_RCFORC_MOMENT\n" + row({"1", "-2"})),
            prefix(folder, 2, "*DATABASE_RCFORC_MOMENT") + "field NODESA: '-2' is negative");
}

// The public deck pydyna_mech.k (shared/, beside the checkout; absent in a plain clone): its
// *CONTACT_NODES_TO_SURFACE, *CONTROL_CONTACT and *DATABASE_RCFORC as written there.
TEST(keyword_contact, PublicPydynaMechDeck) {
  const auto path = std::filesystem::path(SPALL_SHARED_DIR) / "decks" / "public" / "pydyna_mech.k";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << path.string() << " is absent (a clone without ../shared)";
  const auto model = read_deck(path);
  ASSERT_EQ(model.contacts.size(), 1u);
  const auto& c = model.contacts[0];
  EXPECT_EQ(c.kind, Contact::Kind::nodes_to_surface);
  EXPECT_EQ(c.keyword, "*CONTACT_NODES_TO_SURFACE");
  EXPECT_EQ(c.id, 0);
  EXPECT_EQ(c.a.type, ContactSurface::Type::part);
  EXPECT_EQ(c.a.id, 3);
  EXPECT_EQ(c.b.type, ContactSurface::Type::part);
  EXPECT_EQ(c.b.id, 2);
  EXPECT_EQ(c.fs, 0.5);
  EXPECT_EQ(c.fd, 0.5);
  EXPECT_EQ(c.dc, 0.0);
  EXPECT_EQ(c.vdc, 0.0);
  EXPECT_EQ(c.death, 1.0e20);  // 0.0 -> 1e20
  EXPECT_EQ(c.sfsa, 1.0);
  EXPECT_EQ(c.sfsb, 0.06667);
  EXPECT_EQ(c.fsf, 1.0);
  EXPECT_EQ(c.vsf, 1.0);
  EXPECT_EQ(c.where.line, 61);
  EXPECT_EQ(c.where_card2.line, 63);
  EXPECT_EQ(c.where_card3.line, 65);
  ASSERT_TRUE(model.control_contact);
  EXPECT_EQ(model.control_contact->slsfac, 0.1);  // 0.0 -> 0.1
  EXPECT_EQ(model.control_contact->penopt, 1);    // 0 -> 1
  EXPECT_EQ(model.control_contact->xpene, 4.0);   // 0.0 -> 4
  EXPECT_EQ(model.control_contact->ignore, 1);
  EXPECT_EQ(model.control_contact->where.line, 10);
  ASSERT_TRUE(model.rcforc);
  EXPECT_EQ(model.rcforc->dt, 2.0e-4);
  EXPECT_EQ(model.rcforc->ioopt, 1);
}

}  // namespace
}  // namespace spall::io::keyword
