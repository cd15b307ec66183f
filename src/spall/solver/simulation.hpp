#pragma once
// The explicit time loop (central difference) as one step of named phases (docs/ARCHITECTURE.md):
//   internal forces -> contact (penalty) -> loads -> stable step -> velocity update (with SPCs)
//   -> halo (MPI: every rank's new velocities to every rank) -> constraints (prescribed motion,
//   rigid walls) -> energies -> output -> position update
// The stable step comes before the velocity update because the central difference with a varying
// step needs dt^{n+1/2} for v^{n+1/2} = v^{n-1/2} + a^n (dt^{n-1/2} + dt^{n+1/2}) / 2.
#include <array>
#include <functional>
#include <memory>
#include <string_view>

#include "spall/discretization/energy_ledger.hpp"
#include "spall/discretization/part_summary.hpp"
#include "spall/solver/load_balance.hpp"
#include "spall/solver/problem.hpp"

namespace spall::solver {

struct StepInfo {
  long long step = 0;
  Real time = 0;
  Real dt = 0;
};

// A history node's motion at t^n (*DATABASE_HISTORY_NODE): displacement x^n - X, velocity v^n,
// acceleration a^n (as the constraints left it: 2 (v^{n+1/2} - v^n) / dt^{n+1/2}; f / m at the
// last step, whose dt^{n+1/2} is 0) and position x^n.
struct NodeHistory {
  Id id = 0;
  Vec3 displacement, velocity, acceleration, position;
};

// A history element's state at t^n (*DATABASE_HISTORY_SOLID), the mean over its integration
// points: the stress (xx yy zz xy yz zx), pressure, von Mises stress and effective plastic strain,
// and whether it has eroded.
struct ElementHistory {
  Id id = 0;
  std::array<Real, 6> stress{};
  Real pressure = 0, von_mises = 0, plastic_strain = 0;
  bool eroded = false;
};

// The phases of a step, in the order they run.
enum class Phase { internal_forces, contact, loads, stable_step, velocity_update, halo, constraints, energies, output,
                   position_update, count };
std::string_view phase_name(Phase phase);

// Wall-clock seconds spent in each phase over a run.
struct PhaseTimes {
  std::array<double, static_cast<std::size_t>(Phase::count)> seconds{};
  double& operator[](Phase p) { return seconds[static_cast<std::size_t>(p)]; }
  double operator[](Phase p) const { return seconds[static_cast<std::size_t>(p)]; }
  double total() const;
};

// What the loop reports to whoever runs it (the CLI writes files; tests record histories).
struct Observer {
  // Field output at t^n (every D3PLOT interval, and at the end; without *DATABASE_BINARY_D3PLOT at
  // the first step and at the end).
  std::function<void(const StepInfo&, const Problem&)> on_field_output;
  // Energies at t^n (every GLSTAT interval, and at the end).
  std::function<void(const StepInfo&, const discretization::EnergyLedger&)> on_history;
  // Forces on the rigid walls at t^n (every RWFORC interval, GLSTAT's by default, and at the end).
  std::function<void(const StepInfo&, const std::vector<contact::RigidWall>&)> on_rigid_wall_forces;
  // Forces of the penalty contacts at t^n (every RCFORC interval, GLSTAT's by default, and at the end).
  std::function<void(const StepInfo&, const std::vector<contact::PenaltyContact>&)> on_contact_forces;
  // The rigid bodies after their update of this step (every RBDOUT interval, GLSTAT's by default,
  // and at the end).
  std::function<void(const StepInfo&, const rigid::RigidBodies&)> on_rigid_bodies;
  // The history nodes' motion at t^n, in the deck's order (every NODOUT interval, GLSTAT's by
  // default, and at the end); under MPI on every rank.
  std::function<void(const StepInfo&, const std::vector<NodeHistory>&)> on_node_histories;
  // The resultant of the SPCs' reactions at t^n (every SPCFORC interval, with *DATABASE_SPCFORC
  // only, and at the end); under MPI on every rank.
  std::function<void(const StepInfo&, const Vec3&)> on_spc_reaction;
  // The resultant of the prescribed motions' reactions at t^n and their work since the start
  // (every BNDOUT interval, with *DATABASE_BNDOUT only, and at the end); under MPI on every rank.
  std::function<void(const StepInfo&, const Vec3&, Real)> on_motion_reaction;
  // The parts' energies and momenta at t^n (every MATSUM interval, with *DATABASE_MATSUM only, and
  // at the end); under MPI on every rank.
  std::function<void(const StepInfo&, const discretization::PartSummary&)> on_part_summary;
  // The history elements' state at t^n, in the deck's order (every ELOUT interval, GLSTAT's by
  // default, and at the end); under MPI on every rank.
  std::function<void(const StepInfo&, const std::vector<ElementHistory>&)> on_element_histories;
  // Called on every step (cheap): for progress lines.
  std::function<void(const StepInfo&)> on_step;
};

struct RunSummary {
  long long steps = 0;
  Real end_time = 0;
  discretization::EnergyLedger energies;
  PhaseTimes phases;
};

// The time loop over one problem. run() goes to ENDTIM (or ENDCYC, or ENDENG); it throws
// InstabilityError when the solution becomes non-finite or runs away. between_steps, when given,
// is called after every step with the next one's start; run() returns early when it says false.
// phases() holds the time spent in each phase so far, also after such an error.
class TimeLoop {
 public:
  TimeLoop(Problem& problem, const Observer& observer, const LoadBalance& balance = {});
  ~TimeLoop();
  RunSummary run(const std::function<bool(const StepInfo&)>& between_steps = {});
  const PhaseTimes& phases() const;
  // How often the node blocks were dealt anew to even the ranks' work (LoadBalance).
  long long rebalances() const;
  // Under MPI: whether each step brings in only the velocities the formulations read (the halo by
  // reach) rather than every node's.
  bool velocities_by_reach() const;
  // The nodes' mass (every rank's) when the run began, before DT2MS added any (ENDMAS's base).
  Real initial_mass() const;
  // Between two steps (in between_steps, or before run()): writes the state of the problem and of
  // the loop into the archive, or reads it back over a problem built from the same deck, which
  // then continues bitwise as the run that wrote it (core/archive.hpp). Under MPI every rank calls
  // complete_state() first (a collective), then checkpoint() (collective too): rank 0 writes, and
  // where a deck is dealt by region each other rank writes its own rows and particles into the
  // same file at their place (core/pieces.hpp), keeping nothing else.
  void complete_state();
  void checkpoint(Archive& archive);

 private:
  class Step;
  std::unique_ptr<Step> step_;
};

// TimeLoop(problem, observer).run().
RunSummary run(Problem& problem, const Observer& observer);

}  // namespace spall::solver
