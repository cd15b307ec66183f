// *SECTION_SOLID, *SECTION_SOLID_SPG, *SECTION_SPH, *MAT_ELASTIC (001), *MAT_RIGID (020), and the
// IDs of the thermal materials (*MAT_THERMAL_*).
#include "spall/io/keyword/keyword_readers.hpp"

#include <algorithm>
#include <cctype>
#include <iterator>

namespace spall::io::keyword {

namespace {
// LS-DYNA reads a 0 in many real fields as "use the default"; a blank field reads as 0 too.
Real zero_means_default(Real value, Real fallback) { return value == 0.0 ? fallback : value; }
}  // namespace

void read_section_solid(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    const Card card = cursor.next(standard_fields, "card 1 (SECID ELFORM AET)");
    model::SectionSolid section;
    section.id = card.required_integer(0, "SECID");
    section.elform = card.int32(1, "ELFORM", 1);
    if (section.elform == 0) section.elform = 1;
    section.aet = card.int32(2, "AET", 0);
    section.where = card.where();
    // User-defined elements carry cards 2-5 of integration-point data that Spall cannot use.
    if (section.elform >= 101 && section.elform <= 105)
      card.fail("ELFORM", "user-defined solid element " + std::to_string(section.elform) +
                              " is not supported");
    insert_unique(model.sections, section.id, section, card, "section");
  }
}

// Both card layouts read the same columns: R9-R11 manuals call card 2 column 6 LSCALE and column 8
// SWTIME and end card 3 after ITB; current manuals leave column 6 unused, call column 8 MSC and add
// MSFAC ISC BOXID PDAMP. Blank (or 0) DX DY DZ SMSTEP ITB take the manual's KERNEL-dependent
// defaults; what the solver cannot run is refused when the problem is built (solver/problem.cpp).
void read_section_solid_spg(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    const Card card1 = cursor.next(standard_fields, "card 1 (SECID ELFORM AET)");
    model::SectionSolidSpg section;
    section.id = card1.required_integer(0, "SECID");
    section.elform = card1.int32(1, "ELFORM", 0);
    if (section.elform != 47)
      card1.fail("ELFORM", (card1.blank(1) ? std::string("blank") : quoted(card1.text(1))) +
                               ": *SECTION_SOLID_SPG needs ELFORM 47 (SPG)");
    section.aet = card1.int32(2, "AET", 0);
    section.cohoff = card1.real(6, "COHOFF", 0.0);
    section.gaskett = card1.real(7, "GASKETT", 0.0);
    section.where = card1.where();

    const Card card2 = cursor.next(standard_fields, "card 2 (DX DY DZ ISPLINE KERNEL LSCALE SMSTEP SWTIME/MSC)");
    section.kernel = card2.int32(4, "KERNEL", 0);
    if (section.kernel < 0 || section.kernel > 2)
      card2.fail("KERNEL", quoted(card2.text(4)) +
                               " is not a kernel update scheme (0 updated Lagrangian, 1 Eulerian, 2 "
                               "pseudo-Lagrangian)");
    static constexpr Real default_dilation[3] = {1.6, 1.8, 1.5};
    static constexpr int default_smstep[3] = {15, 5, 30};
    static constexpr int default_itb[3] = {1, 1, 2};
    Real* dilation[3] = {&section.dx, &section.dy, &section.dz};
    static constexpr const char* dilation_name[3] = {"DX", "DY", "DZ"};
    for (int d = 0; d < 3; ++d) {
      *dilation[d] = zero_means_default(card2.real(d, dilation_name[d], 0.0), default_dilation[section.kernel]);
      if (*dilation[d] < 1.0)
        card2.fail(dilation_name[d], quoted(card2.text(d)) +
                                         " is below 1.0, which LS-DYNA does not allow (1.4 to 1.8 "
                                         "are recommended)");
    }
    section.ispline = card2.int32(3, "ISPLINE", 0);
    if (section.ispline < 0 || section.ispline > 2)
      card2.fail("ISPLINE", quoted(card2.text(3)) + " is not a kernel function (0, 1 or 2)");
    section.lscale = card2.real(5, "LSCALE", 0.0);
    const int smstep = card2.int32(6, "SMSTEP", 0);
    if (smstep < 0) card2.fail("SMSTEP", quoted(card2.text(6)) + ": the interval must be positive");
    section.smstep = smstep == 0 ? default_smstep[section.kernel] : smstep;
    section.column8 = card2.real(7, "SWTIME/MSC", 0.0);
    section.where_card2 = card2.where();

    const Card card3 = cursor.next(standard_fields, "card 3 (IDAM FS STRETCH ITB ...)");
    section.idam = card3.int32(0, "IDAM", 1);
    static constexpr int known_idam[] = {0, 1, 2, 3, 4, 5, 7, 8, 11, 13};
    if (std::find(std::begin(known_idam), std::end(known_idam), section.idam) == std::end(known_idam))
      card3.fail("IDAM", quoted(card3.text(0)) + " is not a bond-failure option (0-5, 7, 8, 11, 13)");
    section.fs = zero_means_default(card3.real(1, "FS", 0.0), 1.0e10);
    section.stretch = zero_means_default(card3.real(2, "STRETCH", 0.0), 1.0);
    if (section.stretch < 0) card3.fail("STRETCH", quoted(card3.text(2)) + " is negative");
    const auto itb = card3.integer(3, "ITB", 0);
    if (itb < 0 || itb > 3)
      card3.fail("ITB", quoted(card3.text(3)) + " is not a stabilization option (1, 2 or 3)");
    section.itb = itb == 0 ? default_itb[section.kernel] : static_cast<int>(itb);
    section.msfac = card3.real(4, "MSFAC", 0.0);
    const Real isc = card3.real(5, "ISC", 0.0);
    if (isc != 0.0 && isc != 1.0) card3.fail("ISC", quoted(card3.text(5)) + " is not 0 or 1");
    section.isc = static_cast<int>(isc);
    section.boxid = card3.integer(6, "BOXID", 0);
    section.pdamp = zero_means_default(card3.real(7, "PDAMP", 0.0), -0.001);
    section.where_card3 = card3.where();
    insert_unique(model.sections, section.id, section, card1, "section");
  }
}

