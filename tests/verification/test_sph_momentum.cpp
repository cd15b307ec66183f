// Linear momentum in SPH: the pair force is evaluated in a form symmetric in the two particles,
// so Newton's third law holds bitwise per pair and total momentum is conserved to round-off
// (Monaghan 1992, §2.4). Round-off bound: n_particles * eps * |p| per step, far below 1e-9.
// Each test runs the block lying along x, where the list spans too much of the particle order
// (cell order, z slowest) for the force pass's pair-once blocks and every row is gathered whole,
// and along z, where the force pass takes each pair once (SolidFormulation::pairs_taken_once).
#include <gtest/gtest.h>

#include <omp.h>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "spall/sph/solid.hpp"
#include "support/sph_block.hpp"

using namespace spall;

namespace {

Vec3 total_momentum(const discretization::NodeStore& nodes) {
  Vec3 p = Vec3::Zero();
  for (Index i = 0; i < nodes.size(); ++i) p += nodes.mass[i] * nodes.v[i];
  return p;
}

enum class Lying { along_x, along_z };

model::Model block(Real end_time, Lying lying) {
  test_support::ElasticBlock b;
  b.size = lying == Lying::along_x ? Vec3(0.2, 0.1, 0.1) : Vec3(0.1, 0.1, 0.3);
  b.spacing = 0.01;
  b.end_time = end_time;
  return test_support::elastic_block_model(b);
}

// The force pass the block's run took: each pair once along z, every row whole along x.
void expect_force_pass(const solver::Problem& problem, Lying lying) {
  const auto& solid = dynamic_cast<const sph::SolidFormulation&>(*problem.formulations.front());
  EXPECT_EQ(solid.pairs_taken_once(), lying == Lying::along_z);
}

class SphMomentum : public ::testing::TestWithParam<Lying> {};

// Runs `model` from a shearing, compressing velocity field (strong stresses and artificial
// viscosity); returns the change of total momentum and the scale sum m |v| it is measured against.
std::pair<Real, Real> momentum_error_under_violent_motion(model::Model& model, Lying lying) {
  for (const auto& node : model.nodes) {
    model::InitialVelocityNode iv;
    iv.nid = node.id;
    iv.v = Vec3(50 * std::sin(31 * node.x.y()), -40 * node.x.x(), 20 * std::cos(17 * node.x.z()));
    model.initial_velocity_nodes.push_back(iv);
  }
  solver::Problem problem = solver::build_problem(model);
  const Vec3 p0 = total_momentum(problem.nodes);
  Real scale = 0;
  for (Index i = 0; i < problem.nodes.size(); ++i) scale += problem.nodes.mass[i] * problem.nodes.v[i].norm();
  const auto summary = solver::run(problem, {});
  EXPECT_GT(summary.steps, 50);
  expect_force_pass(problem, lying);
  return {(total_momentum(problem.nodes) - p0).norm(), scale};
}

}  // namespace

TEST_P(SphMomentum, UniformMotionKeepsMomentumAndShape) {
  log::set_quiet(true);
  model::Model model = block(2e-4, GetParam());
  model::InitialVelocity iv;
  iv.v = Vec3(3.0, -1.0, 2.0);
  model.initial_velocities.push_back(iv);
  solver::Problem problem = solver::build_problem(model);
  const Vec3 p0 = total_momentum(problem.nodes);
  solver::run(problem, {});
  const Vec3 p1 = total_momentum(problem.nodes);
  EXPECT_LT((p1 - p0).norm(), 1e-12 * p0.norm());
  // A rigid translation creates no strain: every particle moved by v t.
  for (Index i = 0; i < problem.nodes.size(); ++i)
    EXPECT_LT((problem.nodes.x[i] - problem.nodes.x0[i] - 2e-4 * Vec3(3.0, -1.0, 2.0)).norm(), 1e-12);
}

TEST_P(SphMomentum, ViolentNonUniformMotionConservesMomentum) {
  log::set_quiet(true);
  model::Model model = block(2e-4, GetParam());
  const auto [error, scale] = momentum_error_under_violent_motion(model, GetParam());
  EXPECT_LT(error, 1e-11 * scale);
}

// Seed 000's treatment (surface and inner-layer particles pass on only -p I) keeps the pair term
// antisymmetric, so momentum stays exact with it; categories are recomputed every step here.
TEST_P(SphMomentum, ColourFieldTreatmentConservesMomentum) {
  log::set_quiet(true);
  model::Model model = block(2e-4, GetParam());
  model::SphColourField colour;
  colour.treat = 1;
  model.sph_colour_fields.push_back(colour);
  const auto [error, scale] = momentum_error_under_violent_motion(model, GetParam());
  EXPECT_LT(error, 1e-11 * scale);
}

TEST_P(SphMomentum, SameResultOnOneAndTwoThreads) {
  log::set_quiet(true);
  auto run_with = [](int threads) {
    omp_set_num_threads(threads);
    model::Model model = block(1e-4, GetParam());
    // Every optional path of the pair loops: colour-field treatment and artificial stress.
    model::SphColourField colour;
    colour.treat = 1;
    model.sph_colour_fields.push_back(colour);
    model.sph_artificial_stress = model::SphArtificialStress{};
    for (const auto& node : model.nodes) {
      model::InitialVelocityNode iv;
      iv.nid = node.id;
      iv.v = Vec3(30 * std::sin(29 * node.x.y()), -20 * node.x.x(), 10 * node.x.z());
      model.initial_velocity_nodes.push_back(iv);
    }
    solver::Problem problem = solver::build_problem(model);
    solver::run(problem, {});
    expect_force_pass(problem, GetParam());
    return problem.nodes.x;
  };
  const auto one = run_with(1);
  const auto two = run_with(2);
  ASSERT_EQ(one.size(), two.size());
  for (std::size_t i = 0; i < one.size(); ++i) ASSERT_EQ(one[i], two[i]) << "node " << i;
}

INSTANTIATE_TEST_SUITE_P(BothForcePasses, SphMomentum, ::testing::Values(Lying::along_x, Lying::along_z),
                         [](const auto& info) { return info.param == Lying::along_x ? "RowsWhole" : "PairsOnce"; });
