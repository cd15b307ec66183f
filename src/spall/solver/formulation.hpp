#pragma once
// A discretization plugged into the time loop (SPH, later SPG, hexahedra). It owns its own state
// (densities, stresses, ...) and adds its internal forces to the shared node store.
#include <span>
#include <vector>

#include "spall/core/types.hpp"
#include "spall/io/output/vtu.hpp"
#include "spall/solver/node_store.hpp"

namespace spall::solver {

class Formulation {
 public:
  virtual ~Formulation() = default;

  virtual const char* name() const = 0;

  // Advances the formulation's state over `dt` (the step just taken, 0 at the first call) with the
  // current positions x^n and velocities v^{n-1/2}, then adds the internal forces at x^n to
  // nodes.f.
  virtual void compute_forces(NodeStore& nodes, Real dt) = 0;

  // The largest stable step, before TSSFAC, for the state of the last compute_forces (a
  // formulation may find it there; the time loop asks right after, with the same nodes).
  virtual Real stable_time_step(const NodeStore& nodes) const = 0;

  // Power of the last internal forces at the node velocities v (mid-step velocities): the rate
  // of stored (strain) energy and the rate of energy dissipated by artificial viscosity.
  struct Power {
    Real stored = 0;
    Real dissipated = 0;
  };
  virtual Power internal_power(std::span<const Vec3> v) const = 0;

  // Per-node output fields (pressure, von Mises stress, density, ...), node-aligned.
  virtual void add_fields(std::vector<io::output::PointField>& fields,
                          const NodeStore& nodes) const = 0;

  // Largest signal speed, for the runaway-velocity check.
  virtual Real max_wave_speed() const = 0;
};

}  // namespace spall::solver
