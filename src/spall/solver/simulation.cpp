#include "spall/solver/simulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/log.hpp"
#include "spall/core/parallel.hpp"

namespace spall::solver {

using discretization::EnergyLedger;
using Role = EnergyLedger::Role;

std::string_view phase_name(Phase phase) {
  static constexpr std::string_view names[] = {"internal_forces", "contact", "loads", "stable_step",
                                               "velocity_update", "halo", "constraints", "energies", "output",
                                               "position_update"};
  static_assert(std::size(names) == static_cast<std::size_t>(Phase::count));
  return names[static_cast<std::size_t>(phase)];
}

double PhaseTimes::total() const {
  double sum = 0;
  for (double s : seconds) sum += s;
  return sum;
}

namespace {

// The first output time after `now` on the grid start + k * interval (intervals smaller than a
// step give one output per step).
Real next_output_time(Real start, Real interval, Real now) {
  if (!(interval > 0)) return std::numeric_limits<Real>::infinity();
  const Real k = std::floor((now - start) / interval) + 1;
  return start + std::max(k, Real(1)) * interval;
}

// An output on the grid start + k * interval(t), where the interval may follow a curve.
struct OutputSchedule {
  Real interval = 0;
  const model::Curve* interval_curve = nullptr;
  Real next = 0;

  bool enabled() const { return interval > 0 || interval_curve; }
  // Whether an output is due at t (always at the last step); advances the schedule if it is.
  bool due(Real t, Real tolerance, bool last) {
    if (!(t + tolerance >= next || last)) return false;
    next = next_output_time(next, interval_curve ? interval_curve->value(t) : interval, t + tolerance);
    return true;
  }
  void checkpoint(Archive& a) { a(interval, next); }
};

}  // namespace

// One step of the central-difference scheme, phase by phase; the state that lives from one step
// to the next (time, last step, energies, output schedules) is its members.
class TimeLoop::Step {
 public:
  Step(Problem& problem, const Observer& observer, const LoadBalance& balance)
      : problem_(problem), nodes_(problem.nodes), controls_(problem.controls), observer_(observer), balance_(balance) {
    field_output_ = {controls_.d3plot_dt, controls_.d3plot_dt_curve};
    history_ = {controls_.glstat_dt, nullptr};
    rwforc_ = {controls_.rwforc_dt, controls_.rwforc_dt_curve};
    rcforc_ = {controls_.rcforc_dt, controls_.rcforc_dt_curve};
    rbdout_ = {controls_.rbdout_dt, controls_.rbdout_dt_curve};
    nodout_ = {controls_.nodout_dt, controls_.nodout_dt_curve};
    spcforc_ = {controls_.spcforc_dt, controls_.spcforc_dt_curve};
    elout_ = {controls_.elout_dt, controls_.elout_dt_curve};
    bndout_ = {controls_.bndout_dt, controls_.bndout_dt_curve};
    matsum_ = {controls_.matsum_dt, controls_.matsum_dt_curve};
    if (controls_.matsum) ledger_.keep_part_work(controls_.matsum_parts);
    runaway_speed_limit_ = runaway_speed_limit();
    // Over every node: each rank's block of them, summed over the ranks, when the set-up built blocks.
    initial_mass_ = parallel::exact_sum(nodes_.size(), [&](Index i) { return nodes_.mass[i]; },
                                        nodes_.holds_a_block() ? &parallel::world() : nullptr);
    // Each rank searches its own slave nodes against every segment and computes every body whole,
    // moving every body's nodes: with a contact whose segments are not all a body's, a formulation
    // that reads the other ranks' nodes beyond what it brings in, or a body or contact among
    // formulations that move their nodes between the ranks (dealt by region, which the bodies'
    // forces do not follow), every velocity. A rigid wall acts on a rank's own nodes then (a moving
    // one solved from every rank's).
    const parallel::Communicator& ranks = parallel::world();
    const auto every = [&](auto&& is) { return std::all_of(problem_.formulations.begin(), problem_.formulations.end(), is); };
    const bool bodies_and_contacts = !problem_.contacts.empty() || !problem_.rigid_bodies.empty();
    const bool migrating = !problem_.formulations.empty() && every([](const auto& f) { return f->migrates(); });
    halo_by_reach_ = every([](const auto& f) { return f->halo_by_reach(); }) &&
                     std::all_of(problem_.contacts.begin(), problem_.contacts.end(),
                                 [&](const auto& c) { return c.segments_rigid(nodes_); }) &&
                     !(bodies_and_contacts && migrating);
    nodes_.velocities_by_reach = halo_by_reach_ && ranks.size() > 1;
    // Under MPI each rank computes its share of the nodes and holds them all (docs/SCALING.md): by
    // region when every formulation moves its nodes between the ranks as they flow, else in blocks.
    if (ranks.size() > 1) {
      if (halo_by_reach_ && migrating) {
        // The work is in the particles that move (a fluid's fixed wall particles only lend their
        // density to the pairs): a node with mass weighs 1 unless an SPC holds it still; the
        // measured work corrects the cuts later (balance()).
        // Each rank brings a block of the nodes to the cut (the rows it holds when the set-up built
        // a block of them).
        const bool held = nodes_.holds_a_block();
        const Index begin = held ? 0 : parallel::block_begin(nodes_.size(), ranks.rank(), ranks.size());
        const Index end = held ? nodes_.size() : parallel::block_begin(nodes_.size(), ranks.rank() + 1, ranks.size());
        std::vector<double> weight(end - begin);
        for (Index i = begin; i < end; ++i)
          weight[i - begin] = nodes_.mass[i] > 0 && (nodes_.fixed[i] & 7u) != 7u ? 1 : 0;
        const std::span<const Vec3> x(nodes_.x.data() + begin, end - begin);
        nodes_.deal(discretization::Regions::cut(x, weight, ranks.size(), ranks), ranks.rank());
      } else {
        // The set-up's blocks when it built one on each rank (the window of it from now on).
        const bool held = nodes_.holds_a_block();
        nodes_.deal(parallel::block_offsets(nodes_.deck_node_count(), ranks.size()), ranks.rank());
        // One formulation that brings in every node it reads, with no body or contact to read
        // others: a rank holds the window of the nodes it computes and reads (docs/SCALING.md §5).
        nodes_.window_by_reads = halo_by_reach_ && problem_.formulations.size() == 1 &&
                                 problem_.formulations.front()->holds_window() && !bodies_and_contacts;
        if (held && !nodes_.window_by_reads)
          throw std::logic_error("time loop: the set-up built blocks of the nodes, which no formulation holds as windows");
      }
    }
    // The loads are measured from here: the set-up's collectives (the cut among them) are not a
    // rank's work, nor the time it waited in them.
    checked_at_ = std::chrono::steady_clock::now();
    communicating_at_check_ = ranks.communicating_seconds();
    parallel::for_each(nodes_.size(), [&](Index i) { nodes_.f[i] = Vec3::Zero(); });
  }

