// *BOUNDARY_SPC_NODE/_SET, *BOUNDARY_PRESCRIBED_MOTION_NODE/_SET/_RIGID (each with _ID),
// *INITIAL_VELOCITY, *INITIAL_VELOCITY_NODE, *INITIAL_VELOCITY_GENERATION.
#include <cstdlib>

#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {
// `_ID`: a card ID(0,10) HEADING(10,70) before each condition. Spall keeps no use for either.
void skip_id_card(CardCursor& cursor, const KeywordCall& call) {
  if (call.id) cursor.next_text("ID card (ID HEADING)");
}

Vec3 read_vec3(const Card& card, int first, const char* x, const char* y, const char* z) {
  return Vec3(card.real(first, x, 0.0), card.real(first + 1, y, 0.0), card.real(first + 2, z, 0.0));
}
}  // namespace

void read_boundary_spc(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  constexpr const char* dof_names[6] = {"DOFX", "DOFY", "DOFZ", "DOFRX", "DOFRY", "DOFRZ"};
  const bool on_set = call.base == "BOUNDARY_SPC_SET";
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    skip_id_card(cursor, call);
    const Card card = cursor.next(standard_fields, on_set ? "card (NSID CID DOFX ...)"
                                                          : "card (NID CID DOFX ...)");
    model::Spc spc;
    spc.target = on_set ? model::Target::node_set : model::Target::node;
    spc.id = card.required_integer(0, on_set ? "NSID" : "NID");
    spc.cid = card.integer(1, "CID", 0);
    for (int k = 0; k < 6; ++k) {
      const auto flag = card.integer(2 + k, dof_names[k], 0);
      if (flag != 0 && flag != 1)
        card.fail(dof_names[k], quoted(card.text(2 + k)) + " is not 0 or 1");
      spc.dof[k] = flag == 1;
    }
    spc.where = card.where();
    model.spcs.push_back(std::move(spc));
  }
}

void read_boundary_prescribed_motion(CardCursor& cursor, const KeywordCall& call,
                                     model::Model& model) {
  model::Target target = model::Target::node;
  const char* id_name = "NID";
  if (call.base == "BOUNDARY_PRESCRIBED_MOTION_SET") {
    target = model::Target::node_set;
    id_name = "NSID";
  } else if (call.base == "BOUNDARY_PRESCRIBED_MOTION_RIGID") {
    target = model::Target::part;
    id_name = "PID";
  }
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    skip_id_card(cursor, call);
    const Card card = cursor.next(standard_fields, "card 1 (ID DOF VAD LCID SF VID DEATH BIRTH)");
    model::PrescribedMotion motion;
    motion.target = target;
    motion.id = card.required_integer(0, id_name);
    motion.dof = card.required_int32(1, "DOF");
    motion.vad = card.int32(2, "VAD", 0);
    motion.lcid = card.required_integer(3, "LCID");
    // Blank and 0 read alike in LS-DYNA, so 0 takes the defaults SF = 1, DEATH = 1e28.
    motion.sf = card.real(4, "SF", 0.0);
    if (motion.sf == 0.0) motion.sf = 1.0;
    motion.vid = card.integer(5, "VID", 0);
    motion.death = card.real(6, "DEATH", 0.0);
    if (motion.death == 0.0) motion.death = 1.0e28;
    motion.birth = card.real(7, "BIRTH", 0.0);
    motion.where = card.where();
    // DOF 9-11 (offset motions of a node pair) take a second card and have no Spall meaning.
    if (motion.dof == 0 || std::abs(motion.dof) > 8)
      card.fail("DOF", quoted(card.text(1)) + " is not supported (1..8 or -4, -8)");
    if (motion.vad < 0 || motion.vad > 4)
      card.fail("VAD", quoted(card.text(2)) + " is not 0..4");
    model.prescribed_motions.push_back(std::move(motion));
  }
}

void read_initial_velocity(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card1 = cursor.next(standard_fields, "card 1 (NSID NSIDEX BOXID IRIGID ICID)");
  model::InitialVelocity velocity;
  velocity.nsid = card1.integer(0, "NSID", 0);
  velocity.nsidex = card1.integer(1, "NSIDEX", 0);
  velocity.boxid = card1.integer(2, "BOXID", 0);
  velocity.irigid = card1.int32(3, "IRIGID", 0);
  velocity.icid = card1.integer(4, "ICID", 0);
  velocity.where = card1.where();
  const Card card2 = cursor.next(standard_fields, "card 2 (VX VY VZ VXR VYR VZR)");
  velocity.v = read_vec3(card2, 0, "VX", "VY", "VZ");
  velocity.vr = read_vec3(card2, 3, "VXR", "VYR", "VZR");
  if (velocity.nsidex != 0) {
    const Card card3 = cursor.next(standard_fields, "card 3 (VXE VYE VZE ...), needed as NSIDEX != 0");
    velocity.v_exempt = read_vec3(card3, 0, "VXE", "VYE", "VZE");
    velocity.vr_exempt = read_vec3(card3, 3, "VXRE", "VYRE", "VZRE");
  }
  cursor.expect_end({}, "one " + cursor.context().keyword + " defines one initial velocity");
  model.initial_velocities.push_back(std::move(velocity));
}

void read_initial_velocity_node(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card = cursor.next(standard_fields, "card (NID VX VY VZ VXR VYR VZR ICID)");
    model::InitialVelocityNode velocity;
    velocity.nid = card.required_integer(0, "NID");
    velocity.v = read_vec3(card, 1, "VX", "VY", "VZ");
    velocity.vr = read_vec3(card, 4, "VXR", "VYR", "VZR");
    velocity.icid = card.integer(7, "ICID", 0);
    velocity.where = card.where();
    model.initial_velocity_nodes.push_back(std::move(velocity));
  }
}

void read_initial_velocity_generation(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card1 = cursor.next(standard_fields, "card 1 (ID STYP OMEGA VX VY VZ IVATN ICID)");
    model::InitialVelocityGeneration generation;
    generation.id = card1.integer(0, "ID", 0);
    generation.styp = card1.required_int32(1, "STYP");
    if (generation.styp < 1 || generation.styp > 3)
      card1.fail("STYP", quoted(card1.text(1)) + " is not 1 (part set), 2 (part) or 3 (node set)");
    generation.omega = card1.real(2, "OMEGA", 0.0);
    generation.v = read_vec3(card1, 3, "VX", "VY", "VZ");
    generation.ivatn = card1.integer(6, "IVATN", 0);
    generation.icid = card1.integer(7, "ICID", 0);
    generation.where = card1.where();
    const Card card2 = cursor.next(standard_fields, "card 2 (XC YC ZC NX NY NZ PHASE IRIGID)");
    generation.xc = read_vec3(card2, 0, "XC", "YC", "ZC");
    // NX = -999 makes NY and NZ two node IDs on the axis; kept as read for the solver.
    generation.axis = read_vec3(card2, 3, "NX", "NY", "NZ");
    generation.phase = card2.int32(6, "PHASE", 0);
    generation.irigid = card2.int32(7, "IRIGID", 0);
    model.initial_velocity_generations.push_back(std::move(generation));
  }
}

}  // namespace spall::io::keyword
