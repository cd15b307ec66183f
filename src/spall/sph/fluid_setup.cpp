#include "spall/sph/fluid_setup.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <optional>
#include <span>
#include <unordered_map>

#include "spall/core/first_failure.hpp"
#include "spall/core/log.hpp"
#include "spall/kernels/kernel.hpp"
#include "spall/materials/make_material.hpp"

namespace spall::sph {

namespace {

// A fluid part as the set-up needs it, checked once however many particles it has.
struct FluidPart {
  const model::Part* part = nullptr;
  const model::SectionSph* section = nullptr;
  FluidMaterial material;
  Real smoothing_length = 0;  // from SPHINI, or from CSLH and the largest spacing (below)
  Real spacing = 0;
};

FluidPart resolve_fluid_part(const model::Model& model, Id pid) {
  const model::Part& part = *model.find_part(pid);
  const auto sec = model.sections.find(part.secid);
  if (sec == model.sections.end() || !std::holds_alternative<model::SectionSph>(sec->second))
    fail_at(part.where, "*PART",
            fmt::format("part {} has SPH particles but section {} is not a *SECTION_SPH", part.id,
                     part.secid));
  const auto& section = std::get<model::SectionSph>(sec->second);
  if (!kernels::kernel_of_code(section.sphkern))
    fail_at(section.where, "*SECTION_SPH",
            fmt::format("SPHKERN {}: not implemented ({})", section.sphkern, kernels::kernel_codes));
  if (section.death < 1e20 || section.start > 0)
    fail_at(section.where, "*SECTION_SPH", "DEATH/START: particle birth and death are not implemented yet");
  if (part.hgid != 0)
    fail_at(part.where, "*PART",
            fmt::format("part {}: HGID {}: *HOURGLASS controls are not supported", part.id, part.hgid));
  // MAT_NULL + EOS through the material library (it refuses a MAT_NULL without EOS).
  const materials::Material library = materials::make_material(model, part);
  FluidPart fluid{&part, &section, {}, 0, 0};
  auto& m = fluid.material;
  m.density = library.density;
  m.eos = library.eos;
  m.specific_energy = library.initial_specific_energy;
  m.dynamic_viscosity = std::get<materials::Null>(library.strength).viscosity;
  m.pressure_cutoff = library.pressure_cutoff;  // MAT_NULL PC (0: no tension)
  if (!(m.density > 0))
    fail_at(part.where, "*PART", fmt::format("part {}: its *MAT_NULL needs RO > 0", part.id));
  if (!(m.reference_sound_speed() > 0))
    fail_at(part.where, "*PART",
            fmt::format("part {}: the equation of state {} gives no sound speed at RO {:g}; a "
                     "liquid needs dp/drho > 0",
                     part.id, part.eosid, m.density));
  return fluid;
}

// LS-DYNA varies h with the density by default (HMIN 0.2, HMAX 2); a weakly compressible liquid
// changes density by about 1 %, so h would change by under 1 %: the fluid keeps h constant and
// says so once.
void warn_constant_h_once(const model::SectionSph& section, bool& warned) {
  if (warned || (section.hmin == 1.0 && section.hmax == 1.0)) return;
  warned = true;
  log::warning(fmt::format("{}: *SECTION_SPH: HMIN {} HMAX {}: the SPH fluid keeps its "
                           "smoothing length constant (its density varies by about 1 %); set "
                           "HMIN = HMAX = 1.0 to say so in the deck",
                           to_string(section.where), section.hmin, section.hmax));
}

}  // namespace

bool is_fluid_part(const model::Model& model, Id pid) {
  const model::Part* part = model.find_part(pid);
  if (!part) return false;
  const auto mat = model.materials.find(part->mid);
  return mat != model.materials.end() && std::holds_alternative<model::MatNull>(mat->second.params);
}

std::vector<FirstParticle> parts_by_first_particle(const model::Model& model,
                                                   const std::vector<ParticleCard>& particles,
                                                   const parallel::Communicator* across) {
  std::vector<FirstParticle> firsts;
  for (const auto& p : particles)
    if (std::none_of(firsts.begin(), firsts.end(), [&](const FirstParticle& f) { return f.pid == p.element->pid; }))
      firsts.push_back({p.element->pid, p.ordinal, model.card_line(p.element->where)});
  if (across) firsts = across->all(std::span<const FirstParticle>(firsts));
  std::sort(firsts.begin(), firsts.end(),
            [](const FirstParticle& a, const FirstParticle& b) { return a.ordinal < b.ordinal; });
  return firsts;
}

std::unique_ptr<FluidFormulation> build_fluid(const model::Model& model,
                                                   const std::vector<ParticleCard>& particles,
                                                   const ArtificialViscosity& viscosity,
                                                   int dimension, discretization::NodeStore& nodes,
                                                   const parallel::Communicator* across) {
  if (const auto& c = model.control_sph; c && (c->start > 0 || c->dt < 1e20))
    fail_at(c->card_where[0], "*CONTROL_SPH",
            fmt::format("START {:g} / DT {:g}: the SPH fluid has no start or death time", c->start, c->dt));
  // The first failure in the deck's order, at a particle's card: there its plane (0), then its part's
  // set-up when it is the part's first particle (1), then its mass (2).
  std::int64_t position = -1;
  std::optional<InputError> error;
  const auto fail = [&](Index ordinal, int what, const InputError& e) {
    const std::int64_t at = 3 * std::int64_t(ordinal) + what;
    if (position < 0 || at < position) position = at, error = e;
  };

  // The parts in the order of their first particles (over the ranks), each set up there.
  const std::vector<FirstParticle> firsts = parts_by_first_particle(model, particles, across);
  std::unordered_map<Id, FluidPart> parts;
  const FluidPart* first = nullptr;
  bool warned = false;
  for (const FirstParticle& f : firsts) {
    if (parts.contains(f.pid)) continue;  // a later rank's first of a part set up already
    try {
      const FluidPart& part = parts.emplace(f.pid, resolve_fluid_part(model, f.pid)).first->second;
      warn_constant_h_once(*part.section, warned);
      // One liquid: the parts (fluid and its dynamic-boundary walls) share one material.
      if (!first) {
        first = &part;
      } else if (part.section->sphkern != first->section->sphkern) {
        fail_at(part.section->where, "*SECTION_SPH",
                fmt::format("part {}: SPHKERN {}, but SPH fluid part {} has SPHKERN {}: the SPH fluid's "
                            "particles interact through one kernel",
                            part.part->id, part.section->sphkern, first->part->id, first->section->sphkern));
      } else if (part.part->mid != first->part->mid || part.part->eosid != first->part->eosid) {
        fail_at(part.part->where, "*PART",
                fmt::format("part {}: MID {} EOSID {}, but SPH fluid part {} has MID {} EOSID {}: "
                         "the SPH fluid takes one liquid (one MID and EOSID for all its parts)",
                         part.part->id, part.part->mid, part.part->eosid, first->part->id,
                         first->part->mid, first->part->eosid));
      }
    } catch (const InputError& e) {
      fail(f.ordinal, 1, e);
      parts.erase(f.pid);
      break;  // the parts after it are not reached
    }
  }

  // In plane strain every particle lies in the plane of the deck's first.
  struct Plane {
    Index ordinal;
    Real z;
    Id nid;
  };
  const auto z = [&](const ParticleCard& p) { return nodes.x0[p.node].z(); };
  Plane plane{0, particles.empty() ? 0 : z(particles.front()), particles.empty() ? 0 : particles.front().element->nid};
  if (across && dimension == 2) {
    const Index lowest = across->lowest(particles.empty() ? -1 : particles.front().ordinal);
    const bool mine = !particles.empty() && particles.front().ordinal == lowest;
    plane = across->all(std::span<const Plane>(&plane, mine ? 1 : 0)).front();
  }
  for (const auto& p : particles) {
    const model::ElementSph& e = *p.element;
    // Refused here, at the particle's card: the formulation would stop with an internal error.
    if (dimension == 2 && z(p) != plane.z)
      fail(p.ordinal, 0,
           InputError(e.where, "*ELEMENT_SPH",
                      fmt::format("particle {} lies at z = {:g}, off the plane z = {:g} of particle {}: in plane "
                                  "strain (*CONTROL_SPH IDIM 2) every particle of the SPH fluid lies in one plane",
                                  e.nid, z(p), plane.z, plane.nid)));
    const auto found = parts.find(e.pid);
    if (found == parts.end()) continue;  // its part failed: a failure before this particle's
    FluidPart& part = found->second;
    const Real mass = e.mass > 0 ? e.mass : -e.mass * part.material.density;
    if (!(mass > 0)) {
      fail(p.ordinal, 2, InputError(e.where, "*ELEMENT_SPH", fmt::format("MASS: particle {} has no mass", e.nid)));
      continue;
    }
    // In plane strain masses are per unit thickness and the particles stay in their plane.
    const Real spacing = dimension == 2 ? std::sqrt(mass / part.material.density)
                                        : std::cbrt(mass / part.material.density);
    part.spacing = std::max(part.spacing, spacing);
    nodes.mass[p.node] = mass;
    nodes.part[p.node] = e.pid;
    if (dimension == 2) nodes.fixed[p.node] |= 1u << 2;
  }
  if (across) {
    parallel::throw_first_failure(position, error, *across);
    std::vector<double> spacing;  // the largest of each part over the ranks
    for (const FirstParticle& f : firsts) spacing.push_back(parts.at(f.pid).spacing);
    across->maximum(spacing);
    for (std::size_t k = 0; k < firsts.size(); ++k) parts.at(firsts[k].pid).spacing = spacing[k];
  } else if (error) {
    throw *error;
  }
  // LS-DYNA: h = CSLH x initial spacing, unless SPHINI gives h; the fluid takes one h for all.
  Real h = 0;
  const FluidPart* h_part = nullptr;
  for (auto& [pid, part] : parts) {
    part.smoothing_length =
        part.section->sphini > 0 ? part.section->sphini : part.section->cslh * part.spacing;
    if (!h_part || part.part->id < h_part->part->id) h = part.smoothing_length, h_part = &part;
  }
  for (const auto& [pid, part] : parts)
    if (std::abs(part.smoothing_length - h) > 1e-9 * h)
      fail_at(part.section->where, "*SECTION_SPH",
              fmt::format("part {} has h = {:g} but SPH fluid part {} has h = {:g}: the SPH fluid "
                       "takes one smoothing length (give its parts the same spacing and CSLH, "
                       "or SPHINI)",
                       part.part->id, part.smoothing_length, h_part->part->id, h));
  FluidParameters parameters;
  parameters.material = first->material;
  parameters.smoothing_length = h;
  parameters.kernel = *kernels::kernel_of_code(first->section->sphkern);  // checked by resolve_fluid_part
  parameters.viscosity = viscosity;
  parameters.dimension = dimension;
  std::vector<Index> particle_nodes;
  particle_nodes.reserve(particles.size());
  for (const auto& p : particles) particle_nodes.push_back(p.node);
  std::sort(particle_nodes.begin(), particle_nodes.end());  // node (cell) order
  return std::make_unique<FluidFormulation>(parameters, particle_nodes, nodes);
}

}  // namespace spall::sph
