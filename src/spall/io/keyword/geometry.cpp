// *NODE, *ELEMENT_SOLID, *ELEMENT_SHELL, *ELEMENT_SPH, *PART, and the local coordinate systems
// (*DEFINE_COORDINATE_SYSTEM, _VECTOR, _NODES).
#include <algorithm>
#include <array>
#include <cmath>

#include "spall/core/memory.hpp"
#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {
// *NODE: NID i8, X Y Z e16, TC RC i8.
constexpr std::array<int, 6> node_fields = {8, 16, 16, 16, 8, 8};
// *ELEMENT_SOLID: EID PID N1..N8 (legacy one-line), or EID PID then N1..N10 (ten-node format).
constexpr std::array<int, 10> solid_legacy_fields = {8, 8, 8, 8, 8, 8, 8, 8, 8, 8};
constexpr std::array<int, 2> solid_header_fields = {8, 8};
constexpr std::array<int, 10> solid_nodes_fields = {8, 8, 8, 8, 8, 8, 8, 8, 8, 8};
// *ELEMENT_SHELL: EID PID N1..N8 i8; the _THICKNESS card THIC1..THIC4 BETA/MCID e16.
constexpr std::array<int, 10> shell_fields = {8, 8, 8, 8, 8, 8, 8, 8, 8, 8};
constexpr std::array<int, 5> shell_thickness_fields = {16, 16, 16, 16, 16};
// *ELEMENT_SPH: NID PID i8, MASS e16, NEND i8.
constexpr std::array<int, 4> sph_fields = {8, 8, 16, 8};
constexpr const char* node_names[10] = {"N1", "N2", "N3", "N4", "N5",
                                        "N6", "N7", "N8", "N9", "N10"};

// The one-line legacy layout has node numbers after EID and PID; the ten-node layout's first
// line has only EID and PID. As pydyna does, tell them apart by the first line's length.
bool is_legacy_solid_layout(const DataLine& first, bool long_format) {
  const std::string_view text = first.text;
  if (text.find(',') != std::string_view::npos) {
    std::size_t commas = 0;
    for (char c : text) commas += c == ',';
    return commas >= 2;
  }
  std::string_view significant = text;
  while (!significant.empty() && (significant.back() == ' ' || significant.back() == '\t'))
    significant.remove_suffix(1);
  return significant.size() > (long_format ? 40u : 16u);
}
}  // namespace

Id checked_node_id(const Card& card, const char* name, Id id) {
  if (id < 1 || id > largest_id)
    card.fail(name, std::to_string(id) + " is not a node ID (1 to 2^53)");
  return id;
}

void read_node(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  if (model.cards.whole()) model.nodes.reserve(model.nodes.size() + cursor.context().block.data.size());
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card = cursor.next(node_fields, "node card");
    model::Node node;
    node.id = checked_node_id(card, "NID", card.required_integer(0, "NID"));
    node.x = Vec3(card.real(1, "X", 0.0), card.real(2, "Y", 0.0), card.real(3, "Z", 0.0));
    node.tc = card.int32(4, "TC", 0);
    node.rc = card.int32(5, "RC", 0);
    node.where = card.where();
    model.largest_node_id = std::max(model.largest_node_id, node.id);
    if (model.cards.holds(model.node_cards++)) model.nodes.push_back(std::move(node));
  }
}

void read_element_solid(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  cursor.skip_blank_lines();
  if (cursor.done()) return;
  const bool legacy = is_legacy_solid_layout(cursor.peek(), cursor.context().long_format);
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    model::ElementSolid element;
    std::array<Id, 10> nodes{};
    if (legacy) {
      const Card card = cursor.next(solid_legacy_fields, "element card");
      element.eid = card.required_integer(0, "EID");
      element.pid = card.required_integer(1, "PID");
      for (int k = 0; k < 8; ++k) nodes[k] = card.integer(2 + k, node_names[k], 0);
      element.where = card.where();
    } else {
      const Card header = cursor.next(solid_header_fields, "element card 1 (EID PID)");
      element.eid = header.required_integer(0, "EID");
      element.pid = header.required_integer(1, "PID");
      element.where = header.where();
      const Card card = cursor.next(solid_nodes_fields, "element card 2 (N1..N10)");
      for (int k = 0; k < 10; ++k) nodes[k] = card.integer(k, node_names[k], 0);
      if (nodes[8] != 0 || nodes[9] != 0)
        card.fail("N9", "element " + std::to_string(element.eid) +
                            " has nodes N9/N10: ten-node tetrahedra are not supported");
    }
    for (int k = 0; k < 8; ++k) {
      if (nodes[k] <= 0)
        cursor.context().fail(element.where.line,
                              "element " + std::to_string(element.eid) + ": " + node_names[k] +
                                  " is blank or 0; a solid element needs 8 nodes (repeat nodes "
                                  "for degenerate shapes)");
      element.n[k] = nodes[k];
    }
    model.solid_elements.push_back(std::move(element));
  }
}

