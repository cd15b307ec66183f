#include "spall/spg/setup.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <map>
#include <optional>
#include <span>
#include <tuple>

#include "spall/core/first_failure.hpp"
#include "spall/core/id_deal.hpp"
#include "spall/materials/make_material.hpp"
#include "spall/spg/formulation.hpp"

namespace spall::spg {

namespace {

constexpr const char* section_keyword = "*SECTION_SOLID_SPG";

const model::SectionSolidSpg* spg_section(const model::Model& model, const model::Part& part) {
  if (model.rigid_material(part)) return nullptr;  // a rigid body (rigid/setup.hpp)
  auto it = model.sections.find(part.secid);
  if (it == model.sections.end()) return nullptr;
  return std::get_if<model::SectionSolidSpg>(&it->second);
}

// Every field of the section, against what the solver implements (docs/KEYWORDS.md, SPG table).
PartSettings check_section(const model::SectionSolidSpg& s, Id part_id) {
  if (s.aet != 0) fail_at(s.where, section_keyword, fmt::format("AET {}: ambient element types do not apply to SPG (ELFORM 47)", s.aet));
  if (s.cohoff != 0) fail_at(s.where, section_keyword, "COHOFF: applies to cohesive elements, not to SPG (ELFORM 47)");
  if (s.gaskett != 0) fail_at(s.where, section_keyword, "GASKETT: applies to cohesive gasket elements, not to SPG (ELFORM 47)");
  if (s.lscale != 0)
    fail_at(s.where_card2, section_keyword,
            fmt::format("LSCALE {}: a displacement-regularization length scale is not implemented (current "
                     "manuals mark the column unused; leave it blank)", s.lscale));
  if (s.itb == 3)
    fail_at(s.where_card3, section_keyword,
            "ITB 3: momentum-consistent SPG (MC-SPG) is not implemented; use ITB 1 or 2");
  if (s.column8 != 0)
    fail_at(s.where_card2, section_keyword,
            fmt::format("SWTIME {}: switching from the updated-Lagrangian to the Eulerian kernel during the "
                     "run is not implemented (column 8 is SWTIME with ITB {}; MSC only with ITB 3)",
                     s.column8, s.itb));
  if (s.idam < 1 || s.idam > 3)
    fail_at(s.where_card3, section_keyword,
            fmt::format("IDAM {}: bond failure is implemented on the effective plastic strain (IDAM 1), the maximum "
                     "principal stress (2) and the maximum shear strain (3) only",
                     s.idam));
  if (s.stretch < 1)
    fail_at(s.where_card3, section_keyword,
            fmt::format("STRETCH {}: a compression ratio below 1 is not implemented; STRETCH >= 1 makes bonds "
                     "fail only under relative tension (seed 001 §2.3)", s.stretch));
  if (s.msfac != 0) fail_at(s.where_card3, section_keyword, "MSFAC: applies to MC-SPG (ITB 3) only, which is not implemented");
  if (s.isc != 0)
    fail_at(s.where_card3, section_keyword, "ISC 1: self-contact between bond-failed particles is not implemented");
  if (s.boxid != 0)
    fail_at(s.where_card3, section_keyword, fmt::format("BOXID {}: an active SPG region (*DEFINE_BOX) is not implemented", s.boxid));
  if (s.pdamp != -0.001)
    fail_at(s.where_card3, section_keyword,
            fmt::format("PDAMP {}: particle-to-particle damping applies to MC-SPG (ITB 3) only, which is not "
                     "implemented; leave it blank", s.pdamp));
  PartSettings p;
  p.part_id = part_id;
  p.shape = static_cast<KernelShape>(s.ispline);
  p.dilation = Vec3(s.dx, s.dy, s.dz);
  p.kernel_update = static_cast<KernelUpdate>(s.kernel);
  p.update_interval = s.smstep;
  p.stabilization = static_cast<Stabilization>(s.itb);
  p.failure_quantity = static_cast<BondFailure>(s.idam);
  p.failure_value = s.fs;
  p.failure_stretch = s.stretch;
  p.where = s.where_card2;
  return p;
}

materials::Material resolve_material(const model::Model& model, const model::Part& part) {
  if (part.hgid != 0)
    fail_at(part.where, "*PART", fmt::format("part {}: HGID {}: SPG parts have no hourglass modes to control", part.id, part.hgid));
  return materials::make_material(model, part);
}

// LS-DYNA: FS on *MAT_003 and *MAT_024 (FAIL) overwrites the section's FS for bond failure (and the
// material then also sets the stress to zero at that strain); spg.md §3.
Real bond_failure_strain(const materials::Material& material, Real section_fs) {
  Real fs = 0;
  if (const auto* m = std::get_if<materials::PlasticKinematic>(&material.strength)) fs = m->failure_strain;
  if (const auto* m = std::get_if<materials::PiecewiseLinear>(&material.strength)) fs = m->failure_strain;
  return fs > 0 && fs < 1.0e20 ? fs : section_fs;
}

// One SPG part's particle at a node: its nodal volume and spacing gathered over the elements around
// it. The nodal spacing per direction is the mean extent (bounding box) of those elements.
struct NodeAccumulator {
  ParticleSetup particle;
  Vec3 extent_sum = Vec3::Zero();
  int elements = 0;