  // Advances by one step; false once the run has ended (after the last output).
  bool advance() {
    balance();
    timed(Phase::internal_forces, [&] { internal_forces(); });
    timed(Phase::contact, [&] { contact(); });
    timed(Phase::loads, [&] { loads(); });
    timed(Phase::stable_step, [&] { stable_step(); });
    timed(Phase::velocity_update, [&] { velocity_update(); });
    // By reach each rank constrains its own nodes, whose velocities then travel; otherwise every
    // rank constrains every node alike, once they have all come in.
    if (!halo_by_reach_) timed(Phase::halo, [&] { halo(); });
    timed(Phase::constraints, [&] { constraints(); });
    if (halo_by_reach_) timed(Phase::halo, [&] { halo(); });
    timed(Phase::energies, [&] { energies(); });
    bool more = true;
    timed(Phase::output, [&] { more = output(); });
    if (!more) return false;
    timed(Phase::position_update, [&] { position_update(); });
    return true;
  }

  RunSummary summary() const { return {step_.step, step_.time, ledger_, phases_}; }
  long long rebalances() const { return rebalances_; }
  bool velocities_by_reach() const { return nodes_.velocities_by_reach; }
  Real initial_mass() const { return initial_mass_; }
  const PhaseTimes& phases() const { return phases_; }
  const StepInfo& info() const { return step_; }

  void complete_state() {
    for (auto& f : problem_.formulations) f->complete_state(nodes_);
    for (auto& wall : problem_.rigid_walls) wall.complete_state();
    for (auto& c : problem_.contacts) c.complete_state();
  }

  // Between two steps: the problem's state (nodes, formulations, walls, contacts, bodies), then the
  // loop's own (time, last steps, energies, output schedules, the time spent in each phase).
  void checkpoint(Archive& a) {
    a.section("problem");
    a(nodes_);
    a.expect_size("formulations", problem_.formulations.size());
    for (auto& f : problem_.formulations) {
      a.section(f->name());
      f->checkpoint(a, nodes_);
    }
    a.expect_size("rigid walls", problem_.rigid_walls.size());
    for (auto& wall : problem_.rigid_walls) wall.checkpoint(a);
    a.section("contacts 2");
    a.expect_size("contacts", problem_.contacts.size());
    for (auto& c : problem_.contacts) c.checkpoint(a);
    a(problem_.rigid_bodies);
    a.section("time loop 7");
    a(step_, dt_previous_, dt_first_, dt_mid_, velocity_weight_, base_acceleration_, damping_,
      runaway_speed_limit_, initial_mass_, field_output_, history_, rwforc_, rcforc_, rbdout_, nodout_, spcforc_,
      elout_, bndout_, matsum_, motion_work_, ledger_, phases_);
  }

 private:
  // Under MPI, at the checks of balance_ (LoadBalance::checks_at): each rank's own work since the last check;
  // past the threshold, the nodes are dealt anew: the blocks moved, or the regions cut again with
  // each node weighing its rank's work over its rank's nodes (the nodes move into them at the next rebuild).
  // Every rank takes the decision from the same numbers, so all take it alike.
  void balance() {
    const parallel::Communicator& ranks = parallel::world();
    if (ranks.size() == 1 || !balance_.checks_at(step_.step)) return;
    const auto now = std::chrono::steady_clock::now();
    const std::vector<double> work = ranks.each(std::chrono::duration<double>(now - checked_at_).count() -
                                                (ranks.communicating_seconds() - communicating_at_check_));
    checked_at_ = now;
    communicating_at_check_ = ranks.communicating_seconds();
    const double mean = std::accumulate(work.begin(), work.end(), 0.0) / ranks.size();
    if (!(*std::max_element(work.begin(), work.end()) > (1 + balance_.threshold) * mean)) return;
    if (nodes_.by_region()) {
      // Each rank brings its own nodes to the cut, each with mass weighing its rank's work over
      // their number; the nodes then migrate to their new regions' ranks with their particles.
      std::vector<Vec3> x;
      std::vector<double> weight;
      for (const Index i : nodes_.owned) {
        x.push_back(nodes_.x[i]);
        weight.push_back(nodes_.mass[i] > 0 ? 1 : 0);
      }
      const double with_mass = std::accumulate(weight.begin(), weight.end(), 0.0);
      const double each = with_mass > 0 ? std::max(work[ranks.rank()], 0.0) / with_mass : 0;
      for (double& w : weight) w *= each;
      nodes_.recut(discretization::Regions::cut(x, weight, ranks.size(), ranks));
    } else {
      nodes_.deal(balanced_blocks(nodes_.rank_begin, work), ranks.rank());
    }
    ++rebalances_;
  }

