// Loads, constraints and initial conditions against closed forms.
// - Free fall under *LOAD_BODY_Z (LS-DYNA: nodes feel -m a, so +g pulls towards -z): a free
//   body translates rigidly, z(t) = z0 - g t^2 / 2; central difference with a half first kick is
//   exact for constant acceleration, and the work of gravity turns into kinetic energy.
// - *BOUNDARY_PRESCRIBED_MOTION_SET, VAD 2: the driven nodes follow the displacement curve.
// - *BOUNDARY_SPC_SET: held components do not move; the reactions' work keeps the energy ratio 1.
// - *INITIAL_VELOCITY_GENERATION: v = omega n x (x - xc), a rigid rotation.
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "support/sph_block.hpp"

using namespace spall;

namespace {

model::Model small_block(Real end_time) {
  test_support::ElasticBlock b;
  b.size = Vec3(0.1, 0.1, 0.1);
  b.spacing = 0.01;
  b.end_time = end_time;
  return test_support::elastic_block_model(b);
}

model::Curve constant_curve(Id id, Real value) {
  model::Curve c;
  c.id = id;
  c.points = {{0.0, value}, {1.0, value}};
  return c;
}

}  // namespace

TEST(SolverConditions, FreeFallUnderBodyLoad) {
  log::set_quiet(true);
  const Real g = 9.81, t_end = 2e-4;
  model::Model model = small_block(t_end);
  model.curves[1] = constant_curve(1, g);
  model::BodyLoad load;
  load.direction = 2;
  load.lcid = 1;
  model.body_loads.push_back(load);
  solver::Problem problem = solver::build_problem(model);
  const auto summary = solver::run(problem, {});
  const Real expected = -0.5 * g * t_end * t_end;
  // u = x - x0 carries the round-off of positions of size 0.1 m over ~50 steps: ~1e-15 m.
  const Real round_off = 1e-14;
  for (Index i = 0; i < problem.nodes.size(); ++i) {
    const Vec3 u = problem.nodes.x[i] - problem.nodes.x0[i];
    EXPECT_NEAR(u.z(), expected, round_off);
    EXPECT_NEAR(u.x(), 0.0, round_off);
  }
  EXPECT_NEAR(summary.energies.ratio(), 1.0, 1e-6);
  EXPECT_GT(summary.energies.external_work(), 0.0);
}

TEST(SolverConditions, PrescribedDisplacementAndSpc) {
  log::set_quiet(true);
  const Real t_end = 1e-4, speed = 1.0;  // 1 m/s pull: small strain
  model::Model model = small_block(t_end);
  model::NodeSet right, left;
  right.id = 1;
  left.id = 2;
  for (const auto& node : model.nodes) {
    if (node.x.x() > 0.09) right.nodes.push_back(node.id);
    if (node.x.x() < 0.01) left.nodes.push_back(node.id);
  }
  model.node_sets[1] = right;
  model.node_sets[2] = left;
  model::Curve ramp;  // u(t) = speed * t
  ramp.id = 1;
  ramp.points = {{0.0, 0.0}, {1.0, speed}};
  model.curves[1] = ramp;
  model::PrescribedMotion pm;
  pm.target = model::Target::node_set;
  pm.id = 1;
  pm.dof = 1;
  pm.vad = 2;
  pm.lcid = 1;
  model.prescribed_motions.push_back(pm);
  model::Spc spc;
  spc.target = model::Target::node_set;
  spc.id = 2;
  spc.dof = {true, true, true, false, false, false};
  model.spcs.push_back(spc);
  solver::Problem problem = solver::build_problem(model);
  const auto summary = solver::run(problem, {});
  std::map<Id, Index> index;
  for (Index i = 0; i < problem.nodes.size(); ++i) index[problem.nodes.id[i]] = i;
  for (Id id : right.nodes) {
    const Index i = index[id];
    EXPECT_NEAR(problem.nodes.x[i].x() - problem.nodes.x0[i].x(), speed * t_end, 1e-12);
  }
  for (Id id : left.nodes) {
    const Index i = index[id];
    EXPECT_EQ(problem.nodes.x[i], problem.nodes.x0[i]);
  }
  // The pull did work, stored as strain and kinetic energy; the balance closes.
  EXPECT_GT(summary.energies.external_work(), 0.0);
  EXPECT_NEAR(summary.energies.ratio(), 1.0, 0.02);
}

TEST(SolverConditions, InitialVelocityGenerationIsARigidRotation) {
  log::set_quiet(true);
  model::Model model = small_block(1e-6);
  model::InitialVelocityGeneration gen;
  gen.id = 1;
  gen.styp = 2;
  gen.omega = 10.0;
  gen.v = Vec3(0.5, 0, 0);
  gen.xc = Vec3(0.05, 0.05, 0.05);
  gen.axis = Vec3(0, 0, 2);  // normalised by the solver
  model.initial_velocity_generations.push_back(gen);
  solver::Problem problem = solver::build_problem(model);
  for (Index i = 0; i < problem.nodes.size(); ++i) {
    const Vec3 r = problem.nodes.x0[i] - gen.xc;
    const Vec3 expected = gen.v + 10.0 * Vec3(-r.y(), r.x(), 0);
    EXPECT_NEAR((problem.nodes.v[i] - expected).norm(), 0.0, 1e-14);
  }
}

TEST(SolverConditions, UnsupportedConditionIsAnInputErrorAtItsLine) {
  model::Model model = small_block(1e-6);
  model::Spc spc;
  spc.id = model.nodes.front().id;
  spc.cid = 5;
  spc.where = {"deck.k", 42};
  model.spcs.push_back(spc);
  // A system turned 90 degrees about z: its x axis is the global y.
  model::CoordinateSystem turned;
  turned.id = 5;
  turned.keyword = "*DEFINE_COORDINATE_VECTOR";
  turned.axis = Vec3(0, 1, 0);
  turned.in_plane = Vec3(-1, 0, 0);
  turned.where = {"deck.k", 7};
  model.coordinate_systems[5] = turned;
  try {
    solver::build_problem(model);
    FAIL() << "a turned local coordinate system was accepted";
  } catch (const InputError& e) {
    EXPECT_STREQ(e.what(), "deck.k:42: *BOUNDARY_SPC_NODE: CID: coordinate system 5 (*DEFINE_COORDINATE_VECTOR at "
                           "deck.k:7) has local x axis (0, 1, 0), not the global one: Spall applies this card in "
                           "global axes only");
  }
}
