// *CONTACT_NODES_TO_SURFACE, *CONTACT_AUTOMATIC_NODES_TO_SURFACE, *CONTACT_AUTOMATIC_SURFACE_TO_SURFACE,
// *CONTACT_AUTOMATIC_SINGLE_SURFACE (each with `_ID` or `_TITLE`, and `_MPP`), *CONTACT_ERODING_NODES_TO_SURFACE,
// _SURFACE_TO_SURFACE, _SINGLE_SURFACE and *CONTROL_CONTACT (fem-contact.md §1.6, §1.7). Contact cards:
// [_ID/_TITLE: CID HEADING] / [_MPP: IGNORE BCKT LCBCKT NS2TRK INITITR PARMAX - CPARM8, then `&` CHKSEGS
// PENSF GRPABLE if flagged] / card 1 SURFA SURFB SURFATYP SURFBTYP SABOXID SBBOXID SAPR SBPR / card 2
// FS FD DC VC VDC PENCHK BT DT / card 3 SFSA SFSB SAST SBST SFSAT SFSBT FSF VSF / [ERODING: card 4
// ISYM EROSOP IADJ] / optional cards A to G. Every field is read: a value Spall cannot
// honour is refused naming it, so that no deck runs with a setting silently dropped.
#include <array>
#include <string>
#include <string_view>

#include "spall/io/keyword/keyword_readers.hpp"
#include "spall/io/keyword/numbers.hpp"