  template <class Work>
  void timed(Phase phase, Work&& work) {
    const auto start = std::chrono::steady_clock::now();
    work();
    phases_[phase] += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }

  // No material point outruns ten times the fastest wave plus the fastest initial motion.
  Real runaway_speed_limit() const {
    Real c = 0, v0 = 0;
    for (const auto& f : problem_.formulations) c = std::max(c, f->max_wave_speed());
    for (Index i = 0; i < nodes_.size(); ++i) v0 = std::max(v0, nodes_.v[i].norm());
    if (nodes_.holds_a_block()) {
      v0 = parallel::world().largest(v0);
    }
    return c > 0 ? 10 * (c + v0) : std::numeric_limits<Real>::infinity();
  }

  // A speed that is not finite or above the limit, compared squared (a NaN fails the comparison;
  // without a limit, the largest double stands for it).
  bool runaway(Index i) const {
    const Real limit = runaway_speed_limit_;
    const Real bound = std::isfinite(limit) ? limit * limit : std::numeric_limits<Real>::max();
    return !(nodes_.v[i].squaredNorm() <= bound) || !nodes_.x[i].allFinite();
  }

  // Internal forces at x^n of every formulation (f was cleared by the last position update).
  void internal_forces() {
    try {
      for (auto& f : problem_.formulations) f->compute_forces(nodes_, dt_previous_);
    } catch (const InstabilityError& e) {
      // A formulation found its state broken (a material point, a particle's neighbourhood): the
      // same step and time as the runaway check gives.
      throw InstabilityError(
          fmt::format("numerical instability at step {}, time {:.6g}: {}", step_.step, step_.time, e.what()));
    }
  }

  // Penalty contact forces at x^n, from the slip of v^{n-1/2} over the last step, on the surfaces
  // as this step's erosion left them. The soft constraint's stiffness takes the first step, known
  // only now. Under MPI each rank finds and
  // answers the touches of its own slave nodes from the positions, velocities and masses every rank
  // holds, and every rank then adds every touch's forces to the nodes in the order one process does
  // (replicated state, docs/SCALING.md).
  void contact() {
    if (step_.step == 0 && !problem_.contacts.empty()) {
      const Real dt = step_limit();
      for (auto& c : problem_.contacts) c.set_first_step(std::isfinite(dt) ? dt : controls_.end_time);
    }
    if (!problem_.contacts.empty()) {
      std::vector<Id> eroded;
      for (const auto& f : problem_.formulations) {
        const std::span<const Id> ids = f->eroded_elements();
        eroded.insert(eroded.end(), ids.begin(), ids.end());
      }
      if (!eroded.empty()) {
        std::sort(eroded.begin(), eroded.end());
        for (auto& c : problem_.contacts) c.erode(eroded);
      }
    }
    for (auto& c : problem_.contacts) c.apply(nodes_, step_.time, dt_previous_);
  }

  // Base accelerations a(t): every node with mass feels the inertial force -m a (LS-DYNA's
  // *LOAD_BODY convention); *DAMPING_GLOBAL: -D m v on the velocity of the last half step. Both
  // are counted as external work (energies()).
  void loads() {
    base_acceleration_ = Vec3::Zero();
    for (const auto& load : problem_.base_accelerations)
      base_acceleration_[load.direction] += load.sf * load.curve->value(step_.time);
    damping_ = (controls_.damping_curve ? controls_.damping_curve->value(step_.time) : controls_.damping) *
               controls_.damping_scale;
    if (base_acceleration_.isZero(0) && damping_.isZero(0)) return;
    // Under MPI on this rank's nodes: the others' velocities come from their ranks (halo).
    parallel::for_each(nodes_.owned_count(), [&](Index k) {
      const Index i = nodes_.owned_node(k);
      nodes_.f[i] -= load_force(i, nodes_.v[i]);
    });
  }

  Vec3 load_force(Index i, const Vec3& v) const {
    return nodes_.mass[i] * (base_acceleration_ + damping_.cwiseProduct(v));
  }

  // TSSFAC x the smallest stable step of every formulation, within LCTM and, on the first step,
  // DTINIT; infinite when nothing limits it.
  Real step_limit() const {
    Real dt = std::numeric_limits<Real>::infinity();
    for (const auto& f : problem_.formulations) dt = std::min(dt, f->stable_time_step(nodes_));
    dt *= controls_.tssfac;
    if (controls_.max_dt_curve) dt = std::min(dt, controls_.max_dt_curve->value(step_.time));
    if (step_.step == 0 && controls_.dt_initial > 0) dt = std::min(dt, controls_.dt_initial);
    return dt;
  }

  // dt^{n+1/2} = TSSFAC x the smallest stable step of every formulation (a global minimum: under
  // MPI, over the ranks too), within LCTM, DTINIT and the end time.
  void stable_step() {
    Real dt = step_limit();
    if (step_.step == 0) {
      dt_first_ = dt;
      // ERODE: elements whose own step x TSSFAC would fall below DTMIN x dt0 are deleted instead.
      if (controls_.erode)
        for (const auto& f : problem_.formulations) f->erode_below(controls_.dt_min_factor * dt_first_ / controls_.tssfac);
    }
    if (!std::isfinite(dt)) dt = controls_.end_time;  // nothing limits the step (no formulation)
    // DTMIN judges the stable step, not the last step shortened to land on ENDTIM.
    if (controls_.dt_min_factor > 0 && dt < controls_.dt_min_factor * dt_first_ && step_.time < controls_.end_time)
      throw InstabilityError(fmt::format("time step {:.6g} at step {}, time {:.6g} fell below DTMIN x initial step ({:.6g})",
                                         dt, step_.step, step_.time, controls_.dt_min_factor * dt_first_));
    dt = std::min(dt, controls_.end_time - step_.time);
    step_.dt = dt;
    dt_mid_ = step_.step == 0 ? Real(0.5) * dt : Real(0.5) * (dt_previous_ + dt);
    // Where v^n lies between v^{n-1/2} and v^{n+1/2} (see energies()).
    velocity_weight_ = (dt_previous_ + dt) > 0 ? dt_previous_ / (dt_previous_ + dt) : Real(0.5);
  }

