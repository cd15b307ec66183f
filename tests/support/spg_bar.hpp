#pragma once
// The free-free elastic bar in its first longitudinal mode, run with SPG: u(x, t) = A cos(pi x / L)
// sin(omega t), omega = pi c / L, c = sqrt(E / rho) (uniaxial stress; Graff, Wave Motion in
// Elastic Solids, §2.1). Started with v(x, 0) = V cos(pi x / L), the kinetic energy first vanishes
// at a quarter period t = L / (2 c).
#include <cmath>
#include <functional>
#include <omp.h>
#include <vector>

#include "spall/solver/simulation.hpp"
#include "support/spg_block.hpp"

namespace spall::test_support {

struct BarHistory {
  std::vector<Real> time, kinetic, dt;
  solver::RunSummary summary;
};

inline SpgBlock spg_bar(int elements_along) {
  SpgBlock b;
  b.size = Vec3(1.0, 0.1, 0.1);
  b.elements = {elements_along, std::max(2, elements_along / 10), std::max(2, elements_along / 10)};
  return b;
}

inline Real bar_quarter_period(const SpgBlock& b) { return b.size.x() / (2 * std::sqrt(b.young / b.density)); }

// `edit` changes the model before the run (a control card, say).
inline BarHistory run_spg_bar(SpgBlock b, Real end_time, Real tssfac = 0.9,
                              const std::function<void(model::Model&)>& edit = {}) {
  b.end_time = end_time;
  model::Model m = spg_block_model(b);
  if (edit) edit(m);
  for (const auto& node : m.nodes) {
    model::InitialVelocityNode iv;
    iv.nid = node.id;
    iv.v = Vec3(std::cos(M_PI * node.x.x() / b.size.x()), 0, 0);  // 1 m/s: linear elasticity holds
    m.initial_velocity_nodes.push_back(iv);
  }
  solver::Problem problem = solver::build_problem(m);
  problem.controls.tssfac = tssfac;
  problem.controls.glstat_dt = 1e-30;  // every step
  BarHistory h;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo& s, const discretization::EnergyLedger& e) {
    h.time.push_back(s.time);
    h.kinetic.push_back(e.kinetic());
    h.dt.push_back(s.dt);
  };
  h.summary = solver::run(problem, observer);
  return h;
}

// The nodes after running the bar to `end_time` on `threads` threads, started with
// v = (cos(pi x / L), 0.1, 0) m/s: for the checks that a result does not depend on the thread count.
inline discretization::NodeStore bar_nodes_after(SpgBlock b, Real end_time, int threads) {
  omp_set_num_threads(threads);
  b.end_time = end_time;
  model::Model m = spg_block_model(b);
  for (const auto& node : m.nodes)
    m.initial_velocity_nodes.push_back({node.id, Vec3(std::cos(M_PI * node.x.x() / b.size.x()), 0.1, 0), Vec3::Zero(), 0, {}});
  solver::Problem p = solver::build_problem(m);
  solver::run(p, {});
  return p.nodes;
}

// Time of the first minimum of a sampled curve, refined by a parabola through the three samples
// around the smallest one.
inline Real first_minimum(const std::vector<Real>& t, const std::vector<Real>& y) {
  std::size_t k = 1;
  while (k + 1 < y.size() && !(y[k] <= y[k - 1] && y[k] <= y[k + 1])) ++k;
  const Real t0 = t[k - 1], t1 = t[k], t2 = t[k + 1];
  const Real y0 = y[k - 1], y1 = y[k], y2 = y[k + 1];
  const Real denom = (t0 - t1) * (t0 - t2) * (t1 - t2);
  const Real a = (t2 * (y1 - y0) + t1 * (y0 - y2) + t0 * (y2 - y1)) / denom;
  const Real bcoef = (t2 * t2 * (y0 - y1) + t1 * t1 * (y2 - y0) + t0 * t0 * (y1 - y2)) / denom;
  return -bcoef / (2 * a);
}

}  // namespace spall::test_support
