// Taylor bar, OFHC copper, Johnson-Cook: Wilkins & Guinan 1973 test 1 (L0 23.47 mm, D0 7.62 mm,
// 210 m/s). Measured: final length over initial 0.630 and foot radius over initial 2.204
// (reference/validation.md §1(b)). Tolerances from issue 3: 5 % on the length, 10 % on the radius.
// Coarse (D0/10, ~2 400 particles); tests/verification/test_sph_taylor_bar_slow.cpp refines.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "support/taylor_bar.hpp"

using namespace spall;

namespace {

struct Shape {
  Real length = 0, foot_radius = 0;
};

// Length from the wall to the far end, and the largest radius (the foot's: the mushroom is widest
// there); each particle stands for a cell of one spacing, so half a spacing is added beyond the
// centres.
// The ratios divide by the same measure of the rod before impact (the lattice's own length and
// radius; the radius of a square lattice cut to a circle overshoots D0/2 by up to half a cell).
Shape measure(const solver::NodeStore& nodes, Real dx) {
  Shape s;
  for (Index i = 0; i < nodes.size(); ++i) s.length = std::max(s.length, nodes.x[i].z() + dx / 2);
  for (Index i = 0; i < nodes.size(); ++i)
    s.foot_radius = std::max(s.foot_radius, nodes.x[i].head<2>().norm() + dx / 2);
  return s;
}

}  // namespace

TEST(SphTaylorBar, FinalShapeMatchesWilkinsGuinanTest1) {
  log::set_quiet(true);
  test_support::TaylorBar bar;
  bar.particles_across = 10;
  const model::Model model = test_support::taylor_bar_model(bar);
  solver::Problem problem = solver::build_problem(model);
  const Real dx = bar.diameter / bar.particles_across;
  const Shape initial = measure(problem.nodes, dx);
  solver::Observer observer;
  problem.controls.glstat_dt = 10e-6;
  observer.on_history = [&](const solver::StepInfo& step, const solver::Energies& e) {
    const Shape s = measure(problem.nodes, dx);
    std::printf("t %.1f us: L/L0 %.4f  R/R0 %.4f  KE %.4g J  ratio %.4f\n", step.time * 1e6,
                s.length / initial.length, s.foot_radius / initial.foot_radius, e.kinetic, e.ratio());
  };
  solver::run(problem, observer);
  const Shape s = measure(problem.nodes, dx);
  const Real length_ratio = s.length / initial.length, radius_ratio = s.foot_radius / initial.foot_radius;
  std::printf("Taylor bar D0/%d: L/L0 %.4f (measured 0.630, %+.1f %%), R/R0 %.4f (measured 2.204, %+.1f %%)\n",
              bar.particles_across, length_ratio, 100 * (length_ratio / 0.630 - 1), radius_ratio,
              100 * (radius_ratio / 2.204 - 1));
  EXPECT_NEAR(length_ratio, 0.630, 0.05 * 0.630);
  EXPECT_NEAR(radius_ratio, 2.204, 0.10 * 2.204);
}
