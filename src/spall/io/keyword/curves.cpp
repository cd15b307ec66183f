// *DEFINE_CURVE (+ _TITLE).
#include <array>

#include <fmt/format.h>

#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {
// The points are two 20-character fields, A1 O1, one point per line.
constexpr std::array<int, 2> point_fields = {20, 20};
}  // namespace

void read_define_curve(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card = cursor.next(standard_fields, "card 1 (LCID SIDR SFA SFO OFFA OFFO DATTYP)");
  model::Curve curve;
  curve.id = card.required_integer(0, "LCID");
  curve.sidr = card.int32(1, "SIDR", 0);
  // SFA and SFO: 0 (or blank) means 1.0, as the manual says.
  curve.sfa = card.real(2, "SFA", 0.0);
  if (curve.sfa == 0.0) curve.sfa = 1.0;
  curve.sfo = card.real(3, "SFO", 0.0);
  if (curve.sfo == 0.0) curve.sfo = 1.0;
  curve.offa = card.real(4, "OFFA", 0.0);
  curve.offo = card.real(5, "OFFO", 0.0);
  const auto dattyp = card.integer(6, "DATTYP", 0);
  // DATTYP -2/-1/1/6 give curves of other kinds (e.g. of radius or fabric stress) with their
  // own abscissa meaning; Spall's curves are plain functions.
  if (dattyp != 0)
    card.fail("DATTYP", quoted(card.text(6)) + " is not supported (only 0)");
  curve.where = card.where();
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card point = cursor.next(point_fields, "point card");
    const Real a = point.required_real(0, "A1");
    const Real o = point.real(1, "O1", 0.0);
    if (!curve.points.empty() && a <= curve.points.back().first)
      point.fail("A1", fmt::format("abscissa '{}' does not increase (the previous point is at {:g})",
                                   point.text(0), curve.points.back().first));
    curve.points.emplace_back(a, o);
  }
  if (curve.points.empty())
    card.context().fail(card.line(), "curve " + std::to_string(curve.id) + " has no points");
  insert_unique(model.curves, curve.id, std::move(curve), card, "curve");
}

}  // namespace spall::io::keyword