  // v^{n+1/2} = v^{n-1/2} + dt^n f / m on the active nodes with mass, with the components an SPC
  // holds set to zero in the same pass; v^{n-1/2} kept for the energies. Under MPI the other
  // ranks' nodes get theirs in the halo phase; by reach a rank's own nodes alone pass here (the
  // constraints and energies read no other's v^{n-1/2} then), else every node, whose v^{n-1/2}
  // the constraints and contacts read.
  void velocity_update() {
    const Real dt_mid = dt_mid_;
    // Sized to the rows, its storage too: with rows of its own, a rank's nodes change at rebuilds,
    // and a window of the nodes is held from the first step on (the set-up's every node would stay).
    if (v_old_.size() != static_cast<std::size_t>(nodes_.size())) v_old_ = std::vector<Vec3>(nodes_.size());
    const bool own_only = nodes_.velocities_by_reach;
    parallel::for_each(own_only ? nodes_.owned_count() : nodes_.size(), [&](Index k) {
      const Index i = own_only ? nodes_.owned_node(k) : k;
      v_old_[i] = nodes_.v[i];
      if (nodes_.mass[i] <= 0 || !nodes_.active[i] || !nodes_.owns(i)) return;
      Vec3 v_new = nodes_.v[i] + (dt_mid / nodes_.mass[i]) * nodes_.f[i];
      for (int d = 0; d < 3; ++d)
        if (nodes_.fixed[i] & (1u << d)) v_new[d] = 0;
      nodes_.v[i] = v_new;
    });
    // The bodies' nodes, which every rank moves: their v^{n-1/2}, for the contacts' energies.
    if (own_only)
      for (const Index i : problem_.rigid_bodies.node_rows())
        if (!nodes_.owns(i)) v_old_[i] = nodes_.v[i];
  }

  // Rigid bodies, prescribed motion at the mid-step, then the rigid walls (last, so that no
  // constraint carries a node through a wall).
  void constraints() {
    const Real dt = step_.dt, t_mid = step_.time + Real(0.5) * dt;
    // By reach the bodies' nodes' forces come in here, before the halo: each body sums them all.
    if (nodes_.velocities_by_reach) problem_.rigid_bodies.share_forces(nodes_);
    problem_.rigid_bodies.advance(nodes_, step_.time, dt, dt_mid_);
    // The driven nodes' rows (with rows of its own or a window they change: NodeStore::layout).
    if (motion_rows_layout_ != nodes_.layout) {
      motion_row_.clear();
      for (const auto& m : problem_.motions) motion_row_.push_back(nodes_.row_of(m.node));
      motion_rows_layout_ = nodes_.layout;
    }
    for (std::size_t k = 0; k < problem_.motions.size(); ++k) {
      const NodalMotion& m = problem_.motions[k];
      const Index i = motion_row_[k];
      if (i < 0 || t_mid < m.birth || t_mid > m.death) continue;  // not held here, or not now
      if (nodes_.velocities_by_reach && !nodes_.owns(i)) continue;  // its rank's, whose v comes in
      Real& v = nodes_.v[i][m.direction];
      switch (m.vad) {
        case 0: v = m.sf * m.curve->value(t_mid); break;
        case 1: v = v_old_[i][m.direction] + dt_mid_ * m.sf * m.curve->value(step_.time); break;
        case 2: {
          const Real u_next = m.sf * m.curve->value(step_.time + dt);
          const Real u_now = nodes_.x[i][m.direction] - nodes_.x0[i][m.direction];
          v = dt > 0 ? (u_next - u_now) / dt : 0;
          break;
        }
      }
    }
    for (auto& wall : problem_.rigid_walls) wall.enforce(nodes_, t_mid, dt, dt_mid_);
  }

  // Under MPI: every rank's new velocities v^{n+1/2} of its own nodes, and the formulations' state
  // of them, to every rank. Positions need nothing: each rank advances every node by the same
  // arithmetic from the same velocities. Before the constraints, so that every rank applies the
  // walls, prescribed motions and rigid bodies to every node alike (a wall's force is then whole on
  // each). A rigid body sums the forces of all its nodes: with bodies, the nodes' forces too. When
  // every formulation brings in the velocities it reads (halo_by_reach), only those travel, after
  // the constraints, which each rank then applies to its own nodes (a wall's force summed over the
  // ranks, a body's forces from their nodes' ranks); the others' nodes go stale until a
  // formulation completes them, but for the bodies', which every rank moves.
  void halo() {
    const parallel::Communicator& ranks = parallel::world();
    if (ranks.size() == 1) return;
    if (!halo_by_reach_) {
      ranks.share(std::span(nodes_.v), nodes_.rank_begin);
      if (!problem_.rigid_bodies.empty()) ranks.share(std::span(nodes_.f), nodes_.rank_begin);
    }
    for (auto& f : problem_.formulations) f->share_state(nodes_);
  }

