// *SECTION_SOLID, *SECTION_SPH, *MAT_ELASTIC (001), *MAT_RIGID (020).
#include "spall/io/keyword/keyword_readers.hpp"

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
    section.elform = static_cast<int>(card.integer(1, "ELFORM", 1));
    if (section.elform == 0) section.elform = 1;
    section.aet = static_cast<int>(card.integer(2, "AET", 0));
    section.where = card.where();
    // User-defined elements carry cards 2-5 of integration-point data that Spall cannot use.
    if (section.elform >= 101 && section.elform <= 105)
      card.fail("ELFORM", "user-defined solid element " + std::to_string(section.elform) +
                              " is not supported");
    insert_unique(model.sections, section.id, section, card, "section");
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
    section.sphkern = static_cast<int>(card.integer(7, "SPHKERN", 0));
    section.where = card.where();
    if (section.cslh < 1.0)
      card.fail("CSLH", "CSLH " + std::string(card.text(1)) +
                            " is below 1, which LS-DYNA calls inadmissible (1.05 to 1.3 are usual)");
    if (section.sphkern < 0 || section.sphkern > 3)
      card.fail("SPHKERN", quoted(card.text(7)) + " is not a kernel (0 to 3)");
    insert_unique(model.sections, section.id, section, card, "section");
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
  rigid.con1 = static_cast<int>(card2.integer(1, "CON1", 0));
  rigid.con2 = static_cast<int>(card2.integer(2, "CON2", 0));
  if (rigid.cmo != 0.0 && rigid.cmo != 1.0 && rigid.cmo != -1.0)
    card2.fail("CMO", quoted(card2.text(0)) + ": only 0, +1 and -1 are supported");
  // With CMO = -1, CON1 is a coordinate system and CON2 a digit code: only +1 has codes 0..7.
  if (rigid.cmo == 1.0 && (rigid.con1 < 0 || rigid.con1 > 7))
    card2.fail("CON1", quoted(card2.text(1)) + " is not a constraint code 0..7");
  if (rigid.cmo == 1.0 && (rigid.con2 < 0 || rigid.con2 > 7))
    card2.fail("CON2", quoted(card2.text(2)) + " is not a constraint code 0..7");
  // Card 3 (LCO, or local axes A1..V3) is optional; Spall's rigid bodies use global axes.
  cursor.next_if_any(standard_fields);
  cursor.skip_blank_lines();
  if (!cursor.done())
    cursor.context().fail(cursor.peek().line,
                          "unexpected data line after card 3; one *MAT_RIGID defines one material");
  material.params = rigid;
  insert_unique(model.materials, material.id, std::move(material), card1, "material");
}

}  // namespace spall::io::keyword
