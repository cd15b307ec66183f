#include "spall/solver/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "spall/core/ordered_sum.hpp"

namespace spall::solver {

namespace {

Real stable_time_step(const Problem& problem, Real time) {
  Real dt = std::numeric_limits<Real>::infinity();
  for (const auto& f : problem.formulations) dt = std::min(dt, f->stable_time_step(problem.nodes));
  dt *= problem.controls.tssfac;
  if (problem.controls.max_dt_curve) dt = std::min(dt, problem.controls.max_dt_curve->value(time));
  return dt;
}

// Base accelerations a(t): every node with mass feels the inertial force -m a (LS-DYNA
// *LOAD_BODY convention). Returns the summed load vector per unit mass.
Vec3 base_acceleration(const Problem& problem, Real time) {
  Vec3 a = Vec3::Zero();
  for (const auto& load : problem.base_accelerations)
    a[load.direction] += load.sf * load.curve->value(time);
  return a;
}

// A particle is running away when it moves much faster than any signal in the material.
struct RunawayCheck {
  Real speed_limit = std::numeric_limits<Real>::infinity();

  // Whether node i has run away (the time loop counts these in its pass over the energies): a
  // speed that is not finite or above the limit, compared squared (a NaN fails the comparison;
  // without a limit, the largest double stands for it).
  bool runaway(const NodeStore& nodes, Index i) const {
    const Real bound = std::isfinite(speed_limit) ? speed_limit * speed_limit : std::numeric_limits<Real>::max();
    return !(nodes.v[i].squaredNorm() <= bound) || !nodes.x[i].allFinite();
  }

  // Throws for the lowest-numbered node that has run away, if one has.
  void check(const NodeStore& nodes, const StepInfo& step) const {
    const Index n = nodes.size();
    Index worst = -1;
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      if (runaway(nodes, i)) {
#pragma omp critical
        if (worst < 0 || i < worst) worst = i;  // the lowest index: the same for any thread count
      }
    }
    if (worst >= 0) {
      const Real s = nodes.v[worst].norm();
      throw InstabilityError(fmt::format(
          "numerical instability at step {}, time {:.6g}: node {} has velocity {:.6g} "
          "({}); last dt {:.6g}",
          step.step, step.time, nodes.id[worst], s,
          std::isfinite(s) ? fmt::format("above the runaway bound {:.6g}", speed_limit)
                           : std::string("not finite"),
          step.dt));
    }
  }
};

// The first output time after `now` on the grid start + k * interval (intervals smaller than a
// step give one output per step).
Real next_output_time(Real start, Real interval, Real now) {
  if (!(interval > 0)) return std::numeric_limits<Real>::infinity();
  const Real k = std::floor((now - start) / interval) + 1;
  return start + std::max(k, Real(1)) * interval;
}

}  // namespace

