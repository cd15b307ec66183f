#include "spall/spg/setup.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <map>

#include "spall/spg/formulation.hpp"
#include "spall/spg/nodal_volumes.hpp"

namespace spall::spg {

namespace {

constexpr const char* section_keyword = "*SECTION_SOLID_SPG";

[[noreturn]] void fail(const SourceLocation& where, const std::string& keyword, const std::string& message) {
  throw InputError(where, keyword, message);
}

const model::SectionSolidSpg* spg_section(const model::Model& model, const model::Part& part) {
  auto it = model.sections.find(part.secid);
  if (it == model.sections.end()) return nullptr;
  return std::get_if<model::SectionSolidSpg>(&it->second);
}

// Every field of the section, against what the solver implements (docs/KEYWORDS.md, SPG table).
PartSettings check_section(const model::SectionSolidSpg& s, Id part_id) {
  if (s.aet != 0) fail(s.where, section_keyword, fmt::format("AET {}: ambient element types do not apply to SPG (ELFORM 47)", s.aet));
  if (s.cohoff != 0) fail(s.where, section_keyword, "COHOFF: applies to cohesive elements, not to SPG (ELFORM 47)");
  if (s.gaskett != 0) fail(s.where, section_keyword, "GASKETT: applies to cohesive gasket elements, not to SPG (ELFORM 47)");
  if (s.lscale != 0)
    fail(s.where_card2, section_keyword,
         fmt::format("LSCALE {}: a displacement-regularization length scale is not implemented (current "
                     "manuals mark the column unused; leave it blank)", s.lscale));
  if (s.itb == 3)
    fail(s.where_card3, section_keyword,
         "ITB 3: momentum-consistent SPG (MC-SPG) is not implemented; use ITB 1 or 2");
  if (s.column8 != 0)
    fail(s.where_card2, section_keyword,
         fmt::format("SWTIME {}: switching from the updated-Lagrangian to the Eulerian kernel during the "
                     "run is not implemented (column 8 is SWTIME with ITB {}; MSC only with ITB 3)",
                     s.column8, s.itb));
  if (s.idam != 1)
    fail(s.where_card3, section_keyword,
         fmt::format("IDAM {}: only bond failure on the effective plastic strain (IDAM 1) is implemented", s.idam));
  if (s.stretch < 1)
    fail(s.where_card3, section_keyword,
         fmt::format("STRETCH {}: a compression ratio below 1 is not implemented; STRETCH >= 1 makes bonds "
                     "fail only under relative tension (seed 001 §2.3)", s.stretch));
  if (s.msfac != 0) fail(s.where_card3, section_keyword, "MSFAC: applies to MC-SPG (ITB 3) only, which is not implemented");
  if (s.isc != 0)
    fail(s.where_card3, section_keyword, "ISC 1: self-contact between bond-failed particles is not implemented");
  if (s.boxid != 0)
    fail(s.where_card3, section_keyword, fmt::format("BOXID {}: an active SPG region (*DEFINE_BOX) is not implemented", s.boxid));
  if (s.pdamp != -0.001)
    fail(s.where_card3, section_keyword,
         fmt::format("PDAMP {}: particle-to-particle damping applies to MC-SPG (ITB 3) only, which is not "
                     "implemented; leave it blank", s.pdamp));
  PartSettings p;
  p.part_id = part_id;
  p.shape = static_cast<KernelShape>(s.ispline);
  p.dilation = Vec3(s.dx, s.dy, s.dz);
  p.kernel_update = static_cast<KernelUpdate>(s.kernel);
  p.update_interval = s.smstep;
  p.stabilization = static_cast<Stabilization>(s.itb);
  p.failure_strain = s.fs;
  p.failure_stretch = s.stretch;
  p.where = s.where_card2;
  return p;
}

materials::ElasticConstants resolve_material(const model::Model& model, const model::Part& part) {
  if (part.hgid != 0)
    fail(part.where, "*PART", fmt::format("part {}: HGID {}: SPG parts have no hourglass modes to control", part.id, part.hgid));
  auto mat = model.materials.find(part.mid);
  if (mat == model.materials.end()) fail(part.where, "*PART", fmt::format("MID: material {} does not exist", part.mid));
  const auto* elastic = std::get_if<model::MatElastic>(&mat->second.params);
  if (!elastic)
    fail(mat->second.where, mat->second.keyword,
         fmt::format("material {} is used by SPG part {}, but the SPG solver supports only *MAT_ELASTIC so far",
                     mat->first, part.id));
  if (elastic->ro <= 0 || elastic->e <= 0 || elastic->pr < 0 || elastic->pr >= 0.5)
    fail(mat->second.where, mat->second.keyword,
         fmt::format("material {}: needs RO > 0, E > 0 and 0 <= PR < 0.5 (found RO {}, E {}, PR {})",
                     mat->first, elastic->ro, elastic->e, elastic->pr));
  if (part.eosid != 0)
    fail(part.where, "*PART", fmt::format("part {}: EOSID {} with *MAT_ELASTIC is not supported", part.id, part.eosid));
  return materials::ElasticConstants::from_young_poisson(elastic->ro, elastic->e, elastic->pr);
}

// One SPG part's particles: nodal volumes and spacings gathered over its elements.
struct PartParticles {
  std::map<Index, ParticleSetup> by_node;  // ascending node index: particles in node (cell) order
};

}  // namespace

bool is_spg_part(const model::Model& model, Id part_id) {
  const model::Part* part = model.find_part(part_id);
  return part && spg_section(model, *part);
}

std::unique_ptr<solver::Formulation> build_spg(const model::Model& model,
                                               const std::unordered_map<Id, Index>& index_of_node,
                                               solver::NodeStore& nodes, std::vector<Id>& part_of_node) {
  std::map<Id, PartParticles> parts;  // by part ID: deterministic order
  for (const auto& e : model.solid_elements) {
    if (!is_spg_part(model, e.pid)) continue;
    auto& part = parts[e.pid];
    HexCorners x;
    std::array<Index, 8> index;
    for (int a = 0; a < 8; ++a) {
      auto it = index_of_node.find(e.n[a]);
      if (it == index_of_node.end())
        fail(e.where, "*ELEMENT_SOLID", fmt::format("element {}: node {} does not exist", e.eid, e.n[a]));
      index[a] = it->second;
      x[a] = nodes.x0[index[a]];
    }
    const HexVolumes v = hex_volumes(x);
    if (!(v.min_jacobian > 0) || !(v.total > 0))
      fail(e.where, "*ELEMENT_SOLID",
           fmt::format("element {}: inverted or flat (Jacobian {:.3g} at a Gauss point); check the node "
                       "order (N1-N4 one face, N5-N8 the opposite face)", e.eid, v.min_jacobian));
    for (int a = 0; a < 8; ++a) {
      ParticleSetup& p = part.by_node[index[a]];
      p.node = index[a];
      p.volume += v.corner[a];
      // Nodal spacing: the largest extent, per direction, of the elements around the node.
      for (int b = 0; b < 8; ++b) p.spacing = p.spacing.cwiseMax((x[b] - x[a]).cwiseAbs());
    }
  }
  if (parts.empty()) return nullptr;
  std::vector<Part> built;
  for (const auto& [pid, particles] : parts) {
    const model::Part& part = *model.find_part(pid);
    const auto& section = *spg_section(model, part);
    PartSettings settings = check_section(section, pid);
    settings.material = resolve_material(model, part);
    std::vector<ParticleSetup> list;
    list.reserve(particles.by_node.size());
    for (const auto& [node, p] : particles.by_node) {
      if (part_of_node[node] != 0 && !is_spg_part(model, part_of_node[node]))
        fail(part.where, "*PART",
             fmt::format("part {}: node {} is also an SPH particle of part {}; SPG and SPH parts cannot "
                         "share nodes", pid, nodes.id[node], part_of_node[node]));
      if (part_of_node[node] == 0) part_of_node[node] = pid;
      nodes.mass[node] += settings.material.density * p.volume;
      list.push_back(p);
    }
    built.emplace_back(std::move(settings), list, nodes);
  }
  return std::make_unique<SpgFormulation>(std::move(built));
}

}  // namespace spall::spg