  // The ledger at t^n. v^n = v^{n-1/2} + a^n dt^{n-1/2} / 2 is the point dt^{n-1/2} /
  // (dt^{n-1/2} + dt^{n+1/2}) of the way from v^{n-1/2} to v^{n+1/2} (the mean of the two only
  // when the steps are equal; v^0 at the start, v^{n+1/2} at the shortened last step). External
  // power at v^n, with v^{n+1/2} as the constraints left it: of the loads, and of the constraint
  // reactions r = m dv/dt - f on every held or driven component and on every node a wall pushed.
  // The reactions' power on the first step is taken at the mean of v^0 and v^{1/2} instead: a
  // constraint that changes the initial velocity (a wall stopping a node that starts on it, a
  // motion that starts at once) acts as an impulse at t^0, whose work is m/2 (v^{1/2}² - v^0²).
  // One pass sums (load power, reaction power, kinetic energy, runaway nodes), each exactly (the same
  // for any thread count or order of the nodes); v_old becomes v^n on the way.
  void energies() {
    const Real weight = velocity_weight_, dt_mid = dt_mid_;
    const Real reaction_weight = step_.step == 0 ? Real(0.5) : weight;
    std::vector<Vec3>& v_n = v_old_;
    // v^n of the other ranks' nodes is read only by the contacts (each rank books its own slave
    // nodes' touches, whose segments may be any nodes'): without contacts a rank's own nodes alone;
    // by reach (the others' velocities may be stale) its own and the bodies' nodes, the segments'.
    const bool own_only = halo_by_reach_ || problem_.contacts.empty();
    const Index count = own_only ? nodes_.owned_count() : nodes_.size();
    if (controls_.bndout) motion_work_ += dt_mid * motion_power(reaction_weight);  // a collective
    const Sums<4> sums = parallel::exact_sum(
        count,
        [&](Index k) {
          const Index i = own_only ? nodes_.owned_node(k) : k;
          Sums<4> term;
          const Vec3 v_start = v_old_[i], dv = nodes_.v[i] - v_start;
          v_n[i] += weight * dv;
          if (!nodes_.owns(i)) return term;  // another rank's
          term[3] = runaway(i);
          if (nodes_.mass[i] <= 0) return term;
          term[0] = -load_force(i, v_start).dot(v_start + weight * dv);
          // A rigid body's nodes: its kinetic energy and constraint work are the body's (below).
          if (nodes_.body[i] != discretization::NodeStore::no_body) return term;
          term[2] = Real(0.5) * nodes_.mass[i] * v_n[i].squaredNorm();
          if (dt_mid > 0) {
            const Vec3 reaction = nodes_.mass[i] * dv / dt_mid - nodes_.f[i];
            term[1] = reaction.dot(v_start + reaction_weight * dv);
          }
          return term;
        },
        &parallel::world());
    if (nodes_.velocities_by_reach)
      for (const Index i : problem_.rigid_bodies.node_rows())
        if (!nodes_.owns(i)) v_n[i] += weight * (nodes_.v[i] - v_n[i]);
    const rigid::RigidBodies::Energies bodies = problem_.rigid_bodies.energies(weight, reaction_weight, dt_mid);
    ledger_.set(EnergyLedger::kinetic_energy, Role::kinetic, sums[2] + bodies.kinetic);
    for (const auto& f : problem_.formulations) f->book_energies(ledger_, nodes_, v_n, dt_mid);
    for (const auto& c : problem_.contacts) c.book_energies(ledger_, nodes_, v_n, dt_mid);
    ledger_.add(EnergyLedger::external_work_name, Role::external,
                dt_mid * (sums[0] + sums[1] + bodies.reaction_power));
    if (step_.step == 0) ledger_.set_initial_total();
    if (sums[3] > 0) throw_runaway();
  }

  // Throws for the node first in the deck's order that has run away (the same for any thread or
  // rank count: under MPI each rank looks at its own nodes, whose velocities only it may hold
  // current).
  [[noreturn]] void throw_runaway() const {
    Index first = -1, row = -1;
    for (Index k = 0; k < nodes_.owned_count(); ++k) {
      const Index i = nodes_.owned_node(k);
      if (runaway(i) && (first < 0 || nodes_.deck_index(i) < first)) first = nodes_.deck_index(i), row = i;
    }
    const parallel::Communicator& ranks = parallel::world();
    const Index worst = ranks.lowest(first);
    // The speed and ID from its rank, -1 for NaN and -2 for infinity (every other rank offers
    // infinity).
    const Real infinity = std::numeric_limits<Real>::infinity();
    double found[2] = {infinity, infinity};
    if (first == worst) {
      const Real norm = nodes_.v[row].norm();
      found[0] = std::isnan(norm) ? -1 : std::isinf(norm) ? -2 : norm;
      found[1] = static_cast<double>(nodes_.id[row]);
    }
    ranks.minimum(found);
    const Real speed = found[0];
    const Real s = speed == -1 ? std::numeric_limits<Real>::quiet_NaN() : speed == -2 ? infinity : speed;
    throw InstabilityError(fmt::format(
        "numerical instability at step {}, time {:.6g}: node {} has velocity {:.6g} ({}); last dt {:.6g}", step_.step,
        step_.time, static_cast<Id>(found[1]), s,
        std::isfinite(s) ? fmt::format("above the runaway bound {:.6g}", runaway_speed_limit_)
                         : std::string("not finite"),
        step_.dt));
  }

