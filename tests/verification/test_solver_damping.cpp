// *DAMPING_GLOBAL: mass-weighted damping f = -D m v. A free block translating rigidly feels no
// internal force, so its speed decays as v0 exp(-D t) (the solution of m dv/dt = -D m v), here to
// 1 % (central difference: the decay rate is exact to O(D dt)); the damping work enters the energy
// balance as external work, whose ratio stays 1; STX STY STZ scale the damping per direction.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "support/spg_block.hpp"

using namespace spall;

TEST(SolverDamping, RigidTranslationDecaysExponentially) {
  log::set_quiet(true);
  test_support::SpgBlock b;
  b.elements = {3, 3, 3};
  b.size = Vec3(0.3, 0.3, 0.3);
  const Real D = 1000;  // 1/s
  b.end_time = 2.0 / D;
  model::Model m = test_support::spg_block_model(b);
  for (const auto& node : m.nodes) m.initial_velocity_nodes.push_back({node.id, Vec3(3, 2, 1), Vec3::Zero(), 0, {}});
  model::DampingGlobal damping;
  damping.valdmp = D;
  damping.translation_scale = Vec3(1, 0.5, 0);  // z undamped
  m.damping_global = damping;
  solver::Problem p = solver::build_problem(m);
  const auto summary = solver::run(p, {});
  const Real t = summary.end_time;
  const Vec3 v = p.nodes.v[0];
  // v is the half-step velocity v^{n+1/2} of the last step, at t + dt/2 ~ t (dt << 1/D).
  std::printf("%lld steps: v = (%.5f, %.5f, %.5f), expected (%.5f, %.5f, 1), energy ratio %.6f\n", summary.steps,
              v.x(), v.y(), v.z(), 3 * std::exp(-D * t), 2 * std::exp(-0.5 * D * t), summary.energies.ratio());
  EXPECT_NEAR(v.x() / (3 * std::exp(-D * t)), 1.0, 0.01);
  EXPECT_NEAR(v.y() / (2 * std::exp(-0.5 * D * t)), 1.0, 0.01);
  EXPECT_NEAR(v.z(), 1.0, 1e-9);  // undamped (round-off of the internal forces of a rigid motion)
  EXPECT_NEAR(summary.energies.ratio(), 1.0, 0.01);
}
