#pragma once
// Largest eigenfrequency of an SPH solid's linearized, undamped operator, by power iteration: the
// number that decides the stability of the central-difference scheme (stable while
// omega_max dt <= 2; e.g. Belytschko, Liu & Moran, Nonlinear Finite Elements, §6.3).
//
// K u is measured with the solver itself: a fresh, stress-free copy of the formulation is given
// the velocity u and advanced over a tiny step tau, so that its stress is tau C : L(u) and its
// force -tau K u (viscosity and artificial stress must be off: they are not part of K).
// Rigid-body modes have omega = 0 and do not disturb the iteration.
#include <cmath>
#include <random>

#include "spall/solver/problem.hpp"
#include "spall/sph/solid.hpp"

namespace spall::test_support {

struct Frequency {
  Real omega_max = 0;    // rad/s
  Real stable_step = 0;  // the formulation's stable step (before TSSFAC) at rest
  // The largest TSSFAC at which central difference is stable for this operator.
  Real critical_tssfac() const { return 2 / (omega_max * stable_step); }
};

// The formulation's stable step (before TSSFAC) at rest, after the first pass that computes the
// correction and the categories it depends on.
inline Real stable_step_at_rest(const solver::Problem& problem) {
  const auto& solid = dynamic_cast<const sph::SolidFormulation&>(*problem.formulations.at(0));
  discretization::NodeStore nodes = problem.nodes;
  std::fill(nodes.v.begin(), nodes.v.end(), Vec3::Zero());
  sph::SolidFormulation primed = solid;
  primed.compute_forces(nodes, 0);
  return primed.stable_time_step(nodes);
}

inline Frequency largest_frequency(const solver::Problem& problem, int iterations = 200) {
  const auto& solid = dynamic_cast<const sph::SolidFormulation&>(*problem.formulations.at(0));
  discretization::NodeStore nodes = problem.nodes;
  const Index n = nodes.size();
  const auto held = [&](Index i, int d) { return (nodes.fixed[i] >> d) & 1; };
  std::mt19937 random(7);
  std::uniform_real_distribution<Real> uniform(-1, 1);
  std::vector<Vec3> u(n);
  for (Index i = 0; i < n; ++i)
    for (int d = 0; d < 3; ++d) u[i][d] = held(i, d) ? 0 : uniform(random);
  Frequency result;
  result.stable_step = stable_step_at_rest(problem);
  const Real tau = 1e-6 * result.stable_step;
  Real omega2 = 0;
  for (int it = 0; it < iterations; ++it) {
    Real norm = 0;
    for (Index i = 0; i < n; ++i) norm += nodes.mass[i] * u[i].squaredNorm();
    for (Index i = 0; i < n; ++i) u[i] /= std::sqrt(norm);
    sph::SolidFormulation fresh = solid;
    nodes.v = u;
    std::fill(nodes.f.begin(), nodes.f.end(), Vec3::Zero());
    fresh.compute_forces(nodes, tau);
    Real uKu = 0;
    for (Index i = 0; i < n; ++i) {
      const Vec3 Ku = -nodes.f[i] / tau;
      uKu += u[i].dot(Ku);  // Rayleigh quotient, u of unit M-norm
      for (int d = 0; d < 3; ++d) u[i][d] = held(i, d) ? 0 : Ku[d] / nodes.mass[i];
    }
    omega2 = uKu;
  }
  result.omega_max = std::sqrt(omega2);
  return result;
}

}  // namespace spall::test_support