  // Fields, histories and rigid-wall forces at t^n when due, and all of them at the step where the
  // run ends (end time, ENDCYC, ENDMAS, or an energy ratio that moved by ENDENG percent); false there.
  // Without *DATABASE_BINARY_D3PLOT the fields are still written at the first and the last step, so
  // that every run leaves its initial and final state.
  bool output() {
    const bool last = step_.time >= controls_.end_time || (controls_.end_cycle > 0 && step_.step >= controls_.end_cycle);
    const bool stop = last || ends_early();
    const Real tolerance = 1e-9 * controls_.end_time;
    const bool fields_due =
        field_output_.enabled() ? field_output_.due(step_.time, tolerance, stop) : step_.step == 0 || stop;
    // Under MPI in blocks, what the fields and reports read beyond a rank's own nodes first. By
    // region (a fluid alone) each rank writes its own particles from its rows.
    if (fields_due && parallel::world().size() > 1 && !nodes_.by_region()) {
      for (auto& f : problem_.formulations) f->complete_for_output(nodes_);
      for (auto& wall : problem_.rigid_walls) wall.complete_state();
    }
    if (fields_due && observer_.on_field_output) observer_.on_field_output(step_, problem_);
    if (history_.due(step_.time, tolerance, stop) && observer_.on_history) observer_.on_history(step_, ledger_);
    if (!problem_.rigid_walls.empty() && rwforc_.due(step_.time, tolerance, stop) && observer_.on_rigid_wall_forces)
      observer_.on_rigid_wall_forces(step_, problem_.rigid_walls);
    if (!problem_.contacts.empty() && rcforc_.due(step_.time, tolerance, stop) && observer_.on_contact_forces)
      observer_.on_contact_forces(step_, problem_.contacts);
    if (!problem_.rigid_bodies.empty() && rbdout_.due(step_.time, tolerance, stop) && observer_.on_rigid_bodies)
      observer_.on_rigid_bodies(step_, problem_.rigid_bodies);
    if (!problem_.history_nodes.empty() && nodout_.due(step_.time, tolerance, stop)) {
      const std::vector<NodeHistory> histories = node_histories();  // a collective: on every rank
      if (observer_.on_node_histories) observer_.on_node_histories(step_, histories);
    }
    if (!problem_.history_solids.empty() && elout_.due(step_.time, tolerance, stop)) {
      const std::vector<ElementHistory> histories = element_histories();  // a collective: on every rank
      if (observer_.on_element_histories) observer_.on_element_histories(step_, histories);
    }
    if (controls_.bndout && bndout_.due(step_.time, tolerance, stop)) {
      const Vec3 reaction = motion_reaction();  // a collective: on every rank
      if (observer_.on_motion_reaction) observer_.on_motion_reaction(step_, reaction, motion_work_);
    }
    if (controls_.matsum && matsum_.due(step_.time, tolerance, stop)) {
      const discretization::PartSummary parts = part_summary();  // a collective: on every rank
      if (observer_.on_part_summary) observer_.on_part_summary(step_, parts);
    }
    if (controls_.spcforc && spcforc_.due(step_.time, tolerance, stop)) {
      const Vec3 reaction = spc_reaction();  // a collective: on every rank
      if (observer_.on_spc_reaction) observer_.on_spc_reaction(step_, reaction);
    }
    if (observer_.on_step) observer_.on_step(step_);
    return !stop;
  }

  // The parts' energies and momenta at t^n (*DATABASE_MATSUM): the internal and eroded energies the
  // ledger keeps by part and the formulations' own (Formulation::sum_parts: a liquid's, the
  // elements' hourglass energy, the mass DT2MS added), the kinetic energy and momentum of each node
  // under the node's part (v^n is in v_old_ from energies() on; a node that parts share counts,
  // whole, to the part NodeStore::part names), and a rigid body's, of its own mass properties,
  // under its part. Each an exact sum over the ranks' own nodes (the ledger's and the bodies',
  // which every rank holds, from rank 0).
  discretization::PartSummary part_summary() const {
    using Summary = discretization::PartSummary;
    Summary parts(controls_.matsum_parts);
    for (const auto& f : problem_.formulations) f->sum_parts(parts, nodes_);
    for (Index k = 0; k < nodes_.owned_count(); ++k) {
      const Index i = nodes_.owned_node(k);
      if (nodes_.body[i] != discretization::NodeStore::no_body || !(nodes_.mass[i] > 0)) continue;
      const Vec3& v = v_old_[i];
      parts.add(nodes_.part[i], Summary::kinetic_energy, Real(0.5) * nodes_.mass[i] * v.squaredNorm());
      parts.add_momentum(nodes_.part[i], nodes_.mass[i] * v);
    }
    const parallel::Communicator& ranks = parallel::world();
    if (ranks.rank() == 0) {
      for (std::size_t k = 0; k < ledger_.part_ids().size(); ++k) {
        const auto& part = ledger_.part_energies(k);
        parts.add(ledger_.part_ids()[k], Summary::internal_energy, part.work);
        parts.add(ledger_.part_ids()[k], Summary::eroded_internal_energy, part.eroded_internal);
        parts.add(ledger_.part_ids()[k], Summary::eroded_kinetic_energy, part.eroded_kinetic);
      }
      for (const rigid::RigidBody& body : problem_.rigid_bodies.bodies()) {
        parts.add(body.part_id, Summary::kinetic_energy, body.kinetic_energy_at(velocity_weight_));
        parts.add_momentum(body.part_id, body.mass * body.velocity_at(velocity_weight_));
      }
    }
    parts.sum_over(ranks);
    return parts;
  }