// EID PID N1..N8 (i8); _THICKNESS, _BETA and _MCID add THIC1-THIC4 and BETA or MCID (e16), the
// last of which orients material axes that a rigid part does not have.
void read_element_shell(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  const bool thickness_card = call.base != "ELEMENT_SHELL";
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card = cursor.next(shell_fields, "element card (EID PID N1..N8)");
    model::ElementShell element;
    element.eid = card.required_integer(0, "EID");
    element.pid = card.required_integer(1, "PID");
    element.where = card.where();
    for (int k = 0; k < 4; ++k) {
      element.n[k] = card.integer(2 + k, node_names[k], 0);
      if (element.n[k] <= 0 && !(k == 3 && element.n[k] == 0))
        card.fail(node_names[k], "element " + std::to_string(element.eid) + ": " + node_names[k] +
                                     " is blank or not a node ID; a shell needs N1-N3, and N4 (or N3 repeated)");
    }
    if (element.n[3] == 0) element.n[3] = element.n[2];  // a triangle
    for (int k = 4; k < 8; ++k)
      if (card.integer(2 + k, node_names[k], 0) != 0)
        card.fail(node_names[k], "element " + std::to_string(element.eid) +
                                     ": eight-node (quadratic) shells are not supported");
    if (thickness_card) {
      const Card thick = cursor.next(shell_thickness_fields, "card 2 (THIC1 THIC2 THIC3 THIC4 BETA/MCID)");
      static constexpr const char* names[] = {"THIC1", "THIC2", "THIC3", "THIC4"};
      for (int k = 0; k < 4; ++k) {
        element.thickness[k] = thick.real(k, names[k], 0.0);
        if (element.thickness[k] < 0) thick.fail(names[k], quoted(thick.text(k)) + ": a thickness cannot be negative");
      }
    }
    model.shell_elements.push_back(std::move(element));
  }
}

void read_element_sph(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  const bool volume_option = call.base == "ELEMENT_SPH_VOLUME";
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card = cursor.next(sph_fields, "particle card");
    model::ElementSph particle;
    particle.nid = checked_node_id(card, "NID", card.required_integer(0, "NID"));
    particle.pid = card.required_integer(1, "PID");
    const Real mass = card.real(2, "MASS", 0.0);
    if (mass == 0.0)
      card.fail("MASS", "particle " + std::to_string(particle.nid) +
                            " has no mass: give a mass (> 0) or a volume (< 0)");
    // The model keeps LS-DYNA's convention: a negative MASS is a volume.
    particle.mass = volume_option ? -std::abs(mass) : mass;
    particle.where = card.where();
    const Id nend = card.integer(3, "NEND", 0);
    if (nend > 0 && nend < particle.nid)
      card.fail("NEND", "NEND " + std::to_string(nend) + " is below NID " +
                            std::to_string(particle.nid));
    const Id last = nend > 0 ? checked_node_id(card, "NEND", nend) : particle.nid;
    // A card that generates particles is checked against the memory left; one particle a card is
    // bounded by the file's size (and a check per card would read /proc for each particle).
    if (last > particle.nid)
      if (const std::string why = memory::shortfall(particles_held(model, double(last - particle.nid + 1)),
                                                    particle_bytes, "particles");
          !why.empty())
        card.fail("NEND", "NID to NEND: " + why);
    for (Id nid = particle.nid; nid <= last; ++nid) {
      particle.nid = nid;
      if (model.cards.holds(model.sph_cards++)) model.sph_elements.push_back(particle);
    }
  }
}

