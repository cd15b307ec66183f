#pragma once
// The explicit time loop (central difference), as DESIGN draws it:
//   1. each formulation advances its state and adds internal forces at x^n
//   2. loads (base accelerations)
//   3. v^{n+1/2} = v^{n-1/2} + a^n (dt^{n-1/2} + dt^{n+1/2}) / 2, then SPCs and prescribed motion,
//      then rigid walls
//   4. energies and output at t^n, then x^{n+1} = x^n + v^{n+1/2} dt^{n+1/2}
//   5. dt = TSSFAC * min(stable step of every formulation)
#include <filesystem>
#include <functional>
#include <optional>

#include "spall/solver/problem.hpp"

namespace spall::solver {

// The global energy balance at t^n, as LS-DYNA's glstat: kinetic energy from the mid-step
// velocities, internal (strain) energy and artificial-viscosity dissipation integrated from the
// power of the internal forces, external work of loads and constraints.
struct Energies {
  Real kinetic = 0;
  Real internal = 0;
  Real artificial_viscosity = 0;
  Real external_work = 0;
  Real initial_total = 0;
  Real total() const { return kinetic + internal + artificial_viscosity; }
  // total / (initial + external work): 1 for a perfectly conserving run.
  Real ratio() const {
    const Real reference = initial_total + external_work;
    return reference != 0 ? total() / reference : 1;
  }
};

struct StepInfo {
  long long step = 0;
  Real time = 0;
  Real dt = 0;
};

// What the loop reports to whoever runs it (the CLI writes files; tests record histories).
struct Observer {
  // Field output at t^n (every D3PLOT interval, and at the end).
  std::function<void(const StepInfo&, const Problem&)> on_field_output;
  // Energies at t^n (every GLSTAT interval, and at the end).
  std::function<void(const StepInfo&, const Energies&)> on_history;
  // Forces on the rigid walls at t^n (every RWFORC interval, GLSTAT's by default, and at the end).
  std::function<void(const StepInfo&, const std::vector<contact::RigidWall>&)> on_rigid_wall_forces;
  // Called on every step (cheap): for progress lines.
  std::function<void(const StepInfo&)> on_step;
};

struct RunSummary {
  long long steps = 0;
  Real end_time = 0;
  Energies energies;
};

// Runs to ENDTIM (or ENDCYC). Throws InstabilityError (after a last field output) when the
// solution becomes non-finite or runs away.
RunSummary run(Problem& problem, const Observer& observer);

}  // namespace spall::solver