  // The history nodes' motion at t^n: v^n is in v_old_ from energies() on, v^{n+1/2} in the nodes,
  // so a^n = 2 (v^{n+1/2} - v^n) / dt^{n+1/2}, with what the constraints did.
  // Under MPI each value from the rank that owns the node (the others offer +infinity to the
  // minimum), so that every rank has them all.
  std::vector<NodeHistory> node_histories() const {
    const std::vector<Index>& places = problem_.history_nodes;
    constexpr int values = 13;  // ID, then displacement, velocity, acceleration, position
    std::vector<double> found(values * places.size(), std::numeric_limits<double>::infinity());
    const Real dt = step_.dt;
    for (std::size_t k = 0; k < places.size(); ++k) {
      // Looked up at each output, not kept: by region a node's row may be added to a rank's rows
      // without a change of layout (NodeStore::layout), and a rank's own nodes change as they flow.
      const Index i = nodes_.row_of(places[k]);
      if (i < 0 || !nodes_.owns(i)) continue;
      double* row = &found[values * k];
      // At the run's last step (dt^{n+1/2} = 0) v^{n+1/2} = v^n: the forces' acceleration instead,
      // without the components an SPC holds.
      Vec3 acceleration = Vec3::Zero();
      if (dt > 0) {
        acceleration = 2 * (nodes_.v[i] - v_old_[i]) / dt;
      } else if (nodes_.mass[i] > 0) {
        acceleration = nodes_.f[i] / nodes_.mass[i];
        for (int d = 0; d < 3; ++d)
          if (nodes_.fixed[i] & (1u << d)) acceleration[d] = 0;
      }
      row[0] = static_cast<double>(nodes_.id[i]);
      int c = 1;
      for (const Vec3& v : {Vec3(nodes_.x[i] - nodes_.x0[i]), v_old_[i], acceleration, nodes_.x[i]})
        for (int d = 0; d < 3; ++d) row[c++] = v[d];
    }
    parallel::world().minimum(found);
    std::vector<NodeHistory> histories(places.size());
    for (std::size_t k = 0; k < histories.size(); ++k) {
      const double* row = &found[values * k];
      if (!std::isfinite(row[0]))  // every node is some rank's own
        throw std::logic_error(fmt::format("node histories: the node at place {} is no rank's own", places[k]));
      NodeHistory& h = histories[k];
      h.id = static_cast<Id>(row[0]);
      h.displacement = Vec3(row[1], row[2], row[3]);
      h.velocity = Vec3(row[4], row[5], row[6]);
      h.acceleration = Vec3(row[7], row[8], row[9]);
      h.position = Vec3(row[10], row[11], row[12]);
    }
    return histories;
  }

  // The history elements' state at t^n from the formulations that follow them, each from the rank
  // that accounts for it (the others offer +infinity to the minimum), so that every rank has them.
  std::vector<ElementHistory> element_histories() const {
    constexpr int values = discretization::element_history_values;
    const std::vector<Id>& ids = problem_.history_solids;
    std::vector<double> found(values * ids.size(), std::numeric_limits<double>::infinity());
    for (const auto& f : problem_.formulations) f->element_histories(found);
    parallel::world().minimum(found);
    std::vector<ElementHistory> histories(ids.size());
    for (std::size_t k = 0; k < ids.size(); ++k) {
      const double* row = &found[values * k];
      ElementHistory& h = histories[k];
      h.id = ids[k];
      std::copy(row, row + 6, h.stress.begin());
      h.pressure = row[6];
      h.von_mises = row[7];
      h.plastic_strain = row[8];
      h.eroded = row[9] != 0;
    }
    return histories;
  }

  // The components the prescribed motions drive this step (held at t^{n+1/2}), each (node place,
  // direction) once.
  std::vector<std::pair<Index, int>> driven_components() const {
    const Real t_mid = step_.time + Real(0.5) * step_.dt;
    std::vector<std::pair<Index, int>> driven;
    for (const NodalMotion& m : problem_.motions)
      if (t_mid >= m.birth && t_mid <= m.death) driven.emplace_back(m.node, m.direction);
    std::sort(driven.begin(), driven.end());
    driven.erase(std::unique(driven.begin(), driven.end()), driven.end());
    return driven;
  }

  // The power of the prescribed motions' reactions over this step (*DATABASE_BNDOUT's work), as the
  // constraints' in energies(): on each driven component of a node this rank owns, (m dv / dt_mid
  // - f) (v^{n-1/2} + w dv), dv = v^{n+1/2} - v^{n-1/2}, before energies() moves v_old_ on to v^n.
  // An exact sum over the ranks.
  Real motion_power(Real reaction_weight) const {
    const std::vector<std::pair<Index, int>> driven = driven_components();
    const Real dt_mid = dt_mid_;
    return parallel::exact_sum(
        static_cast<Index>(driven.size()),
        [&](Index k) {
          const auto [place, d] = driven[k];
          const Index i = nodes_.row_of(place);
          if (i < 0 || !nodes_.owns(i) || !nodes_.active[i] || !(dt_mid > 0)) return Real(0);
          const Real dv = nodes_.v[i][d] - v_old_[i][d];
          return (nodes_.mass[i] * dv / dt_mid - nodes_.f[i][d]) * (v_old_[i][d] + reaction_weight * dv);
        },
        &parallel::world());
  }

  // The force a constraint adds to component d of node i at t^n for the acceleration it leaves:
  // m a^n - f^n, a^n = 2 (v^{n+1/2} - v^n) / dt as in node_histories (v^n in v_old_ from energies()
  // on; 0 at the run's last step, whose dt is 0); -f for a node held at rest. The reaction of the
  // constraint work in energies().
  Real reaction(Index i, int d) const {
    const Real dt = step_.dt;
    const Real acceleration = dt > 0 ? 2 * (nodes_.v[i][d] - v_old_[i][d]) / dt : 0;
    return nodes_.mass[i] * acceleration - nodes_.f[i][d];
  }

  // The resultant of the prescribed motions' reactions at t^n (*DATABASE_BNDOUT) on their driven
  // components. An exact sum over the ranks.
  Vec3 motion_reaction() const {
    const std::vector<std::pair<Index, int>> driven = driven_components();
    const Sums<3> sum = parallel::exact_sum(
        static_cast<Index>(driven.size()),
        [&](Index k) {
          Sums<3> term;
          const auto [place, d] = driven[k];
          const Index i = nodes_.row_of(place);
          if (i >= 0 && nodes_.owns(i) && nodes_.active[i]) term[d] = reaction(i, d);
          return term;
        },
        &parallel::world());
    return {sum[0], sum[1], sum[2]};
  }