namespace {
Vec3 point(const Card& card, int first, const char* const names[3]) {
  return Vec3(card.real(first, names[0], 0.0), card.real(first + 1, names[1], 0.0),
              card.real(first + 2, names[2], 0.0));
}

// The heading and card 2 (PID SECID MID EOSID HGID GRAV ADPOPT TMID) of *PART and its options.
model::Part read_part_cards(CardCursor& cursor) {
  model::Part part;
  part.heading = cursor.next_text("heading card");
  const Card card = cursor.next(standard_fields, "card 2 (PID SECID MID ...)");
  part.id = card.required_integer(0, "PID");
  part.secid = card.required_integer(1, "SECID");
  part.mid = card.required_integer(2, "MID");
  part.eosid = card.integer(3, "EOSID", 0);
  part.hgid = card.integer(4, "HGID", 0);
  part.tmid = card.integer(7, "TMID", 0);
  part.where = card.where();
  return part;
}
}  // namespace

void read_part(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  while (!cursor.done()) model.parts.push_back(read_part_cards(cursor));
}

// Card 3 XC YC ZC TM IRCS NODEID, card 4 IXX IXY IXZ IYY IYZ IZZ, card 5 VTX VTY VTZ VRX VRY VRZ,
// and with IRCS 1 card 6 XL YL ZL XLIP YLIP ZLIP CID. Some writers give card 6 with IRCS 0 too: a
// lone line left after card 5 is taken as it (and has no use), not as the next part's heading.
void read_part_inertia(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    model::Part part = read_part_cards(cursor);
    model::PartInertia inertia;
    const Card card3 = cursor.next(standard_fields, "card 3 (XC YC ZC TM IRCS NODEID)");
    static constexpr const char* centre[] = {"XC", "YC", "ZC"};
    inertia.centre = point(card3, 0, centre);
    inertia.mass = card3.required_real(3, "TM");
    if (!(inertia.mass > 0)) card3.fail("TM", quoted(card3.text(3)) + ": the mass must be > 0");
    const std::int64_t ircs = card3.integer(4, "IRCS", 0);
    if (ircs != 0 && ircs != 1) card3.fail("IRCS", quoted(card3.text(4)) + " is not 0 (global axes) or 1 (local)");
    inertia.local = ircs == 1;
    inertia.node = card3.integer(5, "NODEID", 0);
    if (inertia.node < 0) card3.fail("NODEID", quoted(card3.text(5)) + " is not a node ID");
    inertia.where = card3.where();
    const Card card4 = cursor.next(standard_fields, "card 4 (IXX IXY IXZ IYY IYZ IZZ)");
    static constexpr const char* names[] = {"IXX", "IXY", "IXZ", "IYY", "IYZ", "IZZ"};
    static constexpr int row_of[] = {0, 0, 0, 1, 1, 2}, column_of[] = {0, 1, 2, 1, 2, 2};
    for (int k = 0; k < 6; ++k)
      inertia.tensor(row_of[k], column_of[k]) = inertia.tensor(column_of[k], row_of[k]) =
          k == 0 ? card4.required_real(k, names[k]) : card4.real(k, names[k], 0.0);
    const Card card5 = cursor.next(standard_fields, "card 5 (VTX VTY VTZ VRX VRY VRZ)");
    static constexpr const char* translation[] = {"VTX", "VTY", "VTZ"};
    static constexpr const char* rotation[] = {"VRX", "VRY", "VRZ"};
    inertia.velocity = point(card5, 0, translation);
    inertia.angular_velocity = point(card5, 3, rotation);
    cursor.skip_blank_lines();
    const bool lone_line = !cursor.done() && cursor.context().block.data.back().line == cursor.peek().line;
    if (inertia.local || lone_line) {
      const Card card6 = cursor.next(standard_fields, "card 6 (XL YL ZL XLIP YLIP ZLIP CID)");
      static constexpr const char* axis[] = {"XL", "YL", "ZL"};
      static constexpr const char* plane[] = {"XLIP", "YLIP", "ZLIP"};
      inertia.local_x = point(card6, 0, axis);
      inertia.local_in_plane = point(card6, 3, plane);
      inertia.cid = card6.integer(6, "CID", 0);
      if (inertia.local && inertia.cid == 0 &&
          !(inertia.local_x.cross(inertia.local_in_plane).norm() > 0))
        card6.fail("XL", "the local x axis (XL YL ZL) and the in-plane vector (XLIP YLIP ZLIP) must be nonzero and "
                         "not parallel, or CID given");
    }
    part.inertia = inertia;
    model.parts.push_back(std::move(part));
  }
}

