#include "spall/spg/formulation.hpp"

#include <algorithm>
#include <limits>

namespace spall::spg {

void SpgFormulation::compute_forces(discretization::NodeStore& nodes, Real dt) {
  const Part::HoldNodes hold = [&](parallel::Range places) { hold_nodes(nodes, places); };
  for (auto& part : parts_) part.compute_forces(nodes, dt, hold);
}

void SpgFormulation::hold_nodes(discretization::NodeStore& nodes, parallel::Range places) const {
  if (!nodes.window_by_reads) return;
  places = parallel::hull(places, {nodes.rank_begin[nodes.rank], nodes.rank_begin[nodes.rank + 1]});
  for (const auto& part : parts_) places = parallel::hull(places, part.places_read());
  nodes.hold_window(places.begin, places.end);
}

Real SpgFormulation::stable_time_step(const discretization::NodeStore& nodes) const {
  Real dt = std::numeric_limits<Real>::infinity();
  for (const auto& part : parts_) dt = std::min(dt, part.stable_time_step(nodes));
  return dt;
}

void SpgFormulation::book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                                   std::span<const Vec3> v, Real dt) const {
  // Part by part (each a collective), the parts' stored work also for *DATABASE_MATSUM when the
  // ledger keeps it: its particles' e leaves out the stabilization's springs and goes on where the
  // bonds have broken.
  discretization::InternalPower p;
  for (const auto& part : parts_) {
    const auto q = part.internal_power(nodes, v);
    p.stored += q.stored;
    p.dissipated += q.dissipated;
    if (const int slot = ledger.part_slot(part.settings().part_id); slot >= 0)
      ledger.add_part_work(static_cast<std::size_t>(slot), dt * q.stored);
  }
  discretization::book_internal_power(ledger, p, dt);
  if (!mass_scaled_) return;
  Real added = 0;
  for (const auto& part : parts_) added += part.added_mass_step();
  ledger.add(discretization::EnergyLedger::added_mass, discretization::EnergyLedger::Role::reported, added);
}

void SpgFormulation::sum_parts(discretization::PartSummary& parts, const discretization::NodeStore&) const {
  if (!mass_scaled_ || parallel::world().rank() != 0) return;  // each part's sum is every rank's already
  for (const auto& part : parts_)
    parts.add(part.settings().part_id, discretization::PartSummary::added_mass, part.added_mass());
}

bool SpgFormulation::scale_mass_below(Real step, bool first_step_only) {
  for (auto& part : parts_) part.scale_mass_below(step, first_step_only);
  mass_scaled_ = true;
  return true;
}

void SpgFormulation::complete_state(discretization::NodeStore& nodes) {
  for (auto& part : parts_) part.complete_state(nodes);
}

void SpgFormulation::share_state(discretization::NodeStore& nodes) {
  for (auto& part : parts_) part.share_velocities(nodes);
}

parallel::Range SpgFormulation::rows_read(const discretization::NodeStore& nodes) const {
  parallel::Range rows;
  for (const auto& part : parts_) rows = parallel::hull(rows, part.nodes_read(nodes));
  return rows;
}

void SpgFormulation::checkpoint(Archive& a, const discretization::NodeStore& /*nodes*/) {
  a.expect_size("SPG parts", parts_.size());
  for (auto& part : parts_) part.checkpoint(a);
  a(mass_scaled_);
}

void SpgFormulation::write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const {
  for (const auto& part : parts_) part.write_fields(fields, nodes);
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