  // The resultant of the SPCs' reactions at t^n (*DATABASE_SPCFORC) on each component a constraint
  // holds (an SPC, a node's TC, the plane of a 2D model); a rigid body's nodes are the body's
  // (rbdout.csv), an eroded node has none. An exact sum over each rank's own nodes and the ranks.
  Vec3 spc_reaction() const {
    const Sums<3> sum = parallel::exact_sum(
        nodes_.owned_count(),
        [&](Index k) {
          const Index i = nodes_.owned_node(k);
          Sums<3> term;
          const unsigned held = nodes_.fixed[i] & 7u;
          if (!held || !nodes_.active[i] || nodes_.body[i] != discretization::NodeStore::no_body) return term;
          for (int d = 0; d < 3; ++d)
            if (held & (1u << d)) term[d] = reaction(i, d);
          return term;
        },
        &parallel::world());
    return {sum[0], sum[1], sum[2]};
  }

  // ENDMAS (the mass DT2MS added passed its percentage of the initial mass) or ENDENG (the energy
  // ratio moved by more than its percentage; never for a model at rest, whose ratio is NaN).
  bool ends_early() const {
    if (controls_.mass_scaling_step > 0 &&
        100 * ledger_.value(discretization::EnergyLedger::added_mass) > controls_.end_mass_percent * initial_mass_) {
      log::info(fmt::format("ENDMAS: the mass DT2MS added is above {:g} % of the initial mass at step {}, time {:.6g}: "
                            "the run ends", controls_.end_mass_percent, step_.step, step_.time));
      return true;
    }
    return controls_.end_energy > 0 && 100 * std::abs(ledger_.ratio() - 1) > controls_.end_energy;
  }

  // x^{n+1} = x^n + dt v^{n+1/2}, f cleared for the next step's forces; walls move; t advances.
  void position_update() {
    const Real dt = step_.dt;
    const parallel::Range rows = rows_advanced();
    const auto advance = [&](Index i) {
      nodes_.x[i] += dt * nodes_.v[i];
      nodes_.f[i] = Vec3::Zero();
    };
    parallel::for_each(rows, advance);
    // The bodies' nodes beyond them, which every rank moves (their velocities are every rank's).
    for (const Index i : problem_.rigid_bodies.node_rows())
      if (i < rows.begin || i >= rows.end) advance(i);
    for (auto& wall : problem_.rigid_walls) wall.advance(dt);
    step_.time += dt;
    if (controls_.end_time - step_.time < 1e-9 * controls_.end_time) step_.time = controls_.end_time;
    dt_previous_ = dt;
    ++step_.step;
  }

  // The rows whose positions this rank keeps current: in blocks with the halo by reach, from the
  // first of its own and those its formulations read to the last (the others are stale until a
  // formulation completes them, which brings their positions in); else every row.
  parallel::Range rows_advanced() const {
    if (!nodes_.velocities_by_reach || nodes_.by_region()) return {0, nodes_.size()};
    parallel::Range rows{nodes_.owned_begin, nodes_.owned_end};
    for (const auto& f : problem_.formulations) rows = parallel::hull(rows, f->rows_read(nodes_));
    return rows;
  }

  Problem& problem_;
  discretization::NodeStore& nodes_;
  const RunControls& controls_;
  const Observer& observer_;
  const LoadBalance balance_;
  std::vector<Vec3> v_old_;  // v^{n-1/2} during the update, then v^n (energies)
  std::vector<Index> motion_row_;  // each prescribed motion's node's row, -1 where not held
  long long motion_rows_layout_ = -1;
  // The last check of the ranks' work (balance()): when, and the time in collectives until then.
  std::chrono::steady_clock::time_point checked_at_;
  double communicating_at_check_ = 0;
  long long rebalances_ = 0;
  bool halo_by_reach_ = false;  // halo(): the formulations bring in the velocities they read
  StepInfo step_;
  Real dt_previous_ = 0, dt_first_ = 0, dt_mid_ = 0, velocity_weight_ = 0.5;
  Vec3 base_acceleration_ = Vec3::Zero(), damping_ = Vec3::Zero();
  Real runaway_speed_limit_ = std::numeric_limits<Real>::infinity();
  Real initial_mass_ = 0;  // the nodes' mass before DT2MS adds any (ENDMAS)
  OutputSchedule field_output_, history_, rwforc_, rcforc_, rbdout_, nodout_, spcforc_, elout_, bndout_, matsum_;
  Real motion_work_ = 0;  // the prescribed motions' reactions' work since the start (BNDOUT)
  EnergyLedger ledger_;
  PhaseTimes phases_;
};

TimeLoop::TimeLoop(Problem& problem, const Observer& observer, const LoadBalance& balance)
    : step_(std::make_unique<Step>(problem, observer, balance)) {}
TimeLoop::~TimeLoop() = default;

RunSummary TimeLoop::run(const std::function<bool(const StepInfo&)>& between_steps) {
  parallel::CoreShare cores;  // fewer threads while other work shares the machine's cores
  while (step_->advance()) {
    cores.between_steps();
    if (between_steps && !between_steps(step_->info())) break;
  }
  return step_->summary();
}

void TimeLoop::complete_state() { step_->complete_state(); }

void TimeLoop::checkpoint(Archive& archive) { step_->checkpoint(archive); }

const PhaseTimes& TimeLoop::phases() const { return step_->phases(); }

long long TimeLoop::rebalances() const { return step_->rebalances(); }
bool TimeLoop::velocities_by_reach() const { return step_->velocities_by_reach(); }
Real TimeLoop::initial_mass() const { return step_->initial_mass(); }

RunSummary run(Problem& problem, const Observer& observer) { return TimeLoop(problem, observer).run(); }

}  // namespace spall::solver