namespace {

// Cards repeat (one system each), after a title line each with `_TITLE`.
template <class ReadOne>
void read_coordinate_systems(CardCursor& cursor, const KeywordCall& call, model::Model& model, ReadOne&& read_one) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    model::CoordinateSystem system;
    system.keyword = cursor.context().keyword;
    const Card card = read_one(system);
    system.where = card.where();
    if (system.id <= 0) card.fail("CID", quoted(card.text(0)) + " is not a coordinate system ID (> 0)");
    insert_unique(model.coordinate_systems, system.id, std::move(system), card, "coordinate system");
  }
}

}  // namespace

// Origin O, a point L on the local x axis, a point P in the local x-y plane.
void read_define_coordinate_system(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  read_coordinate_systems(cursor, call, model, [&](model::CoordinateSystem& system) {
    const Card card1 = cursor.next(standard_fields, "card 1 (CID XO YO ZO XL YL ZL CIDL)");
    system.id = card1.required_integer(0, "CID");
    static constexpr const char* o_names[3] = {"XO", "YO", "ZO"};
    static constexpr const char* l_names[3] = {"XL", "YL", "ZL"};
    static constexpr const char* p_names[3] = {"XP", "YP", "ZP"};
    const Vec3 origin = point(card1, 1, o_names);
    system.axis = point(card1, 4, l_names) - origin;
    if (card1.integer(7, "CIDL", 0) != 0)
      card1.fail("CIDL", quoted(card1.text(7)) + ": points given in another local system are not supported; give "
                                                 "them in global coordinates (CIDL 0)");
    const Card card2 = cursor.next(standard_fields, "card 2 (XP YP ZP)");
    system.in_plane = point(card2, 0, p_names) - origin;
    return card1;
  });
}

// The local x axis (XX YX ZX) and a vector in the local x-y plane (XV YV ZV); NID only moves the origin.
void read_define_coordinate_vector(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  read_coordinate_systems(cursor, call, model, [&](model::CoordinateSystem& system) {
    const Card card = cursor.next(standard_fields, "card 1 (CID XX YX ZX XV YV ZV NID)");
    system.id = card.required_integer(0, "CID");
    static constexpr const char* x_names[3] = {"XX", "YX", "ZX"};
    static constexpr const char* v_names[3] = {"XV", "YV", "ZV"};
    system.axis = point(card, 1, x_names);
    system.in_plane = point(card, 4, v_names);
    return card;
  });
}

// VID XT YT ZT XH YH ZH CID, repeated (after a title line each with _TITLE).
void read_define_vector(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    const Card card = cursor.next(standard_fields, "card 1 (VID XT YT ZT XH YH ZH CID)");
    model::Vector vector;
    vector.id = card.required_integer(0, "VID");
    if (vector.id <= 0) card.fail("VID", quoted(card.text(0)) + " is not a vector ID (> 0)");
    static constexpr const char* tail[3] = {"XT", "YT", "ZT"};
    static constexpr const char* head[3] = {"XH", "YH", "ZH"};
    vector.tail = point(card, 1, tail);
    vector.head = point(card, 4, head);
    vector.cid = card.integer(7, "CID", 0);
    vector.where = card.where();
    if (!((vector.head - vector.tail).norm() > 0))
      card.fail("XH", "the head is the tail: the vector has no direction");
    insert_unique(model.vectors, vector.id, std::move(vector), card, "vector");
  }
}

// N1 -> N2 is the axis DIR (X, Y or Z; blank X), N3 lies in the plane of that axis and the next.
void read_define_coordinate_nodes(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  read_coordinate_systems(cursor, call, model, [&](model::CoordinateSystem& system) {
    const Card card = cursor.next(standard_fields, "card 1 (CID N1 N2 N3 FLAG DIR)");
    system.id = card.required_integer(0, "CID");
    for (int k = 0; k < 3; ++k) {
      system.nodes[k] = card.required_integer(1 + k, node_names[k]);
      if (system.nodes[k] <= 0) card.fail(node_names[k], quoted(card.text(1 + k)) + " is not a node ID");
    }
    system.follows_nodes = card.zero_or_one(4, "FLAG") == 1;
    const std::string_view dir = card.text(5);
    if (dir.empty() || dir == "X" || dir == "x") system.axis_index = 0;
    else if (dir == "Y" || dir == "y") system.axis_index = 1;
    else if (dir == "Z" || dir == "z") system.axis_index = 2;
    else card.fail("DIR", quoted(dir) + " is not X, Y or Z");
    return card;
  });
}

}  // namespace spall::io::keyword