  // An element's corner at the node: its volume, and, at the first of the element's corners on
  // this node (repeated corners of a degenerate element add their volumes up), its extent.
  void add(Real volume, const Vec3& extent, bool first_corner) {
    particle.volume += volume;
    if (!first_corner) return;
    extent_sum += extent;
    ++elements;
  }
  ParticleSetup setup() const {
    ParticleSetup p = particle;
    p.spacing = extent_sum / elements;
    return p;
  }
};
struct PartParticles {
  std::map<Index, NodeAccumulator> by_node;  // ascending node index: particles in node (cell) order
};

[[noreturn]] void fail_missing_node(const model::ElementSolid& e, int corner) {
  fail_at(e.where, "*ELEMENT_SOLID", fmt::format("element {}: node {} does not exist", e.eid, e.n[corner]));
}

// The element's corner volumes (spg/nodal_volumes.hpp); an inverted or flat element stops the run.
HexVolumes checked_volumes(const model::ElementSolid& e, const HexCorners& x) {
  const HexVolumes v = hex_volumes(x);
  if (!(v.min_jacobian > 0) || !(v.total > 0))
    fail_at(e.where, "*ELEMENT_SOLID",
            fmt::format("element {}: inverted or flat (Jacobian {:.3g} at a Gauss point); check the node "
                        "order (N1-N4 one face, N5-N8 the opposite face)", e.eid, v.min_jacobian));
  return v;
}

// The extent of the element's bounding box.
Vec3 element_extent(const HexCorners& x) {
  Vec3 lo = x[0], hi = x[0];
  for (const Vec3& p : x) lo = lo.cwiseMin(p), hi = hi.cwiseMax(p);
  return hi - lo;
}

// Whether corner a's node is not one of the corners before it (the first of repeated corners).
bool first_corner(const std::array<Index, 8>& node, int a) {
  return std::find(node.begin(), node.begin() + a, node[a]) == node.begin() + a;
}

// A face of a hexahedron as its distinct corner nodes, sorted (a degenerate element has triangular
// faces; a face that collapsed to an edge or a point is no face).
using FaceKey = std::array<Index, 4>;
constexpr int hex_faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4}, {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};

// Face f of the element on nodes `node`, or none where it collapsed to an edge or a point.
std::optional<FaceKey> face_key(const std::array<Index, 8>& node, int f) {
  FaceKey key;
  for (int c = 0; c < 4; ++c) key[c] = node[hex_faces[f][c]];
  std::sort(key.begin(), key.end());
  // Repeated corners (degenerate faces) become -1: the key holds the distinct nodes.
  for (int c = 3; c > 0; --c)
    if (key[c] == key[c - 1]) key[c] = -1;
  std::sort(key.begin(), key.end());
  if (key[1] < 0) return std::nullopt;  // fewer than three distinct corners: an edge or a point
  return key;
}

// The nodes of faces that only one element of the part has are on the part's surface.
void mark_surface_nodes(const model::Model& model, const discretization::NodeIndex& index_of_node,
                        std::map<Id, PartParticles>& parts) {
  std::map<Id, std::map<FaceKey, int>> face_count;
  for (const auto& e : model.solid_elements) {
    auto part = parts.find(e.pid);
    if (part == parts.end()) continue;
    std::array<Index, 8> node;
    for (int a = 0; a < 8; ++a) node[a] = index_of_node.at(e.n[a]);
    for (int f = 0; f < 6; ++f)
      if (const auto key = face_key(node, f)) ++face_count[e.pid][*key];
  }
  for (const auto& [pid, faces] : face_count)
    for (const auto& [key, count] : faces)
      if (count == 1)
        for (Index node : key)
          if (node >= 0) parts.at(pid).by_node.at(node).particle.on_surface = true;
}

// Part `pid`'s settings, its section and material checked (without its particles).
PartSetup part_setup(const model::Model& model, Id pid) {
  const model::Part& part = *model.find_part(pid);
  PartSetup setup;
  setup.settings = check_section(*spg_section(model, part), pid);
  setup.settings.material = resolve_material(model, part);
  if (setup.settings.failure_quantity == BondFailure::plastic_strain)
    setup.settings.failure_value = bond_failure_strain(setup.settings.material, setup.settings.failure_value);
  // TYPE -1 and -2 also add the standard bulk viscosity to shells (-2 without its energy in the
  // shells' balance; solids always count it): for solids they are TYPE 1.
  const auto& viscosity = model.bulk_viscosity;
  setup.settings.bulk_viscosity_quadratic = viscosity.q1;
  setup.settings.bulk_viscosity_linear = viscosity.q2;
  return setup;
}

}  // namespace