namespace spall::io::keyword {

namespace {

using model::Contact;
using model::ContactSurface;

constexpr std::array<int, 2> id_card_fields = {10, 70};

struct ContactType {
  std::string_view name;
  Contact::Kind kind;
  bool eroding = false;
};
// The eroding types search as the automatic ones do (both sides of a segment, PENMAX 0.4).
constexpr ContactType contact_types[] = {
    {"CONTACT_NODES_TO_SURFACE", Contact::Kind::nodes_to_surface},
    {"CONTACT_AUTOMATIC_NODES_TO_SURFACE", Contact::Kind::automatic_nodes_to_surface},
    {"CONTACT_AUTOMATIC_SURFACE_TO_SURFACE", Contact::Kind::automatic_surface_to_surface},
    {"CONTACT_AUTOMATIC_SINGLE_SURFACE", Contact::Kind::automatic_single_surface},
    {"CONTACT_ERODING_NODES_TO_SURFACE", Contact::Kind::automatic_nodes_to_surface, true},
    {"CONTACT_ERODING_SURFACE_TO_SURFACE", Contact::Kind::automatic_surface_to_surface, true},
    {"CONTACT_ERODING_SINGLE_SURFACE", Contact::Kind::automatic_single_surface, true},
};

const ContactType& type_of(std::string_view base) {
  for (const auto& type : contact_types)
    if (type.name == base) return type;
  return contact_types[0];  // not reached: split_contact_keyword only gives these
}

bool nodes_to_surface(Contact::Kind kind) {
  return kind == Contact::Kind::nodes_to_surface || kind == Contact::Kind::automatic_nodes_to_surface;
}

// Blank and 0 read alike in LS-DYNA where the manual gives a non-zero default.
Real zero_means_default(Real value, Real fallback) { return value == 0.0 ? fallback : value; }

Real non_negative(const Card& card, int field, const char* name, Real fallback) {
  const Real value = card.real(field, name, fallback);
  if (value < 0) card.fail(name, quoted(card.text(field)) + " is negative");
  return value;
}

// A field whose only supported value is 0 (or blank); `what` says what another value would ask for.
void refuse_nonzero(const Card& card, int field, const char* name, const std::string& what) {
  if (card.real(field, name, 0.0) != 0.0) card.fail(name, quoted(card.text(field)) + ": " + what);
}

// The MPP cards are tuning of LS-DYNA's distributed-memory search (bucket sorts, search depth,
// parametric extension, grouping): read so that a malformed line is reported, and accepted. IGNORE
// is the exception: it is the same switch as card C's IGNORE ("if IGNORE is set to 1 in any of
// three places, initial penetrations are tracked"), refused for the same reason.
void read_mpp_cards(CardCursor& cursor) {
  const Card card = cursor.next(standard_fields, "MPP card 1 (IGNORE BCKT LCBCKT NS2TRK INITITR PARMAX - CPARM8)");
  refuse_nonzero(card, 0, "IGNORE", "tracking initial penetrations is not implemented");
  card.integer(1, "BCKT", 0);
  card.integer(2, "LCBCKT", 0);
  card.integer(3, "NS2TRK", 0);
  card.integer(4, "INITITR", 0);
  card.real(5, "PARMAX", 0.0);
  card.integer(7, "CPARM8", 0);
  // MPP card 2 is there only when flagged by `&` as its first non-blank character: a lone `&`, since
  // card 1 may start with a *PARAMETER reference (`&surfa`), which is not the flag.
  if (cursor.done()) return;
  const std::string_view text = trim(cursor.peek().text);
  if (text.empty() || text.front() != '&' || (text.size() > 1 && text[1] != ' ' && text[1] != '\t' && text[1] != ','))
    return;
  const Card card2 = cursor.next(standard_fields, "MPP card 2 (& CHKSEGS PENSF GRPABLE)");
  card2.integer(1, "CHKSEGS", 0);
  card2.real(2, "PENSF", 0.0);
  card2.integer(3, "GRPABLE", 0);
}

const char* surface_type_text(int type) {
  switch (type) {
    case 0: return "a segment set";
    case 2: return "a part set";
    case 3: return "a part";
    case 4: return "a node set";
    case 6: return "a part set of exempted parts";
  }
  return "";
}

// Side A (SURFA, SURFATYP, SABOXID, SAPR: fields 0, 2, 4, 6) or side B (1, 3, 5, 7) of card 1.
ContactSurface read_surface(const Card& card, int side, Contact::Kind kind) {
  const bool a = side == 0;
  const char* id_name = a ? "SURFA" : "SURFB";
  const char* type_name = a ? "SURFATYP" : "SURFBTYP";
  const int type = card.int32(2 + side, type_name, 0);
  const std::string type_text = quoted(card.text(2 + side));
  if (type == 1)
    card.fail(type_name,
              type_text + ": shell element sets (*SET_SHELL) are not read; give the shells' part or part set");
  if (type == 7) card.fail(type_name, type_text + ": branches (*SET_PART_TREE) are not supported");
  if (type == 4 && !a)
    card.fail(type_name, type_text + ": a node set is a side A type only (the nodes that meet side B's segments)");
  if (type == 4 && !nodes_to_surface(kind))
    card.fail(type_name, type_text + ": a node set is for the nodes-to-surface types; this one needs segments on "
                                     "side A");
  if (type < 0 || type > 6)
    card.fail(type_name, type_text + " is not 0 (segment set), 2 (part set), 3 (part)" + (a ? ", 4 (node set)" : "") +
                             ", 5 (all) or 6 (all parts but a part set)");
  refuse_nonzero(card, 4 + side, a ? "SABOXID" : "SBBOXID",
                 "boxes (*DEFINE_BOX) and contact volumes are not supported");
  refuse_nonzero(card, 6 + side, a ? "SAPR" : "SBPR",
                 "the NCFORC / INTFOR output of this side's nodal forces is not written by Spall");

  ContactSurface surface;
  surface.type = static_cast<ContactSurface::Type>(type);
  surface.where = card.where();
  if (surface.type == ContactSurface::Type::all) return surface;  // SURFA/SURFB unused
  surface.id = card.integer(side, id_name, 0);
  // The manual: "SURFA EQ.0: includes all parts in the case of single surface contact types".
  if (surface.id == 0 && kind == Contact::Kind::automatic_single_surface) {
    surface.type = ContactSurface::Type::all;
    return surface;
  }
  if (surface.id <= 0)
    card.fail(id_name, (card.blank(side) ? std::string("is blank") : quoted(card.text(side)) + " is not an ID (> 0)") +
                           ", and " + type_name + " " + std::to_string(type) + " names " + surface_type_text(type) +
                           " by its ID");
  return surface;
}

void read_card2(const Card& card, Contact& contact) {
  contact.fs = card.real(0, "FS", 0.0);
  if (contact.fs == -1.0)
    card.fail("FS", quoted(card.text(0)) + " takes the coefficients of *PART_CONTACT, which is not supported; give "
                                           "FS and FD here");
  if (contact.fs == 2.0)
    card.fail("FS", quoted(card.text(0)) + " makes FD a *DEFINE_TABLE of the coefficient by pressure and sliding "
                                           "speed, which Spall does not read");
  if (contact.fs < 0)
    card.fail("FS", quoted(card.text(0)) + " is negative (-2: *DEFINE_FRICTION tables are not supported)");
  contact.fd = non_negative(card, 1, "FD", 0.0);
  contact.dc = non_negative(card, 2, "DC", 0.0);
  contact.vc = non_negative(card, 3, "VC", 0.0);
  contact.vdc = non_negative(card, 4, "VDC", 0.0);
  if (contact.vdc > 100) card.fail("VDC", quoted(card.text(4)) + " is above 100 (percent of critical damping)");
  if (card.integer(5, "PENCHK", 0) != 0)
    card.fail("PENCHK", quoted(card.text(5)) + ": the small-penetration search is not implemented (only 0)");
  // Negative BT and DT are dynamic-relaxation settings (and DT -9999 a curve of birth and death
  // times); Spall has no dynamic relaxation phase.
  contact.birth = card.real(6, "BT", 0.0);
  if (contact.birth < 0)
    card.fail("BT", quoted(card.text(6)) + ": a negative birth time (followed during dynamic relaxation) is not "
                                           "supported");
  contact.death = zero_means_default(card.real(7, "DT", 0.0), 1.0e20);
  if (contact.death < 0)
    card.fail("DT", quoted(card.text(7)) + ": a negative death time (dynamic relaxation; -9999 a curve of birth "
                                           "and death times) is not supported");
}

void read_card3(const Card& card, Contact& contact) {
  contact.sfsa = zero_means_default(non_negative(card, 0, "SFSA", 0.0), 1.0);
  contact.sfsb = zero_means_default(non_negative(card, 1, "SFSB", 0.0), 1.0);
  // The contact thickness of each side's shell segments: SAST / SBST when given, else the shells'
  // own, scaled by SFSAT / SFSBT.
  contact.sast = non_negative(card, 2, "SAST", 0.0);
  contact.sbst = non_negative(card, 3, "SBST", 0.0);
  contact.sfsat = zero_means_default(non_negative(card, 4, "SFSAT", 0.0), 1.0);
  contact.sfsbt = zero_means_default(non_negative(card, 5, "SFSBT", 0.0), 1.0);
  contact.fsf = zero_means_default(non_negative(card, 6, "FSF", 0.0), 1.0);
  contact.vsf = zero_means_default(non_negative(card, 7, "VSF", 0.0), 1.0);
}

// Card 4 of the eroding types: ISYM 1 leaves out the faces on symmetry planes; EROSOP 1 keeps the
// faces inside the body, each to become a segment when the element beyond it erodes (0: the body's
// outer faces only, each leaving with its element); IADJ 1 takes a face shared with another part's
// element as a boundary of the side.
void read_eroding_card(const Card& card, Contact& contact) {
  contact.isym = card.zero_or_one(0, "ISYM");
  contact.erosop = card.zero_or_one(1, "EROSOP");
  contact.iadj = card.zero_or_one(2, "IADJ");
}

void read_card_a(const Card& card, Contact& contact) {
  const auto soft = card.integer(0, "SOFT", 0);
  if (soft != 0 && soft != 1)
    card.fail("SOFT", quoted(card.text(0)) + " is not 0 (standard penalty) or 1 (soft constraint): segment-based "
                                             "contact (2) and the forming options (4, 6) are not implemented");
  contact.soft = static_cast<int>(soft);
  contact.sofscl = zero_means_default(card.real(1, "SOFSCL", 0.0), 0.1);
  // The manual calls SOFSCL above 0.5 inadmissible for single surface and above 1.0 for a one-way
  // treatment. A surface-to-surface contact is two-way, each pair met from both sides as in single
  // surface, so it takes the 0.5 bound too.
  const Real largest = nodes_to_surface(contact.kind) ? 1.0 : 0.5;
  if (!(contact.sofscl > 0) || contact.sofscl > largest)
    card.fail("SOFSCL", quoted(card.text(1)) + " is not in (0, " + (largest == 1.0 ? "1.0" : "0.5") +
                            "], which the manual calls admissible for this contact type");
  refuse_nonzero(card, 2, "LCIDAB", "the airbag-fabric curve of soft-constraint contact is not supported");
  contact.maxpar = zero_means_default(card.real(3, "MAXPAR", 0.0), 1.025);
  if (contact.maxpar < 1) card.fail("MAXPAR", quoted(card.text(3)) + " is below 1 (the segment's own extent)");
  // SBOPT and DEPTH act only with SOFT 2, refused above.
  card.integer(4, "SBOPT", 0);
  card.integer(5, "DEPTH", 0);
  // BSORT: LS-DYNA's cycles between bucket sorts. Spall sorts every cycle, which any BSORT allows.
  contact.bsort = card.int32(6, "BSORT", 0);
  if (contact.bsort < 0) card.fail("BSORT", quoted(card.text(6)) + ": a curve of the sort interval is not supported");
  const auto frcfrq = card.integer(7, "FRCFRQ", 0);
  if (frcfrq != 0 && frcfrq != 1)
    card.fail("FRCFRQ", quoted(card.text(7)) + ": Spall updates contact forces every cycle (only 0 or 1)");
}

void read_card_b(const Card& card, Contact& contact) {
  contact.penmax = non_negative(card, 0, "PENMAX", 0.0);
  refuse_nonzero(card, 1, "THKOPT", "the thickness options of shell segments are not implemented");
  if (!card.blank(2)) {
    const auto shlthk = card.integer(2, "SHLTHK", 0);
    if (shlthk < 0 || shlthk > 2) card.fail("SHLTHK", quoted(card.text(2)) + " is not 0, 1 or 2");
    contact.shlthk = static_cast<int>(shlthk);
  }
  // SNLOG 1 switches off LS-DYNA's shooting-node logic, a detail of its search.
  card.zero_or_one(3, "SNLOG");
  // ISYM blank: card 4's (eroding types), else *CONTROL_CONTACT's.
  if (!card.blank(4)) contact.isym = card.zero_or_one(4, "ISYM");
  refuse_nonzero(card, 5, "I2D3D", "it prefers solid faces to shells on the same segment, which Spall does not "
                                   "compare");
  refuse_nonzero(card, 6, "SLDTHK", "a contact thickness of solid segments is not implemented");
  contact.sldstf = non_negative(card, 7, "SLDSTF", 0.0);
}

void read_card_c(const Card& card, Contact& contact) {
  card.integer(0, "IGAP", 0);  // acts with SOFT 2 (refused) and mortar contact only
  refuse_nonzero(card, 1, "IGNORE", "tracking initial penetrations is not implemented");
  refuse_nonzero(card, 2, "DPRFAC", "the penetration-depth reduction of segment-based contact is not implemented");
  contact.dtstif = non_negative(card, 3, "DTSTIF", 0.0);
  refuse_nonzero(card, 4, "EDGEK", "the edge-to-edge stiffness of segment-based contact is not implemented");
  refuse_nonzero(card, 6, "FLANGL", "the flange angle of segment-based contact is not implemented");
  refuse_nonzero(card, 7, "CID_RCF", "RCFORC in a local coordinate system is not supported");
}

// Optional cards D to G: options of segment-based, tied, forming, beam and shell contact. Each is
// accepted only at its default (blank or 0; FRICSF 1; FSTOL 2), so that none is dropped unnoticed.
void read_cards_d_to_g(CardCursor& cursor) {
  static constexpr const char* names[4][8] = {
      {"Q2TRI", "DTPCHK", "SFNBR", "FNLSCL", "DNLSCL", "TCSO", "TIEDID", "SHLEDG"},
      {"SHAREC", "CPARM8", "IPBACK", "SRNDE", "FRICSF", "ICOR", "FTORQ", "REGION"},
      {"PSTIFF", "IGNROFF", "", "FSTOL", "2DBINR", "SSFTYP", "SWTPR", "TETFAC"},
      {"", "SHLOFF", "", "", "", "", "", ""}};
  for (const auto& card_names : names) {
    const auto card = cursor.next_if_any(standard_fields);
    if (!card) return;
    for (int field = 0; field < 8; ++field) {
      const std::string_view name = card_names[field];
      if (name.empty()) continue;
      const Real value = card->real(field, name, 0.0);
      const bool at_default =
          value == 0.0 || (name == "FRICSF" && value == 1.0) || (name == "FSTOL" && value == 2.0);
      if (!at_default)
        card->fail(name, quoted(card->text(field)) + ": not implemented (optional cards D to G are read only "
                                                     "at their defaults)");
    }
  }
}

}  // namespace

bool split_contact_keyword(std::string_view name, KeywordCall& call) {
  KeywordCall options;
  // The options come off the end, each at most once: LS-DYNA writes _MPP_ID and _ID_MPP alike.
  while (true) {
    bool* option = nullptr;
    std::string_view suffix;
    for (auto [text, flag] : {std::pair{std::string_view("_ID"), &options.id},
                              std::pair{std::string_view("_TITLE"), &options.title},
                              std::pair{std::string_view("_MPP"), &options.mpp}})
      if (name.ends_with(text)) {
        suffix = text;
        option = flag;
      }
    if (!option) break;
    if (*option) return false;  // an option twice is no LS-DYNA spelling
    *option = true;
    name.remove_suffix(suffix.size());
  }
  if (options.id && options.title) return false;  // _TITLE is another name for _ID, not a second card
  for (const auto& type : contact_types)
    if (type.name == name) {
      options.base = type.name;
      call = options;
      return true;
    }
  return false;
}

void read_contact(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  Contact contact;
  const ContactType& type = type_of(call.base);
  contact.kind = type.kind;
  contact.eroding = type.eroding;
  contact.keyword = cursor.context().keyword;
  if (call.id || call.title) {
    const Card card = cursor.next(id_card_fields, "ID card (CID HEADING)");
    // CID 0 or blank: numbered in deck order, as contacts without the option are.
    contact.id = card.integer(0, "CID", 0);
    if (contact.id < 0) card.fail("CID", quoted(card.text(0)) + " is negative");
    contact.heading = std::string(card.text(1));
    for (const auto& other : model.contacts)
      if (contact.id != 0 && other.id == contact.id)
        card.fail("CID", "contact " + std::to_string(contact.id) + " is defined twice (first at " +
                             to_string(other.where) + ")");
  }
  if (call.mpp) read_mpp_cards(cursor);

  const Card card1 = cursor.next(standard_fields, "card 1 (SURFA SURFB SURFATYP SURFBTYP SABOXID SBBOXID SAPR SBPR)");
  contact.where = card1.where();
  contact.a = read_surface(card1, 0, contact.kind);
  // Single surface has side A only: LS-DYNA ignores SURFB, SURFBTYP, SBBOXID and SBPR there.
  if (contact.kind != Contact::Kind::automatic_single_surface) contact.b = read_surface(card1, 1, contact.kind);

  // Cards 2 and 3 may be left out when the block ends: all their fields take the defaults.
  contact.where_card2 = contact.where_card3 = contact.where;
  if (const auto card2 = cursor.next_if_any(standard_fields)) {
    read_card2(*card2, contact);
    contact.where_card2 = card2->where();
  }
  if (const auto card3 = cursor.next_if_any(standard_fields)) {
    read_card3(*card3, contact);
    contact.where_card3 = card3->where();
  }
  if (contact.eroding)
    if (const auto card4 = cursor.next_if_any(standard_fields)) read_eroding_card(*card4, contact);
  if (const auto card = cursor.next_if_any(standard_fields)) read_card_a(*card, contact);
  if (const auto card = cursor.next_if_any(standard_fields)) read_card_b(*card, contact);
  if (const auto card = cursor.next_if_any(standard_fields)) read_card_c(*card, contact);
  read_cards_d_to_g(cursor);

  cursor.expect_end("optional card G", "one " + contact.keyword + " defines one contact");
  model.contacts.push_back(std::move(contact));
}

// *DATABASE_RCFORC_MOMENT: one card CID NODESA NODESB per contact.
void read_database_rcforc_moment(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card = cursor.next(standard_fields, "card (CID NODESA NODESB)");
    model::RcforcMoment moment;
    moment.cid = card.required_integer(0, "CID");
    moment.nodes_a = card.integer(1, "NODESA", 0);
    moment.nodes_b = card.integer(2, "NODESB", 0);
    if (moment.cid <= 0) card.fail("CID", quoted(card.text(0)) + " must be greater than 0");
    if (moment.nodes_a < 0) card.fail("NODESA", quoted(card.text(1)) + " is negative");
    if (moment.nodes_b < 0) card.fail("NODESB", quoted(card.text(2)) + " is negative");
    moment.where = card.where();
    model.rcforc_moments.push_back(moment);
  }
}