void read_section_sph(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    const Card card = cursor.next(standard_fields, "card 1 (SECID CSLH HMIN ...)");
    model::SectionSph section;
    section.id = card.required_integer(0, "SECID");
    section.cslh = zero_means_default(card.real(1, "CSLH", 0.0), 1.2);
    section.hmin = zero_means_default(card.real(2, "HMIN", 0.0), 0.2);
    section.hmax = zero_means_default(card.real(3, "HMAX", 0.0), 2.0);
    section.sphini = card.real(4, "SPHINI", 0.0);
    section.death = zero_means_default(card.real(5, "DEATH", 0.0), 1.0e20);
    section.start = card.real(6, "START", 0.0);
    section.sphkern = card.int32(7, "SPHKERN", 0);
    section.where = card.where();
    if (section.cslh < 1.0)
      card.fail("CSLH", "CSLH " + std::string(card.text(1)) +
                            " is below 1, which LS-DYNA calls inadmissible (1.05 to 1.3 are usual)");
    if (section.sphkern < 0 || section.sphkern > 3)
      card.fail("SPHKERN", quoted(card.text(7)) + " is not a kernel (0 to 3)");
    insert_unique(model.sections, section.id, section, card, "section");
  }
}

// Card 1 SECID ELFORM SHRF NIP PROPT QR/IRID ICOMP SETYP, card 2 T1 T2 T3 T4 NLOC MAREA IDOF EDGSET,
// then with ICOMP 1 the NIP layer angles, eight a line. Spall runs shells only as rigid geometry
// (model.hpp): what a rigid part cannot use is read for the layout.
void read_section_shell(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    const Card card1 = cursor.next(standard_fields, "card 1 (SECID ELFORM SHRF NIP PROPT QR ICOMP SETYP)");
    model::SectionShell section;
    section.id = card1.required_integer(0, "SECID");
    const int elform = card1.int32(1, "ELFORM", 2);
    section.elform = elform == 0 ? 2 : elform;
    // These formulations add cards of their own (user integration, meshfree shells).
    if ((section.elform >= 41 && section.elform <= 44) || (section.elform >= 101 && section.elform <= 105))
      card1.fail("ELFORM", quoted(card1.text(1)) + ": this shell formulation's extra cards are not read");
    const std::int64_t nip = card1.integer(3, "NIP", 2);
    const Real icomp = card1.real(6, "ICOMP", 0.0);
    if (icomp != 0.0 && icomp != 1.0) card1.fail("ICOMP", quoted(card1.text(6)) + " is not 0 or 1");
    if (nip < 0 || nip > 100)
      card1.fail("NIP", quoted(card1.text(3)) + " is not a number of integration points (0-100)");
    section.where = card1.where();
    const Card card2 = cursor.next(standard_fields, "card 2 (T1 T2 T3 T4 NLOC MAREA IDOF EDGSET)");
    section.t[0] = card2.real(0, "T1", 0.0);
    if (!(section.t[0] > 0))
      card2.fail("T1", quoted(card2.text(0)) + ": a shell needs a thickness > 0 (its mass and contact surface)");
    for (int k = 1; k < 4; ++k) {
      static constexpr const char* names[] = {"T1", "T2", "T3", "T4"};
      section.t[k] = zero_means_default(card2.real(k, names[k], 0.0), section.t[0]);
      if (!(section.t[k] > 0)) card2.fail(names[k], quoted(card2.text(k)) + ": a thickness must be > 0");
    }
    if (card2.real(4, "NLOC", 0.0) != 0.0)
      card2.fail("NLOC", quoted(card2.text(4)) + ": a reference surface off the mid-surface is not implemented (0)");
    section.marea = card2.real(5, "MAREA", 0.0);
    if (section.marea < 0) card2.fail("MAREA", quoted(card2.text(5)) + ": a mass per area cannot be negative");
    section.where_card2 = card2.where();
    if (icomp == 1.0)
      for (std::int64_t angles = 0; angles < (nip == 0 ? 2 : nip); angles += 8)
        cursor.next(standard_fields, "layer angles");
    insert_unique(model.sections, section.id, section, card1, "section");
  }
}

