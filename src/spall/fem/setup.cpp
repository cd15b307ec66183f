#include "spall/fem/setup.hpp"

#include <fmt/format.h>
#include <map>

#include "spall/core/log.hpp"
#include "spall/fem/solid_elements.hpp"
#include "spall/materials/make_material.hpp"

namespace spall::fem {

namespace {

const model::SectionSolid* solid_section(const model::Model& model, const model::Part& part) {
  if (model.rigid_material(part)) return nullptr;  // a rigid body (rigid/setup.hpp)
  auto it = model.sections.find(part.secid);
  if (it == model.sections.end()) return nullptr;
  return std::get_if<model::SectionSolid>(&it->second);
}

HourglassForm hourglass_form(int ihq) {
  switch (ihq) {
    case 1: return HourglassForm::viscous_base;
    case 2:
    case 3: return HourglassForm::viscous;
    default: return HourglassForm::stiffness;  // 4, 5 (6-10 are refused where they are read)
  }
}

// *MAT_ADD_EROSION's criteria: each one whose value is not EXCL.
Erosion resolve_erosion(const model::MatAddErosion& card) {
  Erosion e;
  const auto criterion = [&](Real value) { return value != card.excl ? std::optional<Real>(value) : std::nullopt; };
  e.max_pressure = criterion(card.mxpres);
  e.min_pressure = criterion(card.mnpres);
  e.max_principal_stress = criterion(card.sigp1);
  e.von_mises = criterion(card.sigvm);
  e.max_principal_strain = criterion(card.mxeps);
  e.min_principal_strain = criterion(card.mneps);
  e.effective_strain = criterion(card.effeps);
  e.volumetric_strain = criterion(card.voleps);
  e.failure_time = criterion(card.failtm);
  e.criteria = static_cast<int>(card.ncs);
  e.points = static_cast<int>(card.numfip);
  return e;
}

// The part's hourglass control and bulk viscosity: its *HOURGLASS card (HGID), else
// *CONTROL_HOURGLASS, else the defaults. IHQ 0 means the global type, and with none given LS-DYNA's
// explicit default for solids, type 2 (fem-contact.md §1.2).
PartSettings resolve_part(const model::Model& model, const model::Part& part, const model::SectionSolid& section) {
  if (section.elform != 1 && section.elform != 2 && section.elform != 10) {
    const std::string what =
        section.elform == -1 || section.elform == -2
            ? "the fully integrated hexahedra for poor aspect ratios are not implemented; use 2"
            : "not implemented (Spall runs 1 one-point hexahedron, 2 fully integrated selective-reduced "
              "hexahedron, 10 one-point tetrahedron, and 47 SPG with *SECTION_SOLID_SPG)";
    fail_at(section.where, "*SECTION_SOLID", fmt::format("ELFORM {}: {}", section.elform, what));
  }
  if (section.aet != 0)
    fail_at(section.where, "*SECTION_SOLID", fmt::format("AET {}: ambient element types are not implemented", section.aet));
  PartSettings p;
  p.part_id = part.id;
  p.elform = section.elform;
  p.material = materials::make_material(model, part);
  const model::Hourglass* card = nullptr;
  if (part.hgid != 0) {
    auto it = model.hourglasses.find(part.hgid);
    if (it == model.hourglasses.end())
      fail_at(part.where, "*PART", fmt::format("part {}: HGID {}: no *HOURGLASS has that ID", part.id, part.hgid));
    card = &it->second;
  }
  const auto& control = model.control_hourglass;
  int ihq = card ? card->ihq : 0;
  if (ihq == 0 && control) ihq = control->ihq;
  const bool chosen = ihq == 0;
  if (chosen) ihq = 2;
  p.hourglass.form = section.elform == 1 ? hourglass_form(ihq) : HourglassForm::none;
  p.hourglass.coefficient = card ? card->qm : control ? control->qh : 0.1;
  p.bulk_quadratic = card && card->q1 > 0 ? card->q1 : model.bulk_viscosity.q1;
  p.bulk_linear = card && card->q2 > 0 ? card->q2 : model.bulk_viscosity.q2;
  if (auto it = model.add_erosions.find(part.mid); it != model.add_erosions.end())
    p.erosion = resolve_erosion(it->second);
  if (section.elform == 1 && chosen)
    log::info(fmt::format("part {}: one-point hexahedra with hourglass type 2 (Flanagan-Belytschko viscous, "
                          "QM {:g}): no IHQ given, LS-DYNA's explicit default for solids", part.id,
                          p.hourglass.coefficient));
  return p;
}

}  // namespace

void check_add_erosions(const model::Model& model) {
  for (const auto& [mid, card] : model.add_erosions) {
    if (!model.materials.contains(mid))
      fail_at(card.where, "*MAT_ADD_EROSION", fmt::format("MID {}: no material has that ID", mid));
    for (const auto& part : model.parts)
      if (part.mid == mid && !is_fem_part(model, part.id))
        fail_at(card.where, "*MAT_ADD_EROSION",
                fmt::format("MID {}: part {} uses it and is not meshed with solid finite elements; Spall deletes "
                         "elements only (SPH and SPG particles do not erode)", mid, part.id));
  }
}

bool is_fem_part(const model::Model& model, Id part_id) {
  const model::Part* part = model.find_part(part_id);
  return part && solid_section(model, *part);
}

std::unique_ptr<discretization::Formulation> build_fem(const model::Model& model,
                                                       const discretization::NodeIndex& index_of_node,
                                                       discretization::NodeStore& nodes) {
  check_add_erosions(model);
  std::vector<PartSettings> parts;
  std::map<Id, int> part_index;
  std::vector<ElementSetup> elements;
  for (const auto& e : model.solid_elements) {
    const model::Part* part = model.find_part(e.pid);
    const model::SectionSolid* section = part ? solid_section(model, *part) : nullptr;
    if (!section) continue;
    auto [it, inserted] = part_index.try_emplace(e.pid, static_cast<int>(parts.size()));
    if (inserted) parts.push_back(resolve_part(model, *part, *section));
    if (section->elform == 10 && !e.is_tetrahedron())
      fail_at(e.where, "*ELEMENT_SOLID",
              fmt::format("element {}: part {} has ELFORM 10 (tetrahedra) but the element is not written as one "
                       "(N1 N2 N3 N4 N4 N4 N4 N4)", e.eid, e.pid));
    ElementSetup setup;
    setup.id = e.eid;
    setup.part = it->second;
    for (int a = 0; a < 8; ++a) {
      const Index* node = index_of_node.find(e.n[a]);
      if (!node)
        fail_at(e.where, "*ELEMENT_SOLID", fmt::format("element {}: node {} does not exist", e.eid, e.n[a]));
      setup.node[a] = *node;
    }
    const Real volume = element_volume(setup.node, section->elform == 10, nodes);
    if (!(volume > 0))
      fail_at(e.where, "*ELEMENT_SOLID",
              fmt::format("element {}: volume {:.6g}: inverted or flat; check the node order (N1-N4 one face, "
                       "N5-N8 the opposite face, N1-N4 counter-clockwise seen from N5-N8)", e.eid, volume));
    elements.push_back(setup);
  }
  if (elements.empty()) return nullptr;
  auto formulation = std::make_unique<SolidElements>(std::move(parts), elements, nodes);
  formulation->add_nodal_masses(nodes);
  for (const auto& e : elements)
    for (Index i : e.node)
      if (nodes.part[i] == 0) nodes.part[i] = formulation->parts()[e.part].part_id;
  return formulation;
}

}  // namespace spall::fem
