#include "spall/contact/setup.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <map>
#include <set>

#include "spall/core/log.hpp"
#include "spall/materials/make_material.hpp"

namespace spall::contact {

namespace {

using model::Contact;
using model::ContactSurface;
using Type = ContactSurface::Type;
using Corners = std::array<Index, 4>;  // a triangle repeats corner 2

bool is_triangle(const Corners& f) { return f[3] == f[2]; }
Corners reversed(const Corners& f) {
  return is_triangle(f) ? Corners{f[0], f[2], f[1], f[1]} : Corners{f[0], f[3], f[2], f[1]};
}

// n A of a face: half the cross product of its diagonals (of two edges for a triangle).
Vec3 area_vector(const Corners& f, const std::vector<Vec3>& x) {
  if (is_triangle(f)) return Real(0.5) * (x[f[1]] - x[f[0]]).cross(x[f[2]] - x[f[0]]);
  return Real(0.5) * (x[f[2]] - x[f[0]]).cross(x[f[3]] - x[f[1]]);
}

Vec3 centre_of(const Corners& f, const std::vector<Vec3>& x) {
  const int corners = is_triangle(f) ? 3 : 4;
  Vec3 c = Vec3::Zero();
  for (int k = 0; k < corners; ++k) c += x[f[k]];
  return c / corners;
}

// The corners sorted, a triangle's fourth slot -1: the key that finds a face from any corner.
Corners key_of(Corners f) {
  if (is_triangle(f)) f[3] = -1;
  std::sort(f.begin(), f.end());
  return f;
}

constexpr std::size_t no_element = std::numeric_limits<std::size_t>::max();

// A face of a solid element, turned to face out of it.
struct Face {
  Corners node{};
  std::size_t element = 0;            // in model.solid_elements
  std::size_t beyond = no_element;    // the element on its other side
};

// LS-DYNA's hexahedron numbering: N1-N4 one end, N5-N8 the other.
constexpr int hex_faces[6][4] = {{0, 1, 2, 3}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
constexpr int tet_faces[4][3] = {{0, 1, 2}, {0, 1, 3}, {1, 2, 3}, {2, 0, 3}};

// Every face of every solid element of the model (FEM, SPG and rigid meshes alike), with how many
// elements share it, and every element's volume. A degenerate hexahedron loses the faces that
// collapse to an edge; a face that collapses to a triangle is one.
class SolidFaces {
 public:
  SolidFaces(const model::Model& model, const discretization::NodeIndex& index_of_node,
             const std::vector<Vec3>& x) {
    volume_.resize(model.solid_elements.size());
    for (std::size_t e = 0; e < model.solid_elements.size(); ++e) {
      const auto& element = model.solid_elements[e];
      std::array<Index, 8> n;
      for (int k = 0; k < 8; ++k) {
        const Index* it = index_of_node.find(element.n[k]);
        if (!it)
          fail_at(element.where, "*ELEMENT_SOLID", fmt::format("node {} does not exist", element.n[k]));
        n[k] = *it;
      }
      std::vector<Corners> faces;
      if (element.is_tetrahedron()) {
        for (const auto& f : tet_faces) faces.push_back({n[f[0]], n[f[1]], n[f[2]], n[f[2]]});
      } else {
        for (const auto& f : hex_faces) {
          std::vector<Index> c;
          for (int k : f)
            if (std::find(c.begin(), c.end(), n[k]) == c.end()) c.push_back(n[k]);
          if (c.size() == 3) faces.push_back({c[0], c[1], c[2], c[2]});
          if (c.size() == 4) faces.push_back({c[0], c[1], c[2], c[3]});
        }
      }
      Vec3 centre = Vec3::Zero();
      for (const auto& f : faces) centre += centre_of(f, x);
      centre /= static_cast<Real>(faces.size());
      Real volume = 0;
      for (auto f : faces) {
        // Outward: the face's area vector points away from the element's centre. The volume is
        // the sum of the cones from the centre to the faces (Gauss's theorem).
        if (area_vector(f, x).dot(centre_of(f, x) - centre) < 0) f = reversed(f);
        volume += area_vector(f, x).dot(centre_of(f, x) - centre) / 3;
        Entry& entry = faces_[key_of(f)];
        if (entry.count < 2) entry.side[entry.count] = Face{f, e};
        ++entry.count;
      }
      volume_[e] = volume;
    }
  }

  // The faces of the elements `take` accepts, in a fixed order, each with the element beyond it:
  // those of the body's boundary (one element only; with `side_boundary`, also those whose element
  // beyond is one `take` refuses, which then counts as none), and with `inner` the faces two of its
  // elements share, once turned out of each.
  template <class Take>
  std::vector<Face> faces_of(Take&& take, bool inner, bool side_boundary) const {
    std::vector<Face> out;
    for (const auto& [key, entry] : faces_) {
      if (entry.count > 2) continue;  // not a face of a solid body
      for (int k = 0; k < entry.count; ++k) {
        Face face = entry.side[k];
        if (!take(face.element)) continue;
        if (entry.count == 2) face.beyond = entry.side[1 - k].element;
        if (side_boundary && face.beyond != no_element && !take(face.beyond)) face.beyond = no_element;
        if (face.beyond == no_element || inner) out.push_back(face);
      }
    }
    return out;
  }

  // The element face with these corners, turned out of the first element that has it; nullptr
  // when no element has it.
  const Face* find(const Corners& corners) const {
    auto it = faces_.find(key_of(corners));
    return it == faces_.end() ? nullptr : &it->second.side[0];
  }

  Real volume(std::size_t element) const { return volume_[element]; }

 private:
  struct Entry {
    std::array<Face, 2> side;  // as the first two elements that have it turn it
    int count = 0;
  };
  std::map<Corners, Entry> faces_;
  std::vector<Real> volume_;
};

// The bulk modulus and density of a part's material: the penalty stiffnesses scale with K.
struct PartStiffness {
  Real bulk_modulus = 0;
  Real density = 0;
};

class Builder {
 public:
  Builder(const model::Model& model, const discretization::NodeIndex& index_of_node,
          const discretization::NodeStore& nodes)
      : model_(model), index_of_node_(index_of_node), nodes_(nodes),
        faces_(model, index_of_node, nodes.x) {
    if (model.control_contact) control_ = *model.control_contact;
    for (const auto& part : model.parts) part_index_[part.id] = &part;
    for (std::size_t e = 0; e < model.shell_elements.size(); ++e) {
      Corners& f = shell_corners_.emplace_back();
      const model::ElementShell& shell = model.shell_elements[e];
      for (int k = 0; k < 4; ++k) f[k] = node(shell.n[k], shell.where, "*ELEMENT_SHELL");
      shells_.emplace(key_of(f), e);
    }
  }

  PenaltyContact build(const Contact& c, std::size_t ordinal) {
    contact_ = &c;
    PenaltyContact::Definition d;
    d.id = c.id != 0 ? c.id : static_cast<Id>(ordinal + 1);  // LS-DYNA numbers contacts in order
    d.friction.static_coefficient = c.fsf * c.fs;
    d.friction.dynamic_coefficient = c.fsf * c.fd;
    d.friction.decay = c.dc;
    d.friction.viscous_limit = c.vsf * c.vc;
    d.damping = c.vdc / 100;
    d.soft = c.soft;
    d.soft_scale = c.sofscl;
    d.penopt = control_.penopt;
    d.stiffness_step = c.dtstif;
    d.birth = c.birth;
    d.death = c.death;
    // The release depth: PENMAX segment thicknesses (automatic types: 0.4 by default, the
    // thickness of a solid face V / A); the old node-to-surface type: XPENE times 1/20 of the
    // face's shortest diagonal (fem-contact.md §1.6-1.7).
    const bool old_type = c.kind == Contact::Kind::nodes_to_surface;
    d.release_depth = c.penmax > 0 ? c.penmax : old_type ? control_.xpene : 0.4;
    d.edge_tolerance = c.maxpar - 1;

    std::vector<PenaltyContact::Pass> passes;
    const std::string& keyword = c.keyword;
    if (c.kind == Contact::Kind::automatic_single_surface) {
      PenaltyContact::Pass pass;
      pass.slave = slave_nodes(c.a, c.sfsa, "SURFA");
      pass.slave_stiffness = slave_stiffness_;
      segments(pass, c.a, c.sfsb, old_type, "SURFA", c.sast, c.sfsat);
      passes.push_back(std::move(pass));
    } else {
      PenaltyContact::Pass forward;
      forward.slave = slave_nodes(c.a, c.sfsa, "SURFA");
      forward.slave_stiffness = slave_stiffness_;
      segments(forward, c.b, c.sfsb, old_type, "SURFB", c.sbst, c.sfsbt);
      if (forward.segment.empty())
        fail_at(c.where, keyword,
                "SURFB: the master side has no solid element faces nor shells (SPH particles can only be slave nodes)");
      passes.push_back(std::move(forward));
      if (c.kind == Contact::Kind::automatic_surface_to_surface) {
        // Two-way: side B's nodes against side A's faces too, where side A has faces.
        PenaltyContact::Pass reverse;
        segments(reverse, c.a, c.sfsa, old_type, "SURFA", c.sast, c.sfsat);
        if (!reverse.segment.empty()) {
          reverse.slave = slave_nodes(c.b, c.sfsb, "SURFB");
          reverse.slave_stiffness = slave_stiffness_;
          reverse.slaves_are_side_a = false;
          passes.push_back(std::move(reverse));
        } else {
          log::info(fmt::format("contact {}: side A has no solid element faces nor shells; its nodes are checked "
                                "against side B's segments only", d.id));
        }
      }
    }
    d.side_body = {side_body(passes, true), side_body(passes, false)};
    Index slaves = 0, segment_count = 0, inner = 0;
    for (const auto& p : passes) {
      slaves += static_cast<Index>(p.slave.size());
      segment_count += static_cast<Index>(p.segment.size());
      inner += std::count_if(p.elements.begin(), p.elements.end(), [](const auto& f) { return f.beyond != 0; });
    }
    log::info(fmt::format("contact {} ({}): {} slave nodes, {} segments{}{}", d.id, keyword, slaves, segment_count,
                          inner > 0 ? fmt::format(" ({} inside the body, each live once the element beyond it "
                                                  "erodes)", inner)
                                    : "",
                          d.soft == 1 ? ", soft constraint" : ""));
    return PenaltyContact(d, std::move(passes));
  }

 private:
  // The rigid body all nodes of a side belong to, or no_body.
  std::int32_t side_body(const std::vector<PenaltyContact::Pass>& passes, bool side_a) const {
    constexpr std::int32_t none = discretization::NodeStore::no_body, unseen = none - 1;
    std::int32_t body = unseen;
    auto see = [&](Index i) { body = (body == unseen || body == nodes_.body[i]) ? nodes_.body[i] : none; };
    for (const auto& pass : passes) {
      if (pass.slaves_are_side_a == side_a)
        for (Index i : pass.slave) see(i);
      else
        for (const Segment& s : pass.segment)
          for (Index i : s.node) see(i);
    }
    return body < 0 ? none : body;
  }

  const model::Part& part(Id id, const char* field) const {
    auto it = part_index_.find(id);
    if (it == part_index_.end())
      fail_at(contact_->where, contact_->keyword, fmt::format("{}: part {} does not exist", field, id));
    return *it->second;
  }

  const model::PartSet& part_set(Id id, const char* field) const {
    auto it = model_.part_sets.find(id);
    if (it == model_.part_sets.end())
      fail_at(contact_->where, contact_->keyword, fmt::format("{}: part set {} does not exist", field, id));
    return it->second;
  }

  // The parts of a side given by parts (part, part set, all, all but a part set).
  std::set<Id> parts_of(const ContactSurface& side, const char* field) const {
    std::set<Id> parts;
    switch (side.type) {
      case Type::part: part(side.id, field); parts.insert(side.id); break;
      case Type::part_set:
        for (Id p : part_set(side.id, field).parts) part(p, field), parts.insert(p);
        break;
      case Type::all:
        for (const auto& p : model_.parts) parts.insert(p.id);
        break;
      case Type::exempted_part_set: {
        const auto& exempt = part_set(side.id, field).parts;
        for (const auto& p : model_.parts)
          if (std::find(exempt.begin(), exempt.end(), p.id) == exempt.end()) parts.insert(p.id);
        break;
      }
      default: break;
    }
    return parts;
  }

  Index node(Id id, const SourceLocation& where, const char* keyword) const {
    const Index* it = index_of_node_.find(id);
    if (!it) fail_at(where, keyword, fmt::format("node {} does not exist", id));
    return *it;
  }

  const model::SegmentSet& segment_set(Id id, const char* field) const {
    auto it = model_.segment_sets.find(id);
    if (it == model_.segment_sets.end())
      fail_at(contact_->where, contact_->keyword, fmt::format("{}: segment set {} does not exist", field, id));
    return it->second;
  }

  Corners corners_of(const std::array<Id, 4>& segment, const model::SegmentSet& set) const {
    Corners f;
    for (int k = 0; k < 4; ++k) f[k] = node(segment[k], set.where, "*SET_SEGMENT");
    return f;
  }

  // The nodes of a side (ascending), and their SOFT 0 stiffnesses in slave_stiffness_.
  std::vector<Index> slave_nodes(const ContactSurface& side, Real scale, const char* field) {
    std::set<Index> nodes;
    if (side.type == Type::node_set) {
      auto it = model_.node_sets.find(side.id);
      if (it == model_.node_sets.end())
        fail_at(contact_->where, contact_->keyword, fmt::format("{}: node set {} does not exist", field, side.id));
      for (Id id : it->second.nodes) nodes.insert(node(id, it->second.where, "*SET_NODE"));
    } else if (side.type == Type::segment_set) {
      const auto& set = segment_set(side.id, field);
      for (const auto& s : set.segments)
        for (Index i : corners_of(s, set)) nodes.insert(i);
    } else {
      const std::set<Id> parts = parts_of(side, field);
      for (const auto& e : model_.solid_elements)
        if (parts.count(e.pid))
          for (Id id : e.n) nodes.insert(node(id, e.where, "*ELEMENT_SOLID"));
      for (const auto& e : model_.shell_elements)
        if (parts.count(e.pid))
          for (Id id : e.n) nodes.insert(node(id, e.where, "*ELEMENT_SHELL"));
      for (const auto& e : model_.sph_elements)
        if (parts.count(e.pid)) nodes.insert(node(e.nid, e.where, "*ELEMENT_SPH"));
    }
    std::vector<Index> out(nodes.begin(), nodes.end());
    // k = SLSFAC SFS K V^(1/3), V = m / rho the node's volume: K A^2 / V for a cube of V.
    slave_stiffness_.assign(out.size(), std::numeric_limits<Real>::infinity());
    for (std::size_t k = 0; k < out.size(); ++k) {
      const Index i = out[k];
      if (nodes_.part[i] == 0 || !(nodes_.mass[i] > 0)) continue;
      const PartStiffness& p = stiffness(nodes_.part[i]);
      slave_stiffness_[k] = control_.slsfac * scale * p.bulk_modulus * std::cbrt(nodes_.mass[i] / p.density);
    }
    return out;
  }

  // The master segments of a side into the pass, each with the elements it follows as they erode:
  // the outward faces of its solid elements, with their stiffness SLSFAC SFS K A^2 / V and
  // thickness V / A (the old node-to-surface type: 1/20 of the shortest diagonal), and its shells
  // (shell_segment). An eroding contact with EROSOP 1 takes the faces inside the body too, to wait
  // for the element beyond them to erode.
  void segments(PenaltyContact::Pass& pass, const ContactSurface& side, Real scale, bool old_type, const char* field,
                Real shell_thickness, Real thickness_scale) {
    std::vector<Face> faces;
    std::vector<std::pair<std::size_t, Corners>> shells;  // element, corners as the side gives them
    if (side.type == Type::segment_set) {
      const auto& set = segment_set(side.id, field);
      for (const auto& s : set.segments) {
        const Corners corners = corners_of(s, set);
        if (const Face* face = faces_.find(corners)) {
          faces.push_back(*face);
        } else if (auto shell = shells_.find(key_of(corners)); shell != shells_.end()) {
          shells.emplace_back(shell->second, corners);
        } else {
          fail_at(set.where, "*SET_SEGMENT",
                  fmt::format("segment {} {} {} {} is neither a face of a solid element nor a shell", s[0], s[1], s[2],
                              s[3]));
        }
      }
    } else if (side.type != Type::node_set) {
      const std::set<Id> parts = parts_of(side, field);
      faces = faces_.faces_of([&](std::size_t e) { return parts.count(model_.solid_elements[e].pid) > 0; },
                              contact_->eroding && contact_->erosop == 1, contact_->eroding && contact_->iadj == 1);
      for (std::size_t e = 0; e < model_.shell_elements.size(); ++e)
        if (parts.count(model_.shell_elements[e].pid)) shells.emplace_back(e, shell_corners_[e]);
    }
    std::vector<Segment>& out = pass.segment;
    const auto& x = nodes_.x;
    const bool symmetry_planes_out = (contact_->isym >= 0 ? contact_->isym : control_.isym) == 1;  // ISYM 1
    for (const Face& face : faces) {
      if (symmetry_planes_out && on_symmetry_plane(face.node)) continue;
      pass.elements.push_back({model_.solid_elements[face.element].eid,
                               face.beyond == no_element ? 0 : model_.solid_elements[face.beyond].eid});
      Segment s;
      s.node = face.node;
      s.area = area_vector(face.node, x).norm();
      const Real volume = faces_.volume(face.element);
      if (!(s.area > 0 && volume > 0))
        fail_at(model_.solid_elements[face.element].where, "*ELEMENT_SOLID",
                fmt::format("element {} has a face of zero area or no volume: it cannot be a contact segment",
                         model_.solid_elements[face.element].eid));
      const Id pid = model_.solid_elements[face.element].pid;
      const Real modulus = contact_->sldstf > 0 ? contact_->sldstf : stiffness(pid).bulk_modulus;
      s.stiffness = control_.slsfac * scale * modulus * s.area * s.area / volume;
      s.thickness = old_type ? diagonals(s).first / 20 : volume / s.area;
      out.push_back(s);
    }
    for (const auto& [element, corners] : shells) {
      out.push_back(shell_segment(model_.shell_elements[element], corners, scale, old_type, shell_thickness,
                                  thickness_scale));
      pass.elements.emplace_back();  // Spall's shells are rigid: they do not erode
    }
  }

  // ISYM 1: a face whose normal lies along an axis (within 1e-6 of it) and whose every corner an SPC
  // holds along that axis: a face on a symmetry plane of the model (fem-contact.md §1.6).
  bool on_symmetry_plane(const Corners& face) const {
    const Vec3 n = area_vector(face, nodes_.x).normalized();
    int axis = 0;
    n.cwiseAbs().maxCoeff(&axis);
    if (!(std::abs(n[axis]) >= 1 - 1e-6)) return false;
    for (int k = 0; k < (is_triangle(face) ? 3 : 4); ++k)
      if (!(nodes_.fixed[face[k]] & (1u << axis))) return false;
    return true;
  }

  // The shortest and longest diagonal of a segment (a triangle's edges): 1/20 of the shortest is
  // the old node-to-surface type's segment thickness, the longest sets a shell's stiffness.
  std::pair<Real, Real> diagonals(const Segment& s) const {
    const auto& x = nodes_.x;
    if (!s.triangle()) return std::minmax((x[s.node[2]] - x[s.node[0]]).norm(), (x[s.node[3]] - x[s.node[1]]).norm());
    Real shortest = std::numeric_limits<Real>::infinity(), longest = 0;
    for (int k = 0; k < 3; ++k) {
      const Real edge = (x[s.node[(k + 1) % 3]] - x[s.node[k]]).norm();
      shortest = std::min(shortest, edge), longest = std::max(longest, edge);
    }
    return {shortest, longest};
  }

  // A shell as a segment (fem-contact.md §1.6-1.7): its thickness t is the side's SAST / SBST when
  // given, else the mean of its corners', times SFSAT / SFSBT. The automatic types meet it from
  // both sides at t / 2 off its mid-surface; the old node-to-surface type on the side its normal
  // (N1 N2 N3 counter-clockwise) points to, at the mid-surface unless SHLTHK 2 offsets it by t / 2.
  // Stiffness SLSFAC SFS K A / (longest diagonal) (LS-DYNA's theory manual, [MEM] in fem-contact.md).
  Segment shell_segment(const model::ElementShell& element, const Corners& corners, Real scale, bool old_type,
                        Real given_thickness, Real thickness_scale) {
    const auto& x = nodes_.x;
    Segment s;
    s.node = corners;
    s.area = area_vector(corners, x).norm();
    if (!(s.area > 0))
      fail_at(element.where, "*ELEMENT_SHELL",
              fmt::format("shell element {} has zero area: it cannot be a contact segment", element.eid));
    Real thickness = given_thickness;
    if (!(thickness > 0)) {
      const std::array<Real, 4> t = model_.shell_thickness(element);
      for (int k = 0; k < s.corners(); ++k) thickness += t[k] / s.corners();
    }
    thickness *= thickness_scale;
    const auto [shortest, longest] = diagonals(s);
    s.stiffness = control_.slsfac * scale * stiffness(element.pid).bulk_modulus * s.area / longest;
    const int shlthk = contact_->shlthk >= 0 ? contact_->shlthk : control_.shlthk;
    s.two_sided = !old_type;
    s.offset = !old_type || shlthk == 2 ? thickness / 2 : 0;
    s.thickness = old_type ? shortest / 20 : thickness;
    return s;
  }

  // K and rho of a part: *MAT_RIGID's E and PR; any other material's K = rho c^2 - 4G/3 at its
  // reference state.
  const PartStiffness& stiffness(Id pid) {
    auto found = stiffness_.find(pid);
    if (found != stiffness_.end()) return found->second;
    const model::Part& p = part(pid, "PID");
    PartStiffness s;
    if (const model::MatRigid* rigid = model_.rigid_material(p)) {
      s.density = rigid->ro;
      s.bulk_modulus = rigid->e / (3 * (1 - 2 * rigid->pr));
      if (!(s.bulk_modulus > 0))
        fail_at(contact_->where, contact_->keyword,
                fmt::format("part {} is rigid with E {} and PR {}: the contact stiffness needs E > 0 and PR < 0.5", pid,
                         rigid->e, rigid->pr));
    } else {
      const materials::Material material = materials::make_material(model_, p);
      const Real c = materials::sound_speed(material, material.density, material.initial_specific_energy);
      s.density = material.density;
      s.bulk_modulus = material.density * c * c - Real(4) / 3 * material.shear_modulus;
    }
    return stiffness_.emplace(pid, s).first->second;
  }

  const model::Model& model_;
  const discretization::NodeIndex& index_of_node_;
  const discretization::NodeStore& nodes_;
  SolidFaces faces_;
  model::ControlContact control_;
  std::unordered_map<Id, const model::Part*> part_index_;
  std::unordered_map<Id, PartStiffness> stiffness_;
  std::vector<Corners> shell_corners_;     // of each shell element, in the deck's node order
  std::map<Corners, std::size_t> shells_;  // key_of(corners) -> its index in model.shell_elements
  const Contact* contact_ = nullptr;
  std::vector<Real> slave_stiffness_;
};

}  // namespace

std::vector<PenaltyContact> build_contacts(const model::Model& model,
                                           const discretization::NodeIndex& index_of_node,
                                           const discretization::NodeStore& nodes) {
  std::vector<PenaltyContact> contacts;
  if (model.contacts.empty() && model.rcforc_moments.empty()) return contacts;
  Builder builder(model, index_of_node, nodes);
  for (std::size_t c = 0; c < model.contacts.size(); ++c) contacts.push_back(builder.build(model.contacts[c], c));
  // *DATABASE_RCFORC_MOMENT: the nodes of the contact with that ID.
  for (const auto& moment : model.rcforc_moments) {
    const char* keyword = "*DATABASE_RCFORC_MOMENT";
    auto contact = std::find_if(contacts.begin(), contacts.end(),
                                [&](const PenaltyContact& c) { return c.definition().id == moment.cid; });
    if (contact == contacts.end()) fail_at(moment.where, keyword, fmt::format("CID {}: no contact has that ID", moment.cid));
    std::array<Index, 2> nodes_of{-1, -1};
    for (int side = 0; side < 2; ++side) {
      const Id id = side == 0 ? moment.nodes_a : moment.nodes_b;
      if (id == 0) continue;
      const Index* it = index_of_node.find(id);
      if (!it)
        fail_at(moment.where, keyword, fmt::format("{}: node {} does not exist", side == 0 ? "NODESA" : "NODESB", id));
      nodes_of[side] = *it;
    }
    contact->set_moment_nodes(nodes_of);
  }
  return contacts;
}

}  // namespace spall::contact
