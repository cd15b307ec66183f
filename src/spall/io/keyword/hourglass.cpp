// *HOURGLASS, *CONTROL_HOURGLASS (fem-contact.md §1.2).
#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {
// IHQ 0-5 run (solid_elements.hpp); 6-10 are the assumed-strain and enhanced forms Spall does
// not have, refused where they are written.
int hourglass_type(const Card& card, int field) {
  const auto ihq = card.integer(field, "IHQ", 0);
  if (ihq >= 6 && ihq <= 10)
    card.fail("IHQ", quoted(card.text(field)) +
                         ": not implemented (Spall has 1 viscous, 2-3 Flanagan-Belytschko viscous and 4-5 "
                         "Flanagan-Belytschko stiffness forms)");
  if (ihq < 0 || ihq > 10) card.fail("IHQ", quoted(card.text(field)) + " is not an hourglass type (0 to 10)");
  return static_cast<int>(ihq);
}

Real coefficient(const Card& card, int field, std::string_view name, Real fallback) {
  const Real value = card.real(field, name, fallback);
  if (value < 0) card.fail(name, quoted(card.text(field)) + " is negative");
  return value;
}
}  // namespace

void read_hourglass(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    const Card card = cursor.next(standard_fields, "card 1 (HGID IHQ QM IBQ Q1 Q2 QB/VDC QW)");
    model::Hourglass hourglass;
    hourglass.id = card.required_integer(0, "HGID");
    hourglass.ihq = hourglass_type(card, 1);
    hourglass.qm = coefficient(card, 2, "QM", 0.1);
    if (hourglass.qm == 0) hourglass.qm = 0.1;  // LS-DYNA reads a 0 as the default
    hourglass.q1 = coefficient(card, 4, "Q1", 0.0);
    hourglass.q2 = coefficient(card, 5, "Q2", 0.0);
    hourglass.where = card.where();
    insert_unique(model.hourglasses, hourglass.id, hourglass, card, "hourglass");
  }
}

void read_control_hourglass(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (IHQ QH)");
  if (model.control_hourglass)
    card.context().fail(card.line(), "given twice (first at " + to_string(model.control_hourglass->where) + ")");
  model::ControlHourglass control;
  control.ihq = hourglass_type(card, 0);
  control.qh = coefficient(card, 1, "QH", 0.1);
  if (control.qh == 0) control.qh = 0.1;
  control.where = card.where();
  model.control_hourglass = control;
}

}  // namespace spall::io::keyword