bool is_spg_part(const model::Model& model, Id part_id) {
  const model::Part* part = model.find_part(part_id);
  return part && spg_section(model, *part);
}

std::vector<PartSetup> spg_parts(const model::Model& model, const discretization::NodeIndex& index_of_node,
                                 const discretization::NodeStore& nodes) {
  std::map<Id, PartParticles> parts;  // by part ID: deterministic order
  for (const auto& e : model.solid_elements) {
    if (!is_spg_part(model, e.pid)) continue;
    auto& part = parts[e.pid];
    HexCorners x;
    std::array<Index, 8> index;
    for (int a = 0; a < 8; ++a) {
      const Index* it = index_of_node.find(e.n[a]);
      if (!it) fail_missing_node(e, a);
      index[a] = *it;
      x[a] = nodes.x0[index[a]];
    }
    const HexVolumes v = checked_volumes(e, x);
    const Vec3 extent = element_extent(x);
    for (int a = 0; a < 8; ++a) {
      auto& acc = part.by_node[index[a]];
      acc.particle.node = index[a];
      acc.add(v.corner[a], extent, first_corner(index, a));
    }
  }
  mark_surface_nodes(model, index_of_node, parts);
  std::vector<PartSetup> setups;
  for (const auto& [pid, particles] : parts) {
    PartSetup setup = part_setup(model, pid);
    setup.particles.reserve(particles.by_node.size());
    for (const auto& [node, acc] : particles.by_node) setup.particles.push_back(acc.setup());
    setups.push_back(std::move(setup));
  }
  return setups;
}

