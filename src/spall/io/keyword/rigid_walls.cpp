// *RIGIDWALL_PLANAR, _MOVING, _FINITE, _FINITE_MOVING, each with _ID: one wall per keyword.
// Cards (LS-DYNA manual): [_ID: ID TITLE] / NSID NSIDEX BOXID OFFSET BIRTH DEATH RWKSF /
// XT YT ZT XH YH ZH FRIC WVEL / [_FINITE: XHEV YHEV ZHEV LENL LENM] / [_MOVING: MASS V0].
#include <cmath>
#include <fmt/format.h>

#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {
constexpr std::array<int, 2> id_card_fields = {10, 70};

Vec3 read_point(const Card& card, int first, const char* x, const char* y, const char* z) {
  return Vec3(card.real(first, x, 0.0), card.real(first + 1, y, 0.0), card.real(first + 2, z, 0.0));
}

std::string point_text(const Vec3& p) { return fmt::format("({:g}, {:g}, {:g})", p.x(), p.y(), p.z()); }
}  // namespace

void read_rigidwall_planar(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  model::RigidWallPlanar wall;
  wall.keyword = cursor.context().keyword;
  wall.finite = call.base.find("_FINITE") != std::string_view::npos;
  wall.moving = call.base.find("_MOVING") != std::string_view::npos;
  if (call.id) {
    const Card card = cursor.next(id_card_fields, "ID card (ID TITLE)");
    wall.id = card.required_integer(0, "ID");
    if (wall.id <= 0) card.fail("ID", quoted(card.text(0)) + " must be greater than 0");
    wall.title = std::string(card.text(1));
  }

  const Card card1 = cursor.next(standard_fields, "card 1 (NSID NSIDEX BOXID OFFSET BIRTH DEATH RWKSF)");
  wall.where = card1.where();
  wall.nsid = card1.integer(0, "NSID", 0);
  wall.nsidex = card1.integer(1, "NSIDEX", 0);
  wall.boxid = card1.integer(2, "BOXID", 0);
  wall.offset = card1.real(3, "OFFSET", 0.0);
  if (wall.offset < 0) card1.fail("OFFSET", quoted(card1.text(3)) + " is negative");
  wall.birth = card1.real(4, "BIRTH", 0.0);
  // Blank and 0 read alike in LS-DYNA, so 0 takes the defaults DEATH = 1e20, RWKSF = 1.
  wall.death = card1.real(5, "DEATH", 0.0);
  if (wall.death == 0.0) wall.death = 1.0e20;
  wall.rwksf = card1.real(6, "RWKSF", 0.0);
  if (wall.rwksf == 0.0) wall.rwksf = 1.0;

  const Card card2 = cursor.next(standard_fields, "card 2 (XT YT ZT XH YH ZH FRIC WVEL)");
  wall.tail = read_point(card2, 0, "XT", "YT", "ZT");
  wall.head = read_point(card2, 3, "XH", "YH", "ZH");
  const Vec3 normal = wall.head - wall.tail;
  if (!(normal.norm() > 0))
    card2.context().fail(card2.line(), "the head XH YH ZH " + point_text(wall.head) +
                                           " equals the tail XT YT ZT: the wall has no normal");
  wall.fric = card2.real(6, "FRIC", 0.0);
  if (wall.fric < 0 || (wall.fric > 1 && wall.fric != 2 && wall.fric != 3))
    card2.fail("FRIC", quoted(card2.text(6)) +
                           " is not 0 (frictionless), between 0 and 1 (Coulomb), 1 (no sliding), "
                           "2 or 3 (welding)");
  wall.wvel = card2.real(7, "WVEL", 0.0);
  if (wall.wvel < 0) card2.fail("WVEL", quoted(card2.text(7)) + " is negative");

  if (wall.finite) {
    const Card card = cursor.next(standard_fields, "card 3 (XHEV YHEV ZHEV LENL LENM)");
    wall.edge_head = read_point(card, 0, "XHEV", "YHEV", "ZHEV");
    wall.lenl = card.real(3, "LENL", 0.0);
    wall.lenm = card.real(4, "LENM", 0.0);
    if (wall.lenl < 0) card.fail("LENL", quoted(card.text(3)) + " is negative (0 = unbounded along l)");
    if (wall.lenm < 0) card.fail("LENM", quoted(card.text(4)) + " is negative (0 = unbounded along m)");
    // l must have a part in the wall's plane: the rectangle's edges are l and m = n x l.
    const Vec3 l = wall.edge_head - wall.tail;
    const Vec3 n = normal.normalized();
    if (!((l - l.dot(n) * n).norm() > 1e-6 * l.norm()))
      card.context().fail(card.line(), "the edge vector from XT YT ZT to XHEV YHEV ZHEV " +
                                           point_text(wall.edge_head) +
                                           (l.norm() > 0 ? " is parallel to the wall normal"
                                                         : " has zero length"));
  }
  if (wall.moving) {
    const Card card = cursor.next(standard_fields, "card (MASS V0)");
    wall.mass = card.required_real(0, "MASS");
    if (!(wall.mass > 0)) card.fail("MASS", quoted(card.text(0)) + " must be greater than 0");
    wall.v0 = card.real(1, "V0", 0.0);
  }

  cursor.expect_end({}, "one " + cursor.context().keyword + " defines one wall");
  model.rigid_walls.push_back(std::move(wall));
}

// *CONSTRAINED_RIGID_BODIES: PIDL PIDC IFLAG, one pair a card. IFLAG 1 (keep the constrained
// part's own centre and inertia for output) has no Spall meaning; the merged body's mass
// properties always come from all its nodes.
void read_constrained_rigid_bodies(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card = cursor.next(standard_fields, "card (PIDL PIDC IFLAG)");
    model::ConstrainedRigidBodies merge;
    merge.lead = card.required_integer(0, "PIDL");
    merge.constrained = card.required_integer(1, "PIDC");
    if (card.integer(2, "IFLAG", 0) != 0) card.fail("IFLAG", quoted(card.text(2)) + ": only 0 is supported");
    if (merge.lead == merge.constrained) card.fail("PIDC", quoted(card.text(1)) + " is its own lead");
    merge.where = card.where();
    model.merged_rigid_bodies.push_back(merge);
  }
}

}  // namespace spall::io::keyword