void read_control_contact(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card1 = cursor.next(standard_fields, "card 1 (SLSFAC RWPNAL ISLCHK SHLTHK PENOPT THKCHG ORIEN ENMASS)");
  if (model.control_contact)
    card1.context().fail(card1.line(), "given twice (first at " + to_string(model.control_contact->where) + ")");
  model::ControlContact control;
  control.where = card1.where();
  control.slsfac = zero_means_default(non_negative(card1, 0, "SLSFAC", 0.0), 0.1);
  // RWPNAL: the penalty of rigid walls on the nodes of rigid bodies; Spall's walls are kinematic
  // and act on every node alike.
  card1.real(1, "RWPNAL", 0.0);
  // ISLCHK: LS-DYNA's report of initial penetrations at start-up.
  card1.integer(2, "ISLCHK", 0);
  // SHLTHK: the shell thickness in the non-automatic contacts: 0 not, 1 but not of rigid bodies, 2
  // of every shell. Spall's shells are all rigid, so 1 reads as 0.
  const auto shlthk = card1.integer(3, "SHLTHK", 0);
  if (shlthk < 0 || shlthk > 2) card1.fail("SHLTHK", quoted(card1.text(3)) + " is not 0, 1 or 2");
  control.shlthk = static_cast<int>(shlthk);
  const auto penopt = card1.integer(4, "PENOPT", 0);
  if (penopt == 4 || penopt == 5)
    card1.fail("PENOPT", quoted(card1.text(4)) + ": the area- or mass-weighted node stiffness (for metal forming) "
                                                 "is not implemented");
  if (penopt < 0 || penopt > 5) card1.fail("PENOPT", quoted(card1.text(4)) + " is not 0 to 5");
  control.penopt = penopt == 0 ? 1 : static_cast<int>(penopt);
  card1.integer(5, "THKCHG", 0);  // thickness changes of deformable shells: Spall's are rigid
  // ORIEN: LS-DYNA's reorientation of segments at start-up. Spall builds the segments of parts
  // from the faces of solid elements, which always face outward.
  card1.integer(6, "ORIEN", 0);
  refuse_nonzero(card1, 7, "ENMASS", "eroded nodes always leave the contact in Spall (ENMASS 0)");

  // Cards 2 to 7 are optional.
  if (const auto card = cursor.next_if_any(standard_fields)) {
    refuse_nonzero(*card, 0, "USRSTR", "user contact subroutines are not supported");
    refuse_nonzero(*card, 1, "USRFRC", "user friction subroutines are not supported");
    card->integer(2, "NSBCS", 0);   // cycles between searches: Spall searches every cycle
    card->integer(3, "INTERM", 0);  // intermittent search of the old surface-to-surface contact
    control.xpene = zero_means_default(non_negative(*card, 4, "XPENE", 0.0), 4.0);
    // SSTHK: the single-surface contact takes the shells' actual thickness (as SSTHK 1) in Spall.
    card->integer(5, "SSTHK", 0);
    card->integer(6, "ECDT", 0);     // eroding contact's part in the time step
    card->integer(7, "TIEDPRJ", 0);  // tied contact
  }
  // Card 3 SFRIC DFRIC EDC VFC TH TH_SF PEN_SF PTSCL: the defaults of *PART_CONTACT, which the
  // contacts may not use (FS -1 is refused): nothing for them to act on.
  if (const auto card = cursor.next_if_any(standard_fields)) {
    static constexpr const char* names[8] = {"SFRIC", "DFRIC", "EDC", "VFC", "TH", "TH_SF", "PEN_SF", "PTSCL"};
    for (int field = 0; field < 8; ++field) card->real(field, names[field], 0.0);
  }
  if (const auto card = cursor.next_if_any(standard_fields)) {
    // IGNORE: the default of the contacts' IGNORE; validate() refuses it where a contact would use it.
    control.ignore = card->int32(0, "IGNORE", 0);
    card->integer(1, "FRCENG", 0);  // Spall always computes the friction energy
    // SKIPRWG (display of walls), OUTSEG SPOTSTP SPOTDEL SPOTHIN (spot welds), DIR_TIE (tied contact).
  }
  // Card 5 ISYM: the default of the contacts' ISYM (card B). The rest of cards 5 to 7 are options of
  // implicit, thermal, spot-weld, tied, shell and IGA contact.
  if (const auto card = cursor.next_if_any(standard_fields)) control.isym = card->zero_or_one(0, "ISYM");
  cursor.next_if_any(standard_fields);
  cursor.next_if_any(standard_fields);
  cursor.expect_end("card 7");
  model.control_contact = control;
}

}  // namespace spall::io::keyword