std::vector<PartSetup> spg_parts_in_blocks(const model::Model& model, const std::vector<ElementCorners>& elements,
                                           const std::vector<Index>& blocks, const parallel::Communicator& ranks) {
  // A corner's share of its particle, to the rank whose block holds its node (records of whole
  // words: no padding travels).
  struct Corner {
    Id pid;
    Index place, ordinal;
    std::int32_t corner, first;  // its number in the element; 1 at the first of repeated corners
    Real volume;
    Vec3 extent;
  };
  // A face, to the rank whose block holds its lowest node.
  struct Face {
    Id pid;
    FaceKey key;
  };
  const auto rank_of = [&](Index place) { return parallel::rank_of_place(blocks, place); };
  std::vector<std::vector<Corner>> corners(ranks.size());
  std::vector<std::vector<Face>> faces(ranks.size());
  std::vector<Id> pids;
  Index failed = -1;  // the first bad element of this rank's, in the deck's order
  std::optional<InputError> error;
  for (const ElementCorners& e : elements) {
    const model::ElementSolid& card = *e.card;
    if (!is_spg_part(model, card.pid)) continue;
    pids.push_back(card.pid);
    HexVolumes v;
    try {
      for (int a = 0; a < 8; ++a)
        if (e.place[a] < 0) fail_missing_node(card, a);
      v = checked_volumes(card, e.x);
    } catch (const InputError& bad) {
      failed = e.ordinal, error = bad;
      break;
    }
    const Vec3 extent = element_extent(e.x);
    for (int a = 0; a < 8; ++a)
      corners[rank_of(e.place[a])].push_back(
          {card.pid, e.place[a], e.ordinal, a, first_corner(e.place, a) ? 1 : 0, v.corner[a], extent});
    for (int f = 0; f < 6; ++f)
      if (const auto key = face_key(e.place, f))
        faces[rank_of(*std::find_if(key->begin(), key->end(), [](Index n) { return n >= 0; }))].push_back(
            {card.pid, *key});
  }
  parallel::throw_first_failure(failed, error, ranks);

  // The corners of this rank's nodes added up as spg_parts adds them: by part, then node, in the
  // deck's order of the elements and the corners' in each.
  std::vector<Corner> mine = ranks.deliver(corners);
  std::vector<std::vector<Corner>>().swap(corners);
  std::sort(mine.begin(), mine.end(), [](const Corner& a, const Corner& b) {
    return std::tie(a.pid, a.place, a.ordinal, a.corner) < std::tie(b.pid, b.place, b.ordinal, b.corner);
  });
  std::map<Id, std::vector<NodeAccumulator>> by_part;  // each part's particles of this block, in node order
  for (const Corner& c : mine) {
    auto& particles = by_part[c.pid];
    if (particles.empty() || particles.back().particle.node != c.place) particles.push_back({{c.place}});
    particles.back().add(c.volume, c.extent, c.first != 0);
  }
  std::vector<Corner>().swap(mine);

  // The faces met once, whose nodes are on the surface: their count at the rank of the lowest
  // node, the flags to the ranks of the others.
  std::vector<Face> met = ranks.deliver(faces);
  std::vector<std::vector<Face>>().swap(faces);
  std::sort(met.begin(), met.end(),
            [](const Face& a, const Face& b) { return std::tie(a.pid, a.key) < std::tie(b.pid, b.key); });
  struct Surface {
    Id pid;
    std::int64_t place;
  };
  std::vector<std::vector<Surface>> flags(ranks.size());
  for (std::size_t k = 0; k < met.size();) {
    std::size_t next = k + 1;
    while (next < met.size() && met[next].pid == met[k].pid && met[next].key == met[k].key) ++next;
    if (next == k + 1)
      for (const Index node : met[k].key)
        if (node >= 0) flags[rank_of(node)].push_back({met[k].pid, node});
    k = next;
  }
  for (const Surface& s : ranks.deliver(flags)) {
    auto& particles = by_part.at(s.pid);
    const auto at = std::lower_bound(particles.begin(), particles.end(), static_cast<Index>(s.place),
                                     [](const NodeAccumulator& p, Index place) { return p.particle.node < place; });
    at->particle.on_surface = true;
  }

  // Every part on every rank, in the order of their IDs (as spg_parts), checked alike.
  std::sort(pids.begin(), pids.end());
  pids.erase(std::unique(pids.begin(), pids.end()), pids.end());
  pids = ranks.all(std::span<const Id>(pids));
  std::sort(pids.begin(), pids.end());
  pids.erase(std::unique(pids.begin(), pids.end()), pids.end());
  std::vector<PartSetup> setups;
  for (const Id pid : pids) {
    PartSetup setup = part_setup(model, pid);
    if (const auto particles = by_part.find(pid); particles != by_part.end())
      for (const NodeAccumulator& acc : particles->second) setup.particles.push_back(acc.setup());
    setups.push_back(std::move(setup));
  }
  return setups;
}

namespace {

// The formulation of `setups`, their masses and part added to the rows of their nodes (the node at
// place p in row p - first; set up in blocks, `across` the ranks whose blocks hold the others).
std::unique_ptr<discretization::Formulation> build_parts(const model::Model& model, std::vector<PartSetup> setups,
                                                         discretization::NodeStore& nodes, Index first,
                                                         const parallel::Communicator* across) {
  if (setups.empty()) return nullptr;  // alike on every rank
  std::vector<Part> built;
  for (auto& setup : setups) {
    const Id pid = setup.settings.part_id;
    for (const auto& p : setup.particles) {
      const Index row = p.node - first;
      if (nodes.part[row] != 0 && !is_spg_part(model, nodes.part[row]))
        fail_at(model.find_part(pid)->where, "*PART",
                fmt::format("part {}: node {} is also an SPH particle of part {}; SPG and SPH parts cannot "
                         "share nodes", pid, nodes.id[row], nodes.part[row]));
      if (nodes.part[row] == 0) nodes.part[row] = pid;
      nodes.mass[row] += setup.settings.material.density * p.volume;
    }
    built.emplace_back(std::move(setup.settings), setup.particles, nodes, across);
  }
  return std::make_unique<SpgFormulation>(std::move(built));
}

}  // namespace

std::unique_ptr<discretization::Formulation> build_spg(const model::Model& model,
                                               const discretization::NodeIndex& index_of_node,
                                               discretization::NodeStore& nodes) {
  return build_parts(model, spg_parts(model, index_of_node, nodes), nodes, 0, nullptr);
}

std::unique_ptr<discretization::Formulation> build_spg_in_blocks(const model::Model& model,
                                                                 const std::vector<ElementCorners>& elements,
                                                                 const std::vector<Index>& blocks,
                                                                 discretization::NodeStore& nodes,
                                                                 const parallel::Communicator& ranks) {
  return build_parts(model, spg_parts_in_blocks(model, elements, blocks, ranks), nodes, blocks[ranks.rank()], &ranks);
}

}  // namespace spall::spg
