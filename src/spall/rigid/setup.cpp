#include "spall/rigid/setup.hpp"

#include <fmt/format.h>
#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <map>
#include <optional>
#include <set>

#include "spall/fem/solid_elements.hpp"

namespace spall::rigid {

namespace {

// *MAT_RIGID CON1 / CON2 as the axes they hold.
std::array<bool, 3> axes(int code) {
  const std::uint8_t mask = model::constraint_axes(code);
  return {(mask & 1) != 0, (mask & 2) != 0, (mask & 4) != 0};
}

// *BOUNDARY_PRESCRIBED_MOTION_RIGID (fem-contact.md §1.4): DOF 1-3 translations along, 5-7
// rotations about, the global axes through the centre of mass; DOF 4 and 8 the same along the
// *DEFINE_VECTOR VID, the motion normal to it free; VAD 0 velocity, 1 acceleration, 2 displacement
// (or angle).
PrescribedMotion prescribed_motion(const model::Model& model, const model::PrescribedMotion& pm) {
  const char* keyword = "*BOUNDARY_PRESCRIBED_MOTION_RIGID";
  PrescribedMotion m;
  if ((pm.dof >= 1 && pm.dof <= 3) || (pm.dof >= 5 && pm.dof <= 7)) {
    m.rotation = pm.dof >= 5;
    m.axis = (pm.dof - 1) % 4;
    m.direction = Vec3::Unit(m.axis);
    if (pm.vid != 0)
      fail_at(pm.where, keyword, fmt::format("VID {}: a vector gives the direction of DOF 4 and 8 only (DOF {} is a "
                                             "global axis)", pm.vid, pm.dof));
  } else if (pm.dof == 4 || pm.dof == 8) {
    m.rotation = pm.dof == 8;
    m.axis = -1;
    auto vector = model.vectors.find(pm.vid);
    if (vector == model.vectors.end())
      fail_at(pm.where, keyword, fmt::format("VID {}: DOF {} takes its direction from a *DEFINE_VECTOR, and vector {} "
                                             "is not defined", pm.vid, pm.dof, pm.vid));
    const model::Vector& v = vector->second;
    m.direction = (model.axes(v.cid, v.where, "*DEFINE_VECTOR", "CID") * (v.head - v.tail)).normalized();
  } else {
    fail_at(pm.where, keyword,
            fmt::format("DOF {}: only translations (1, 2, 3, and 4 along VID) and rotations about axes through the "
                        "centre of mass (5, 6, 7, and 8 about VID) apply to a rigid body here (-4 and -8 need "
                        "*MAT_RIGID CMO 2, which is not supported)", pm.dof));
  }
  if (pm.vad < 0 || pm.vad > 2)
    fail_at(pm.where, keyword,
            fmt::format("VAD {}: only velocity (0), acceleration (1) and displacement (2) are supported", pm.vad));
  auto curve = model.curves.find(pm.lcid);
  if (curve == model.curves.end()) fail_at(pm.where, keyword, fmt::format("LCID: curve {} does not exist", pm.lcid));
  m.vad = pm.vad;
  m.curve = &curve->second;
  m.sf = pm.sf;
  m.birth = pm.birth;
  m.death = pm.death;
  return m;
}

// *PART_INERTIA (fem-contact.md §1.5): TM, the centre (XC YC ZC, or node NODEID's position) and the
// tensor, turned from its local axes (IRCS 1: XL YL ZL the local x, XLIP YLIP ZLIP in the local x-y
// plane, or CID's first axes) to the world's. VTX..VRZ, when not all 0, set the body's initial velocity
// and angular velocity about the centre (over any *INITIAL_VELOCITY of its nodes).
MassProperties mass_properties(const model::Model& model, const model::PartInertia& card,
                               const discretization::NodeIndex& index_of_node, const std::vector<Index>& body_nodes,
                               discretization::NodeStore& nodes) {
  const char* keyword = "*PART_INERTIA";
  MassProperties p;
  p.mass = card.mass;
  p.centre = card.centre;
  if (card.node != 0) {
    const Index* it = index_of_node.find(card.node);
    if (!it)
      fail_at(card.where, keyword, fmt::format("NODEID: node {} does not exist", card.node));
    p.centre = nodes.x[*it];
  }
  Mat3 Q = Mat3::Identity();  // columns: the local axes in world coordinates
  if (card.local && card.cid != 0) {
    Q = model.axes(card.cid, card.where, keyword, "CID");  // the tensor is given once: the first axes
  } else if (card.local) {
    const Vec3 x = card.local_x.normalized();
    const Vec3 y = (card.local_in_plane - card.local_in_plane.dot(x) * x).normalized();
    Q.col(0) = x, Q.col(1) = y, Q.col(2) = x.cross(y);
  }
  p.inertia = Q * card.tensor * Q.transpose();
  const Eigen::SelfAdjointEigenSolver<Mat3> principal(p.inertia);
  const Vec3 J = principal.eigenvalues();  // ascending
  if (!(J[0] > 0) || J[2] > J[0] + J[1] * (1 + 1e-12))
    fail_at(card.where, keyword,
            fmt::format("IXX..IZZ: principal moments {:.6g} {:.6g} {:.6g}: an inertia tensor's are positive and each "
                        "at most the sum of the other two", J[0], J[1], J[2]));
  // The nodes' masses m_I (1 + a + b . x_I): the smallest change, in proportion to each mass and
  // linear in space, that gives them the mass TM and the centre (four equations for a and b), so
  // that a base acceleration (*LOAD_BODY) and the contacts act on the body with TM at its centre.
  Eigen::Matrix4d A = Eigen::Matrix4d::Zero();
  Eigen::Vector4d b(p.mass, p.mass * p.centre.x(), p.mass * p.centre.y(), p.mass * p.centre.z()), carried = -b;
  for (Index i : body_nodes) {
    const Eigen::Vector4d x(1, nodes.x[i].x(), nodes.x[i].y(), nodes.x[i].z());
    A += nodes.mass[i] * x * x.transpose();
    b -= nodes.mass[i] * x;
  }
  const Eigen::Vector4d c = A.completeOrthogonalDecomposition().solve(b);
  Real lightest = std::numeric_limits<Real>::infinity();
  for (Index i : body_nodes) {
    nodes.mass[i] *= 1 + c[0] + c.tail<3>().dot(nodes.x[i]);
    lightest = std::min(lightest, nodes.mass[i]);
    carried += nodes.mass[i] * Eigen::Vector4d(1, nodes.x[i].x(), nodes.x[i].y(), nodes.x[i].z());
  }
  Real size = 0;  // the body's extent about the centre: the scale of its first moment
  for (Index i : body_nodes) size = std::max(size, (nodes.x[i] - p.centre).norm());
  if (!(lightest > 0) || std::abs(carried[0]) > 1e-9 * p.mass || carried.tail<3>().norm() > 1e-9 * p.mass * size)
    fail_at(card.where, keyword,
            fmt::format("XC YC ZC ({:.6g}, {:.6g}, {:.6g}): the part's nodes cannot carry the mass TM {:.6g} with its "
                        "centre there (a centre outside the part's elements, or off the plane of a flat part)",
                        p.centre.x(), p.centre.y(), p.centre.z(), p.mass));
  if (!card.velocity.isZero(0) || !card.angular_velocity.isZero(0))
    for (Index i : body_nodes) nodes.v[i] = card.velocity + card.angular_velocity.cross(nodes.x[i] - p.centre);
  return p;
}

}  // namespace

bool is_rigid_part(const model::Model& model, Id part_id) {
  const model::Part* part = model.find_part(part_id);
  return part && model.rigid_material(*part);
}

void add_rigid_masses(const model::Model& model, const discretization::NodeIndex& index_of_node,
                      discretization::NodeStore& nodes) {
  for (const auto& e : model.solid_elements) {
    const model::Part* part = model.find_part(e.pid);
    const model::MatRigid* rigid = part ? model.rigid_material(*part) : nullptr;
    if (!rigid) continue;
    std::array<Index, 8> node;
    for (int a = 0; a < 8; ++a) {
      const Index* it = index_of_node.find(e.n[a]);
      if (!it)
        fail_at(e.where, "*ELEMENT_SOLID", fmt::format("element {}: node {} does not exist", e.eid, e.n[a]));
      node[a] = *it;
    }
    const bool tetrahedron = e.is_tetrahedron();
    const Real volume = fem::element_volume(node, tetrahedron, nodes);
    if (!(volume > 0))
      fail_at(e.where, "*ELEMENT_SOLID", fmt::format("element {}: volume {:.6g}: inverted or flat (rigid part {})", e.eid,
                                                  volume, e.pid));
    const int per = tetrahedron ? 4 : 8;
    for (int a = 0; a < per; ++a) {
      nodes.mass[node[a]] += rigid->ro * volume / per;
      if (nodes.part[node[a]] == 0) nodes.part[node[a]] = e.pid;
    }
  }
  // Shells (rigid only: validate() refuses others): RO times the area times the mean of the corner
  // thicknesses, plus MAREA times the area, shared equally by the corners.
  for (const auto& e : model.shell_elements) {
    const model::Part& part = *model.find_part(e.pid);
    const model::MatRigid& rigid = *model.rigid_material(part);
    const auto& section = std::get<model::SectionShell>(model.sections.at(part.secid));
    const int per = e.is_triangle() ? 3 : 4;
    std::array<Vec3, 4> x;
    for (int a = 0; a < 4; ++a) {
      const Index* it = index_of_node.find(e.n[a]);
      if (!it)
        fail_at(e.where, "*ELEMENT_SHELL", fmt::format("shell element {}: node {} does not exist", e.eid, e.n[a]));
      x[a] = nodes.x[*it];
    }
    // Half the cross product of the diagonals (of two edges for a triangle).
    const Vec3 twice_area = per == 3 ? (x[1] - x[0]).cross(x[2] - x[0]) : (x[2] - x[0]).cross(x[3] - x[1]);
    const Real area = Real(0.5) * twice_area.norm();
    if (!(area > 0))
      fail_at(e.where, "*ELEMENT_SHELL", fmt::format("shell element {}: zero area (rigid part {})", e.eid, e.pid));
    const std::array<Real, 4> t = model.shell_thickness(e);
    Real thickness = 0;
    for (int a = 0; a < per; ++a) thickness += t[a] / per;
    const Real mass = area * (rigid.ro * thickness + section.marea);
    for (int a = 0; a < per; ++a) {
      const Index i = index_of_node.at(e.n[a]);
      nodes.mass[i] += mass / per;
      if (nodes.part[i] == 0) nodes.part[i] = e.pid;
    }
  }
}

RigidBodies build_rigid_bodies(const model::Model& model, const discretization::NodeIndex& index_of_node,
                               discretization::NodeStore& nodes) {
  // *CONSTRAINED_RIGID_BODIES: each part's lead (itself, or its PIDL's lead, followed down).
  std::map<Id, const model::ConstrainedRigidBodies*> lead_card;
  for (const auto& merge : model.merged_rigid_bodies) {
    for (Id pid : {merge.lead, merge.constrained})
      if (!is_rigid_part(model, pid))
        fail_at(merge.where, "*CONSTRAINED_RIGID_BODIES", fmt::format("part {} is not a rigid part (*MAT_RIGID)", pid));
    if (!lead_card.emplace(merge.constrained, &merge).second)
      fail_at(merge.where, "*CONSTRAINED_RIGID_BODIES", fmt::format("PIDC {}: already merged into another body", merge.constrained));
  }
  const auto lead_of = [&](Id pid) {
    for (std::size_t hops = 0; lead_card.contains(pid); ++hops) {
      if (hops > lead_card.size())
        fail_at(lead_card.at(pid)->where, "*CONSTRAINED_RIGID_BODIES", fmt::format("part {} leads itself in a loop", pid));
      pid = lead_card.at(pid)->lead;
    }
    return pid;
  };
  std::map<Id, std::set<Index>> body_nodes;  // by the lead's part ID: deterministic order
  std::set<Id> meshed;
  for (const auto& e : model.solid_elements)
    if (is_rigid_part(model, e.pid)) {
      meshed.insert(e.pid);
      for (Id n : e.n) body_nodes[lead_of(e.pid)].insert(index_of_node.at(n));
    }
  for (const auto& e : model.shell_elements) {
    meshed.insert(e.pid);
    for (Id n : e.n) body_nodes[lead_of(e.pid)].insert(index_of_node.at(n));
  }
  for (const auto& part : model.parts)
    if (model.rigid_material(part) && !meshed.contains(part.id))
      for (const auto& p : model.sph_elements)
        if (p.pid == part.id)
          fail_at(part.where, "*PART", fmt::format("part {}: *MAT_RIGID on SPH particles is not supported (rigid bodies "
                                                "are meshed with solid or shell elements)", part.id));
  RigidBodies bodies;
  using discretization::CellShape;
  for (const auto& e : model.solid_elements)
    if (is_rigid_part(model, e.pid)) {
      std::array<Index, 8> corners;
      for (int a = 0; a < 8; ++a) corners[a] = index_of_node.at(e.n[a]);
      const bool tetrahedron = e.is_tetrahedron();
      bodies.add_cell(tetrahedron ? CellShape::tetrahedron : CellShape::hexahedron, e.eid,
                      std::span<const Index>(corners.data(), tetrahedron ? 4 : 8));
    }
  for (const auto& e : model.shell_elements) {
    std::array<Index, 4> corners;
    for (int a = 0; a < 4; ++a) corners[a] = index_of_node.at(e.n[a]);
    const bool triangle = e.is_triangle();
    bodies.add_cell(triangle ? CellShape::triangle : CellShape::quadrilateral, e.eid,
                    std::span<const Index>(corners.data(), triangle ? 3 : 4));
  }
  for (const auto& [pid, node_set] : body_nodes) {
    const model::Part& part = *model.find_part(pid);
    const model::MatRigid& card = *model.rigid_material(part);
    const SourceLocation& where = model.materials.at(part.mid).where;
    RigidBody body;
    body.part_id = pid;
    body.node.assign(node_set.begin(), node_set.end());
    for (Index i : body.node)
      if (nodes.body[i] != discretization::NodeStore::no_body)
        fail_at(part.where, "*PART", fmt::format("part {}: node {} belongs to another rigid body too (merge the two "
                                              "with *CONSTRAINED_RIGID_BODIES)", pid, nodes.id[i]));
    if (card.cmo == -1) {
      // CON1 is a coordinate system and CON2 six digits (x y z translation, x y z rotation about the
      // system's axes; 1 held, 100000 holds x). The system keeps its first axes.
      body.constraint_axes = model.axes(card.con1, where, "*MAT_RIGID", "CON1");
      if (card.con1 != 0 && model.coordinate_systems.at(card.con1).follows_nodes)
        fail_at(where, "*MAT_RIGID", fmt::format("CON1: coordinate system {} turns with its nodes during the run (FLAG "
                                                 "1), which Spall cannot follow; give FLAG 0", card.con1));
      int code = card.con2;
      bool digits = code >= 0;
      for (int d = 5; d >= 0; --d, code /= 10) {
        digits = digits && code % 10 <= 1;
        (d < 3 ? body.fixed_translation[d] : body.fixed_rotation[d - 3]) = code % 10 == 1;
      }
      if (!digits || code != 0)
        fail_at(where, "*MAT_RIGID", fmt::format("CON2 {}: with CMO -1, six digits 0 or 1 (x y z translation, "
                                                 "x y z rotation)", card.con2));
    }
    if (card.cmo == 1) {
      body.fixed_translation = axes(card.con1);
      body.fixed_rotation = axes(card.con2);
    }
    std::optional<MassProperties> given;
    for (const auto& [constrained, merge] : lead_card)
      if (lead_of(constrained) == pid && model.find_part(constrained)->inertia)
        fail_at(model.find_part(constrained)->inertia->where, "*PART_INERTIA",
                fmt::format("part {} is merged into the body of part {} (*CONSTRAINED_RIGID_BODIES): give the "
                            "merged body's mass properties on the lead part", constrained, pid));
    if (part.inertia) given = mass_properties(model, *part.inertia, index_of_node, body.node, nodes);
    for (const auto& pm : model.prescribed_motions)
      if (pm.target == model::Target::part && pm.id == pid) {
        body.motions.push_back(prescribed_motion(model, pm));
        const PrescribedMotion& motion = body.motions.back();
        const auto& held = motion.rotation ? body.fixed_rotation : body.fixed_translation;
        if (!body.constraint_axes.isIdentity(0) && held != std::array<bool, 3>{})
          fail_at(pm.where, "*BOUNDARY_PRESCRIBED_MOTION_RIGID",
                  fmt::format("DOF {}: part {}'s *MAT_RIGID holds components in the local axes of CMO -1's system {}; "
                              "prescribed motion (global axes) with them is not supported", pm.dof, pid, card.con1));
        for (int d = 0; d < 3; ++d)
          if (held[d] && motion.direction[d] != 0)
            fail_at(pm.where, "*BOUNDARY_PRESCRIBED_MOTION_RIGID",
                    fmt::format("DOF {}: part {}'s *MAT_RIGID (CMO {}, {} {}) holds {} degree of freedom", pm.dof, pid,
                                card.cmo, motion.rotation ? "CON2" : "CON1", motion.rotation ? card.con2 : card.con1,
                                motion.axis >= 0 ? "that" : "a component of that"));
      }
    bodies.add(std::move(body), nodes, given ? &*given : nullptr);
  }
  for (const auto& pm : model.prescribed_motions)
    if (pm.target == model::Target::part && !body_nodes.contains(pm.id))
      fail_at(pm.where, "*BOUNDARY_PRESCRIBED_MOTION_RIGID",
              lead_card.contains(pm.id)
               ? fmt::format("PID {}: merged into the body of part {} (*CONSTRAINED_RIGID_BODIES); prescribe the "
                             "lead's motion", pm.id, lead_of(pm.id))
               : fmt::format("PID {}: not a rigid part (*MAT_RIGID meshed with solid or shell elements)", pm.id));
  return bodies;
}

}  // namespace spall::rigid
