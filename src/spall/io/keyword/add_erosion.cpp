// *MAT_ADD_EROSION (fem-contact.md §1.11): cards 1 and 2, the criteria Spall evaluates; cards 3-5
// (damage models, forming limits, temperature, distortion) are read so that a value there is
// refused rather than dropped.
#include "spall/io/keyword/keyword_readers.hpp"

#include <fmt/format.h>

#include <cmath>
#include <limits>

namespace spall::io::keyword {

void read_mat_add_erosion(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card1 = cursor.next(standard_fields, "card 1 (MID EXCL MXPRES MNEPS EFFEPS VOLEPS NUMFIP NCS)");
  model::MatAddErosion e;
  e.mid = card1.required_integer(0, "MID");
  e.excl = card1.real(1, "EXCL", 0.0);
  e.mxpres = card1.real(2, "MXPRES", 0.0);
  e.mneps = card1.real(3, "MNEPS", 0.0);
  e.effeps = card1.real(4, "EFFEPS", 0.0);
  e.voleps = card1.real(5, "VOLEPS", 0.0);
  e.numfip = card1.real(6, "NUMFIP", 1.0);
  e.ncs = card1.real(7, "NCS", 1.0);
  if (e.numfip == 0) e.numfip = 1;
  if (e.ncs == 0) e.ncs = 1;
  // Compared as reals first: a cast of a value beyond int's range is undefined.
  const auto whole_count = [](Real value) {
    return value >= 1 && value <= std::numeric_limits<int>::max() && value == std::trunc(value);
  };
  if (!whole_count(e.numfip))
    card1.fail("NUMFIP", quoted(card1.text(6)) + ": only a number of integration points (>= 1) is implemented for solids");
  if (!whole_count(e.ncs))
    card1.fail("NCS", quoted(card1.text(7)) + " is not a number of criteria (>= 1)");
  e.where = card1.where();
  if (const auto card2 = cursor.next_if_any(standard_fields)) {
    e.mnpres = card2->real(0, "MNPRES", 0.0);
    e.sigp1 = card2->real(1, "SIGP1", 0.0);
    e.sigvm = card2->real(2, "SIGVM", 0.0);
    e.mxeps = card2->real(3, "MXEPS", 0.0);
    e.epssh = card2->real(4, "EPSSH", 0.0);
    e.sigth = card2->real(5, "SIGTH", 0.0);
    e.impulse = card2->real(6, "IMPULSE", 0.0);
    e.failtm = card2->real(7, "FAILTM", 0.0);
    const auto refuse = [&](int field, const char* name, Real value, const char* what) {
      if (value != 0 && value != e.excl)
        card2->fail(name, quoted(card2->text(field)) + ": " + what + " is not implemented");
    };
    refuse(4, "EPSSH", e.epssh, "the tensorial shear strain criterion");
    refuse(5, "SIGTH", e.sigth, "the Tuler-Butcher threshold stress");
    refuse(6, "IMPULSE", e.impulse, "the Tuler-Butcher stress impulse");
    if (e.mxeps < 0 && e.mxeps != e.excl)
      card2->fail("MXEPS", quoted(card2->text(3)) + ": a curve of the failure strain over the strain rate is not implemented");
    if (e.sigp1 < 0 && e.sigp1 != e.excl)
      card2->fail("SIGP1", quoted(card2->text(1)) + ": a curve of the failure stress over the strain rate is not implemented");
  }
  // Cards 3-5: any value other than blank, 0 or EXCL names a feature Spall does not have.
  static constexpr const char* later_cards[3][8] = {
      {"IDAM", "", "", "", "", "", "", "LCREGD"},
      {"LCFLD", "NSFF", "EPSTHIN", "ENGCRT", "RADCRT", "LCEPS12", "LCEPS13", "LCEPSMX"},
      {"DTEFLT", "VOLFRAC", "MXTMP", "DTMIN", "FFUNC", "DIAGR", "EDGER", ""}};
  for (const auto& names : later_cards) {
    const auto card = cursor.next_if_any(standard_fields);
    if (!card) break;
    for (int field = 0; field < 8; ++field) {
      if (!*names[field] || card->blank(field)) continue;
      const Real value = card->real(field, names[field], 0.0);
      if (value != 0 && value != e.excl)
        card->fail(names[field], quoted(card->text(field)) + ": not implemented (Spall evaluates MXPRES MNEPS EFFEPS "
                                                             "VOLEPS MNPRES SIGP1 SIGVM MXEPS FAILTM)");
    }
  }
  cursor.expect_end("card 5", "one *MAT_ADD_EROSION per material");
  if (model.add_erosions.contains(e.mid))
    card1.context().fail(card1.line(), fmt::format("material {} has a *MAT_ADD_EROSION already (at {})", e.mid,
                                                   to_string(model.add_erosions.at(e.mid).where)));
  model.add_erosions[e.mid] = e;
}

}  // namespace spall::io::keyword
