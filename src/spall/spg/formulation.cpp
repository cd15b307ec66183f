#include "spall/spg/formulation.hpp"

#include <algorithm>
#include <limits>

namespace spall::spg {

void SpgFormulation::compute_forces(solver::NodeStore& nodes, Real dt) {
  for (auto& part : parts_) part.compute_forces(nodes, dt);
}

Real SpgFormulation::stable_time_step(const solver::NodeStore& nodes) const {
  Real dt = std::numeric_limits<Real>::infinity();
  for (const auto& part : parts_) dt = std::min(dt, part.stable_time_step(nodes));
  return dt;
}

solver::Formulation::Power SpgFormulation::internal_power(std::span<const Vec3> v) const {
  Power p;
  for (const auto& part : parts_) {
    const auto q = part.internal_power(v);
    p.stored += q.stored;
    p.dissipated += q.dissipated;
  }
  return p;
}

void SpgFormulation::add_fields(std::vector<io::output::PointField>& fields,
                                const solver::NodeStore& nodes) const {
  const std::size_t n = nodes.id.size();
  Part::NodeFields f;
  f.pressure.assign(n, 0);
  f.von_mises.assign(n, 0);
  f.density.assign(n, 0);
  f.effective_plastic_strain.assign(n, 0);
  f.bond_damage.assign(n, 0);
  f.stress.assign(6 * n, 0);
  f.broken_bonds.assign(n, 0);
  f.bond_count.assign(n, 0);
  for (const auto& part : parts_) part.write_fields(f);
  fields.push_back({"pressure", 1, std::move(f.pressure)});
  fields.push_back({"von_mises", 1, std::move(f.von_mises)});
  fields.push_back({"density", 1, std::move(f.density)});
  fields.push_back({"stress", 6, std::move(f.stress)});
  fields.push_back({"effective_plastic_strain", 1, std::move(f.effective_plastic_strain)});
  fields.push_back({"broken_bonds", 1, std::move(f.broken_bonds)});
  fields.push_back({"bond_damage", 1, std::move(f.bond_damage)});
  fields.push_back({"bond_count", 1, std::move(f.bond_count)});
}

Real SpgFormulation::max_wave_speed() const {
  Real c = 0;
  for (const auto& part : parts_) c = std::max(c, part.max_wave_speed());
  return c;
}

Index SpgFormulation::particle_count() const {
  Index n = 0;
  for (const auto& part : parts_) n += part.particle_count();
  return n;
}

std::size_t SpgFormulation::memory_bytes() const {
  std::size_t b = 0;
  for (const auto& part : parts_) b += part.memory_bytes();
  return b;
}

}  // namespace spall::spg
