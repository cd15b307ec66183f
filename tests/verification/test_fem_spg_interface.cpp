// Solid finite elements and SPG particles meshed together, sharing the nodes of their interface
// (seed 001 §2.3, Fig. 2; issue 32): a free-free bar half FEM (ELFORM 1 and 2) and half SPG keeps
// the quarter period L / (2c) of its first longitudinal mode within 3 % (Graff §2.1), and a
// compression pulse crossing the interface is reflected with less than 2 % of its energy (the
// same material on both sides reflects nothing in the continuum; the FEM-only bar's dispersion
// tail is printed beside it).
#include <gtest/gtest.h>

#include <cmath>

#include "spall/core/log.hpp"
#include "support/spg_bar.hpp"

using namespace spall;
using test_support::first_minimum;

namespace {

// Part 1 (SPG, the block's own) keeps the elements beyond x = split; those before it become
// part 2, solid finite elements of ELFORM `elform` (0: the whole bar stays SPG; < 0: the whole bar
// is FEM of ELFORM -elform).
model::Model half_and_half(test_support::SpgBlock b, int elform, Real split) {
  if (elform < 0) {
    b.fem = test_support::FiniteElements{-elform, {}};
    return test_support::spg_block_model(b);
  }
  model::Model m = test_support::spg_block_model(b);
  if (elform == 0) return m;
  m.parts.push_back({2, "finite elements", 2, 1, 0, 0, 0, {}, {}});
  m.sections[2] = model::SectionSolid{2, elform, 0, {}};
  std::map<Id, Vec3> x;
  for (const auto& node : m.nodes) x[node.id] = node.x;
  for (auto& e : m.solid_elements) {
    Real centre = 0;
    for (Id n : e.n) centre += x[n].x() / 8;
    if (centre < split) e.pid = 2;
  }
  return m;
}

}  // namespace

TEST(FemSpgInterface, HalfFemHalfSpgBarKeepsTheQuarterPeriod) {
  log::set_quiet(true);
  for (int elform : {1, 2}) {
    auto b = test_support::spg_bar(20);
    const Real quarter = test_support::bar_quarter_period(b);
    b.end_time = 1.5 * quarter;
    model::Model m = half_and_half(b, elform, 0.5 * b.size.x());
    for (const auto& node : m.nodes)
      m.initial_velocity_nodes.push_back({node.id, Vec3(std::cos(M_PI * node.x.x() / b.size.x()), 0, 0), Vec3::Zero(), 0, {}});
    solver::Problem p = solver::build_problem(m);
    ASSERT_EQ(p.formulations.size(), 2u);
    p.controls.glstat_dt = 1e-30;
    std::vector<Real> time, kinetic;
    solver::Observer observer;
    observer.on_history = [&](const solver::StepInfo& s, const discretization::EnergyLedger& e) {
      time.push_back(s.time);
      kinetic.push_back(e.kinetic());
    };
    const auto summary = solver::run(p, observer);
    const Real error = (first_minimum(time, kinetic) - quarter) / quarter;
    std::printf("ELFORM %d | SPG: quarter period error %+.3f %%, energy ratio %.5f\n", elform, 100 * error,
                summary.energies.ratio());
    EXPECT_LT(std::abs(error), 0.03);
    EXPECT_NEAR(summary.energies.ratio(), 1.0, 0.01);
  }
}

TEST(FemSpgInterface, APulseCrossesTheInterfaceWithoutReflection) {
  log::set_quiet(true);
  // A slender bar, 1 m x 2 cm x 2 cm of 100 x 2 x 2 elements, FEM before x = 0.5, SPG after. The end x = 0 is driven
  // with v = V sin^2(pi t / T) for T = 0.2 L / c and then released: a compression pulse 0.2 m
  // long runs along the bar. When it has passed the interface (t = T + 0.62 L / c) and not yet
  // reached the far end, what moves before x = 0.45 went back from the interface.
  test_support::SpgBlock b = test_support::spg_bar(100);
  b.size = Vec3(1.0, 0.02, 0.02);
  b.elements = {100, 2, 2};
  const Real c = std::sqrt(b.young / b.density), T = 0.2 * b.size.x() / c;
  b.end_time = T + 0.62 * b.size.x() / c;
  const auto left_energy = [&](int elform) {
    model::Model m = half_and_half(b, elform, 0.5);
    model::NodeSet end;
    end.id = 1;
    for (const auto& node : m.nodes)
      if (node.x.x() == 0) end.nodes.push_back(node.id);
    m.node_sets[1] = end;
    model::Curve pulse;
    pulse.id = 1;
    for (int k = 0; k <= 40; ++k) {
      const Real t = T * k / 40;
      pulse.points.push_back({t, std::pow(std::sin(M_PI * t / T), 2)});
    }
    m.curves[1] = pulse;
    model::PrescribedMotion drive;
    drive.target = model::Target::node_set;
    drive.id = 1;
    drive.dof = 1;
    drive.lcid = 1;
    drive.sf = 1.0;  // 1 m/s: linear elasticity holds
    drive.death = T;
    m.prescribed_motions.push_back(drive);
    solver::Problem p = solver::build_problem(m);
    const auto summary = solver::run(p, {});
    Real left = 0;
    for (Index i = 0; i < p.nodes.size(); ++i)
      if (p.nodes.x0[i].x() < 0.45) left += 0.5 * p.nodes.mass[i] * p.nodes.v[i].squaredNorm();
    // In a travelling wave the kinetic energy is half of the whole.
    return std::pair{2 * left, summary.energies.external_work()};
  };
  for (int elform : {1, 2}) {
    const Real fem_tail = left_energy(-elform).first;
    const auto [left, incident] = left_energy(elform);
    const Real reflected = left / incident;  // the tail of dispersion included
    std::printf("ELFORM %d | SPG: energy behind the interface %.3e J of %.3e J incident (FEM-only bar %.3e J): "
                "reflected %.3f %%\n", elform, left, incident, fem_tail, 100 * reflected);
    EXPECT_GT(incident, 0);
    EXPECT_LT(reflected, 0.02);
  }
}