RunSummary run(Problem& problem, const Observer& observer) {
  auto& nodes = problem.nodes;
  const auto& controls = problem.controls;
  const Index n = nodes.size();

  Energies energies;
  StepInfo step;
  Real dt_previous = 0;
  Real dt_first = 0;
  Real next_field_output = 0;
  Real next_history = 0;
  std::vector<Vec3> v_old(n);

  RunawayCheck runaway;
  {
    Real c = 0, v0 = 0;
    for (const auto& f : problem.formulations) c = std::max(c, f->max_wave_speed());
    for (Index i = 0; i < n; ++i) v0 = std::max(v0, nodes.v[i].norm());
    // No material point outruns ten times the fastest wave plus the fastest initial motion.
    if (c > 0) runaway.speed_limit = 10 * (c + v0);
  }

  auto field_interval = [&](Real t) {
    return controls.d3plot_dt_curve ? controls.d3plot_dt_curve->value(t) : controls.d3plot_dt;
  };
  const bool field_output = controls.d3plot_dt > 0 || controls.d3plot_dt_curve;
  Real next_rwforc = 0;
  auto rwforc_interval = [&](Real t) {
    return controls.rwforc_dt_curve ? controls.rwforc_dt_curve->value(t) : controls.rwforc_dt;
  };

#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) nodes.f[i] = Vec3::Zero();
  for (;;) {
    // 1. internal forces at x^n (f was zeroed with the last position update)
    try {
      for (auto& f : problem.formulations) f->compute_forces(nodes, dt_previous);
    } catch (const InstabilityError& e) {
      // A formulation found its state broken (a material point, a particle's neighbourhood):
      // the same step and time as the runaway check gives.
      throw InstabilityError(fmt::format("numerical instability at step {}, time {:.6g}: {}", step.step,
                                         step.time, e.what()));
    }

    // 5. the next step, from the state at t^n
    Real dt = stable_time_step(problem, step.time);
    if (step.step == 0) {
      if (controls.dt_initial > 0) dt = std::min(dt, controls.dt_initial);
      dt_first = dt;
    }
    if (!std::isfinite(dt)) dt = controls.end_time;  // nothing limits the step (no formulation)
    dt = std::min(dt, controls.end_time - step.time);
    if (controls.dt_min_factor > 0 && dt < controls.dt_min_factor * dt_first &&
        step.time < controls.end_time)
      throw InstabilityError(fmt::format(
          "time step {:.6g} at step {}, time {:.6g} fell below DTMIN x initial step ({:.6g})", dt,
          step.step, step.time, controls.dt_min_factor * dt_first));
    step.dt = dt;

    // 2.-3. loads, then the central-difference velocity update over the mid-interval
    const Real dt_mid = step.step == 0 ? Real(0.5) * dt : Real(0.5) * (dt_previous + dt);
    const Vec3 g = base_acceleration(problem, step.time);
    // *DAMPING_GLOBAL: -D m v on the velocity of the last half step, counted as external work.
    const Vec3 damping = (controls.damping_curve ? controls.damping_curve->value(step.time) : controls.damping) *
                         controls.damping_scale;
    // Where v^n lies between v^{n-1/2} and v^{n+1/2} (see 4. below).
    const Real velocity_weight = (dt_previous + dt) > 0 ? dt_previous / (dt_previous + dt) : Real(0.5);
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      v_old[i] = nodes.v[i];
      if (nodes.mass[i] <= 0) continue;
      nodes.f[i] -= nodes.mass[i] * (g + damping.cwiseProduct(nodes.v[i]));
      Vec3 v_new = nodes.v[i] + (dt_mid / nodes.mass[i]) * nodes.f[i];
      for (int d = 0; d < 3; ++d)
        if (nodes.fixed[i] & (1u << d)) v_new[d] = 0;
      nodes.v[i] = v_new;
    }
    const Real t_mid = step.time + Real(0.5) * dt;
    for (const auto& m : problem.motions) {
      if (t_mid < m.birth || t_mid > m.death) continue;
      Real& v = nodes.v[m.node][m.direction];
      switch (m.vad) {
        case 0: v = m.sf * m.curve->value(t_mid); break;
        case 1: v = v_old[m.node][m.direction] + dt_mid * m.sf * m.curve->value(step.time); break;
        case 2: {
          const Real u_next = m.sf * m.curve->value(step.time + dt);
          const Real u_now = nodes.x[m.node][m.direction] - nodes.x0[m.node][m.direction];
          v = dt > 0 ? (u_next - u_now) / dt : 0;
          break;
        }
      }
    }
    // Rigid walls last, so that no constraint above carries a node through a wall.
    for (auto& wall : problem.rigid_walls) wall.enforce(nodes, t_mid, dt, dt_mid);
    // External power at v^n, with v^{n+1/2} as the constraints left it: of the loads, and of the
    // constraint reactions r = m dv/dt - f on every held or driven component and on every node a
    // wall pushed. The reactions' power on the first step is taken at the mean of v^0 and v^{1/2}
    // instead: a constraint that changes the initial velocity (a wall stopping a node that starts
    // on it, a motion that starts at once) acts as an impulse at t^0, whose work is
    // m/2 (v^{1/2}² - v^0²).
    const Real reaction_weight = step.step == 0 ? Real(0.5) : velocity_weight;
    // 4. energies at t^n from the velocities at t^n: v^n = v^{n-1/2} + a^n dt^{n-1/2} / 2, i.e.
    // the point dt^{n-1/2} / (dt^{n-1/2} + dt^{n+1/2}) of the way from v^{n-1/2} to v^{n+1/2}
    // (the mean of the two only when the steps are equal; v^0 at the start, v^{n+1/2} at the
    // shortened last step).
    // One pass over the nodes sums (load power, reaction power, kinetic energy, runaway nodes),
    // each in an order independent of the thread count; v_old becomes v^n on the way.
    std::vector<Vec3>& v_mid = v_old;
    const Sums<4> sums = ordered_sum(
        n,
        [&](Index i) {
          Sums<4> term;
          term[3] = runaway.runaway(nodes, i);
          const Vec3 v_start = v_old[i], dv = nodes.v[i] - v_start;
          v_mid[i] += velocity_weight * dv;
          term[2] = Real(0.5) * nodes.mass[i] * v_mid[i].squaredNorm();
          if (nodes.mass[i] <= 0) return term;
          const Vec3 f_load = -nodes.mass[i] * (g + damping.cwiseProduct(v_start));
          term[0] = f_load.dot(v_start + velocity_weight * dv);
          if (dt_mid > 0) {
            const Vec3 reaction = nodes.mass[i] * dv / dt_mid - nodes.f[i];
            term[1] = reaction.dot(v_start + reaction_weight * dv);
          }
          return term;
        },
        Sums<4>{});
    const Real external_power = sums[0], reaction_power = sums[1], kinetic = sums[2];
    for (const auto& f : problem.formulations) {
      const auto p = f->internal_power(v_mid);
      energies.internal += dt_mid * p.stored;
      energies.artificial_viscosity += dt_mid * p.dissipated;
    }
    energies.external_work += dt_mid * (external_power + reaction_power);
    energies.kinetic = kinetic;
    if (step.step == 0) energies.initial_total = energies.total();

    if (sums[3] > 0) runaway.check(nodes, step);

    const bool last = step.time >= controls.end_time ||
                      (controls.end_cycle > 0 && step.step >= controls.end_cycle);
    const Real tolerance = 1e-9 * controls.end_time;
    if (field_output && (step.time + tolerance >= next_field_output || last)) {
      if (observer.on_field_output) observer.on_field_output(step, problem);
      next_field_output = next_output_time(next_field_output, field_interval(step.time), step.time + tolerance);
    }
    if (step.time + tolerance >= next_history || last) {
      if (observer.on_history) observer.on_history(step, energies);
      next_history = next_output_time(next_history, controls.glstat_dt, step.time + tolerance);
    }
    if (!problem.rigid_walls.empty() && (step.time + tolerance >= next_rwforc || last)) {
      if (observer.on_rigid_wall_forces) observer.on_rigid_wall_forces(step, problem.rigid_walls);
      next_rwforc = next_output_time(next_rwforc, rwforc_interval(step.time), step.time + tolerance);
    }
    if (observer.on_step) observer.on_step(step);
    if (last) break;
    // ENDENG is a percentage change of the energy ratio.
    if (controls.end_energy > 0 && 100 * std::abs(energies.ratio() - 1) > controls.end_energy) break;

    // x^{n+1} = x^n + dt v^{n+1/2}, and f cleared for the next step's forces
#pragma omp parallel for schedule(static)
    for (Index i = 0; i < n; ++i) {
      nodes.x[i] += dt * nodes.v[i];
      nodes.f[i] = Vec3::Zero();
    }
    for (auto& wall : problem.rigid_walls) wall.advance(dt);
    step.time += dt;
    if (controls.end_time - step.time < tolerance) step.time = controls.end_time;
    dt_previous = dt;
    ++step.step;
  }
  return {step.step, step.time, energies};
}

}  // namespace spall::solver