void read_mat_elastic(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    const Card card = cursor.next(standard_fields, "card 1 (MID RO E PR DA DB)");
    model::Material material;
    material.id = card.required_integer(0, "MID");
    material.keyword = "*MAT_ELASTIC";
    model::MatElastic elastic;
    elastic.ro = card.required_real(1, "RO");
    elastic.e = card.required_real(2, "E");
    elastic.pr = card.real(3, "PR", 0.0);
    elastic.da = card.real(4, "DA", 0.0);
    elastic.db = card.real(5, "DB", 0.0);
    material.params = elastic;
    material.where = card.where();
    insert_unique(model.materials, material.id, std::move(material), card, "material");
  }
}

void read_mat_rigid(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card1 = cursor.next(standard_fields, "card 1 (MID RO E PR N COUPLE M ALIAS)");
  model::Material material;
  material.id = card1.required_integer(0, "MID");
  material.keyword = "*MAT_RIGID";
  model::MatRigid rigid;
  rigid.ro = card1.required_real(1, "RO");
  // E and PR only set the contact penalty stiffness, but LS-DYNA requires them.
  rigid.e = card1.required_real(2, "E");
  rigid.pr = card1.real(3, "PR", 0.0);
  rigid.n = card1.real(4, "N", 0.0);
  rigid.couple = card1.real(5, "COUPLE", 0.0);
  rigid.m = card1.real(6, "M", 0.0);
  // ALIAS (field 8) is a VDA surface name, text that no Spall feature uses.
  material.where = card1.where();

  const Card card2 = cursor.next(standard_fields, "card 2 (CMO CON1 CON2)");
  rigid.cmo = card2.real(0, "CMO", 0.0);
  rigid.con1 = card2.int32(1, "CON1", 0);
  rigid.con2 = card2.int32(2, "CON2", 0);
  if (rigid.cmo != 0.0 && rigid.cmo != 1.0 && rigid.cmo != -1.0)
    card2.fail("CMO", quoted(card2.text(0)) + ": only 0, +1 and -1 are supported");
  // With CMO = -1, CON1 is a coordinate system and CON2 a digit code: only +1 has codes 0..7.
  if (rigid.cmo == 1.0 && (rigid.con1 < 0 || rigid.con1 > 7))
    card2.fail("CON1", quoted(card2.text(1)) + " is not a constraint code 0..7");
  if (rigid.cmo == 1.0 && (rigid.con2 < 0 || rigid.con2 > 7))
    card2.fail("CON2", quoted(card2.text(2)) + " is not a constraint code 0..7");
  // Card 3 (LCO, or local axes A1..V3) is optional; Spall's rigid bodies use global axes.
  cursor.next_if_any(standard_fields);
  cursor.expect_end("card 3", "one *MAT_RIGID defines one material");
  material.params = rigid;
  insert_unique(model.materials, material.id, std::move(material), card1, "material");
}

bool is_thermal_material(std::string_view name) {
  // *MAT_THERMAL_xxx, or its number *MAT_Tnn (the manual's *MAT_T01 to *MAT_T17 ...).
  return name.starts_with("MAT_THERMAL_") ||
         (name.size() >= 7 && name.starts_with("MAT_T") && std::isdigit(static_cast<unsigned char>(name[5])) &&
          std::isdigit(static_cast<unsigned char>(name[6])) && (name.size() == 7 || name[7] == '_'));
}

// TMID on card 1; the thermal properties that follow are not read: Spall runs no thermal solution.
void read_mat_thermal(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card = cursor.next(standard_fields, "card 1 (TMID ...)");
  model::ThermalMaterial thermal;
  thermal.id = card.required_integer(0, "TMID");
  thermal.keyword = card.context().keyword;
  thermal.where = card.where();
  insert_unique(model.thermal_materials, thermal.id, std::move(thermal), card, "thermal material");
}

}  // namespace spall::io::keyword
