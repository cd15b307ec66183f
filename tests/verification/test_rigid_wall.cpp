// Planar rigid walls (*RIGIDWALL_PLANAR, _FINITE, _MOVING) against closed forms.
//
// - Elastic bar end-on against a fixed wall (Ansys VM265; Graff, Wave Motion in Elastic Solids,
//   §2.1): the contact lasts 2L/c, c = sqrt(E/rho) (PR = 0, so bar and P-wave speeds agree), the
//   wall force is rho c v0 A, the bar leaves at -v0. Tolerances: contact time 2 %
//   (shared/reference/validation.md §4); force 5 %; rebound 10 % (40 particles along the bar lose
//   6 % of v0 to the first layer's stop, artificial viscosity and ringing; 80 lose 3.7 %).
// - Coulomb friction: a block sliding on the wall decelerates at mu g and stays stopped; on an
//   inclined plane (gravity g_n into the wall, g_t along it) it slides at g_t - mu g_n when
//   g_t > mu g_n and stays when g_t < mu g_n; FRIC = 1 lets no node slide (LS-DYNA manual,
//   *RIGIDWALL_PLANAR FRIC).
// - A moving wall of mass M takes the reaction impulses: the momentum of wall and body along its
//   normal is conserved to round-off.
// - Single particles (no neighbours, so no internal force): the kinematic contact law exactly.
// - Energy: the wall's work is external work; the balance closes. 1 thread = 2 threads bitwise.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <omp.h>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "support/sph_block.hpp"

using namespace spall;

namespace {

// The problem refers to the model's curves: both live as long as the scene.
struct Scene {
  std::unique_ptr<model::Model> model;
  solver::Problem problem;
};

Scene build(std::unique_ptr<model::Model> model) {
  solver::Problem problem = solver::build_problem(*model);
  return {std::move(model), std::move(problem)};
}

model::Curve constant_curve(Id id, Real value) {
  model::Curve c;
  c.id = id;
  c.points = {{0.0, value}, {1.0, value}};
  return c;
}

struct History {
  std::vector<Real> time, dt, normal_force, wall_velocity;
  std::vector<Vec3> force, body_velocity;
  solver::RunSummary summary;
};

Real total_mass(const discretization::NodeStore& nodes) {
  Real m = 0;
  for (Index i = 0; i < nodes.size(); ++i) m += nodes.mass[i];
  return m;
}

Vec3 mean_velocity(const discretization::NodeStore& nodes) {
  Vec3 p = Vec3::Zero();
  for (Index i = 0; i < nodes.size(); ++i) p += nodes.mass[i] * nodes.v[i];
  return p / total_mass(nodes);
}

Vec3 mean_displacement(const discretization::NodeStore& nodes) {
  Vec3 u = Vec3::Zero();
  for (Index i = 0; i < nodes.size(); ++i) u += nodes.mass[i] * (nodes.x[i] - nodes.x0[i]);
  return u / total_mass(nodes);
}

// Runs with the first wall's force and the body's mean velocity v^{n+1/2} recorded every step.
History run_recorded(solver::Problem& problem) {
  History h;
  solver::Observer observer;
  observer.on_rigid_wall_forces = [&](const solver::StepInfo& s,
                                      const std::vector<contact::RigidWall>& walls) {
    h.time.push_back(s.time);
    h.dt.push_back(s.dt);
    h.normal_force.push_back(walls.front().normal_force());
    h.force.push_back(walls.front().force());
    h.wall_velocity.push_back(walls.front().velocity());
    h.body_velocity.push_back(mean_velocity(problem.nodes));
  };
  problem.controls.rwforc_dt = 1e-30;  // every step
  h.summary = solver::run(problem, observer);
  return h;
}

// The impulse of the recorded wall forces: each step's force acts over its velocity interval,
// dt/2 on the first step and (dt^{n-1/2} + dt^{n+1/2}) / 2 after.
Vec3 impulse_on_wall(const History& h) {
  Vec3 j = Vec3::Zero();
  for (std::size_t k = 0; k < h.time.size(); ++k)
    j += h.force[k] * (k == 0 ? 0.5 * h.dt[0] : 0.5 * (h.dt[k - 1] + h.dt[k]));
  return j;
}

// ---- Elastic bar end-on against a fixed wall ---------------------------------------------------

struct BarImpact {
  Real length = 0.2, width = 0.02, spacing = 0.005;  // 40 x 4 x 4 particles
  Real density = 7850, young = 200e9;
  Real speed = 10;  // m/s: strain v0/c = 2e-3, linear
  Real bar_speed() const { return std::sqrt(young / density); }
  Real contact_time() const { return 2 * length / bar_speed(); }
};

Scene bar_impact(const BarImpact& bar, Real end_time) {
  test_support::ElasticBlock b;
  b.size = Vec3(bar.length, bar.width, bar.width);
  b.spacing = bar.spacing;
  b.density = bar.density;
  b.young = bar.young;
  b.poisson = 0.0;
  b.end_time = end_time;
  auto model = std::make_unique<model::Model>(test_support::elastic_block_model(b));
  // The first layer of particles on the wall x = 0 at t = 0, the bar moving onto it.
  for (auto& node : model->nodes) node.x.x() -= 0.5 * bar.spacing;
  model::InitialVelocity iv;
  iv.v = Vec3(-bar.speed, 0, 0);
  model->initial_velocities.push_back(iv);
  model::RigidWallPlanar wall;
  wall.head = Vec3(1, 0, 0);
  model->rigid_walls.push_back(wall);
  // Half the default step: the energy balance's time-integration error near the highest
  // frequencies the impact excites is 2.4e-3 at TSSFAC 0.9 and 4.7e-4 here (it falls as dt^2).
  model->timestep.tssfac = 0.45;
  return build(std::move(model));
}

// ---- A block standing on the wall z = 0 ------------------------------------------------------

// A 0.1 x 0.1 x 0.05 m steel block, 10 x 10 x 5 particles, its lowest layer on the wall z = 0,
// pressed on it by *LOAD_BODY_Z g_n and pulled along x by *LOAD_BODY_X g_t.
struct BlockOnWall {
  Real g_normal = 6000, g_tangential = 0;  // large g: the block slides and stops in ~300 steps
  Real friction = 0.3;
  Real speed = 0;  // initial velocity along x
  Real ramp = 0;   // the loads grow linearly from 0 over this time (0: all at once)
};

Scene block_on_wall(const BlockOnWall& c, Real end_time) {
  test_support::ElasticBlock b;
  b.size = Vec3(0.1, 0.1, 0.05);
  b.spacing = 0.01;
  b.end_time = end_time;
  auto model = std::make_unique<model::Model>(test_support::elastic_block_model(b));
  for (auto& node : model->nodes) node.x.z() -= 0.5 * b.spacing;
  model->curves[1] = constant_curve(1, 1.0);
  if (c.ramp > 0) model->curves[1].points = {{0.0, 0.0}, {c.ramp, 1.0}, {1.0, 1.0}};
  model::BodyLoad down;
  down.direction = 2;
  down.lcid = 1;
  down.sf = c.g_normal;
  model->body_loads.push_back(down);
  if (c.g_tangential != 0) {
    model::BodyLoad along = down;
    along.direction = 0;
    along.sf = -c.g_tangential;  // nodes feel -m a: a negative X load pulls towards +x
    model->body_loads.push_back(along);
  }
  model::InitialVelocity iv;
  iv.v = Vec3(c.speed, 0, 0);
  model->initial_velocities.push_back(iv);
  model::RigidWallPlanar wall;
  wall.head = Vec3(0, 0, 1);
  wall.fric = c.friction;
  model->rigid_walls.push_back(wall);
  return build(std::move(model));
}

// ---- Single particles --------------------------------------------------------------------------

// Particles of 1 cm^3 steel (h = 1.2 cm) at least 10 cm apart: no neighbours, no internal force.
std::unique_ptr<model::Model> particles(const std::vector<Vec3>& x, const std::vector<Vec3>& v,
                                        Real end_time) {
  test_support::ElasticBlock b;
  b.size = Vec3(0.01, 0.01, 0.01);
  b.spacing = 0.01;
  b.end_time = end_time;
  auto model = std::make_unique<model::Model>(test_support::elastic_block_model(b));
  model->nodes.clear();
  model->sph_elements.clear();
  for (std::size_t k = 0; k < x.size(); ++k) {
    const Id id = static_cast<Id>(k + 1);
    model->nodes.push_back({id, x[k], 0, 0, {}});
    model->sph_elements.push_back({id, 1, -1e-6, {}});
    model::InitialVelocityNode iv;
    iv.nid = id;
    iv.v = v[k];
    model->initial_velocity_nodes.push_back(iv);
  }
  return model;
}

// The node store index of deck node `id`.
Index index_of(const discretization::NodeStore& nodes, Id id) {
  for (Index i = 0; i < nodes.size(); ++i)
    if (nodes.id[i] == id) return i;
  return -1;
}

}  // namespace

TEST(RigidWall, ElasticBarImpactMatchesVM265) {
  log::set_quiet(true);
  const BarImpact bar;
  Scene scene = bar_impact(bar, 1.3 * bar.contact_time());
  const History h = run_recorded(scene.problem);
  const auto& nodes = scene.problem.nodes;

  // Contact: from the first step (the bar starts on the wall) until no node is pushed any more.
  ASSERT_GT(h.normal_force.front(), 0.0);
  std::size_t end = 1;
  while (end < h.time.size() && h.normal_force[end] > 0) ++end;
  ASSERT_LT(end, h.time.size()) << "the bar never left the wall";
  const Real contact = h.time[end];
  for (std::size_t k = end; k < h.time.size(); ++k) EXPECT_EQ(h.normal_force[k], 0.0);

  // The plateau: the median force over the middle half of the contact.
  std::vector<Real> plateau;
  for (std::size_t k = 0; k < end; ++k)
    if (h.time[k] > 0.25 * contact && h.time[k] < 0.75 * contact) plateau.push_back(h.normal_force[k]);
  std::nth_element(plateau.begin(), plateau.begin() + plateau.size() / 2, plateau.end());
  const Real median_force = plateau[plateau.size() / 2];
  const Real expected_force = bar.density * bar.bar_speed() * bar.speed * bar.width * bar.width;
  const Vec3 rebound = mean_velocity(nodes);
  std::printf("contact %.4e s vs 2L/c %.4e s (%+.2f %%); force %.4e N vs rho c v0 A %.4e N (%+.2f %%); "
              "rebound %.4f m/s vs %.1f (%+.2f %%); energy ratio %.6f; %lld steps\n",
              contact, bar.contact_time(), 100 * (contact / bar.contact_time() - 1), median_force,
              expected_force, 100 * (median_force / expected_force - 1), rebound.x(), bar.speed,
              100 * (rebound.x() / bar.speed - 1), h.summary.energies.ratio(), h.summary.steps);
  EXPECT_NEAR(contact / bar.contact_time(), 1.0, 0.02);
  EXPECT_NEAR(median_force / expected_force, 1.0, 0.05);
  EXPECT_NEAR(rebound.x() / bar.speed, 1.0, 0.10);
  EXPECT_LT(std::abs(rebound.y()) + std::abs(rebound.z()), 1e-9 * bar.speed);

  // The force written for the wall is the momentum the bar took: to round-off.
  const Vec3 bar_momentum_change = total_mass(nodes) * (rebound - Vec3(-bar.speed, 0, 0));
  EXPECT_LT((impulse_on_wall(h) + bar_momentum_change).norm(), 1e-9 * bar_momentum_change.norm());
  // Pushed along its normal only: no friction, no tangential force.
  for (const Vec3& f : h.force) {
    EXPECT_EQ(f.y(), 0.0);
    EXPECT_EQ(f.z(), 0.0);
  }

  // The wall's work (the first layer's stop) is external work: the balance closes.
  EXPECT_NEAR(h.summary.energies.ratio(), 1.0, 1e-3);
  EXPECT_LT(h.summary.energies.external_work(), 0.0);
}

TEST(RigidWall, CoulombFrictionStopsASlidingBlock) {
  log::set_quiet(true);
  BlockOnWall c;
  c.speed = 1.0;
  const Real deceleration = c.friction * c.g_normal;
  const Real stop = c.speed / deceleration;
  Scene scene = block_on_wall(c, 1.5 * stop);
  const History h = run_recorded(scene.problem);

  // Least-squares slope of v_x(t) over [0.1, 0.9] t_stop: the normal force rings around M g
  // (the load starts at once), the slope averages that out.
  Real st = 0, sv = 0, stt = 0, stv = 0, count = 0;
  for (std::size_t k = 0; k < h.time.size(); ++k) {
    const Real t = h.time[k] + 0.5 * h.dt[k];  // v^{n+1/2}
    if (t < 0.1 * stop || t > 0.9 * stop) continue;
    const Real v = h.body_velocity[k].x();
    st += t, sv += v, stt += t * t, stv += t * v, count += 1;
  }
  const Real slope = (count * stv - st * sv) / (count * stt - st * st);
  const Real travel = mean_displacement(scene.problem.nodes).x();
  Real after_stop = 0;
  for (std::size_t k = 0; k < h.time.size(); ++k)
    if (h.time[k] > 1.2 * stop) after_stop = std::max(after_stop, std::abs(h.body_velocity[k].x()));
  std::printf("deceleration %.2f m/s2 vs mu g %.2f (%+.2f %%); travel %.4e m vs v0^2/(2 mu g) %.4e "
              "(%+.2f %%); |v| after the stop < %.2e m/s; energy ratio %.5f\n",
              -slope, deceleration, 100 * (-slope / deceleration - 1), travel,
              c.speed * c.speed / (2 * deceleration),
              100 * (travel / (c.speed * c.speed / (2 * deceleration)) - 1), after_stop,
              h.summary.energies.ratio());
  EXPECT_NEAR(-slope / deceleration, 1.0, 0.03);
  EXPECT_NEAR(travel / (c.speed * c.speed / (2 * deceleration)), 1.0, 0.03);
  EXPECT_LT(after_stop, 0.005 * c.speed);
  // Friction took the kinetic energy as (negative) external work.
  const auto& e = h.summary.energies;
  EXPECT_LT(std::abs(e.total() - e.initial_total() - e.external_work()), 1e-3 * e.initial_total());
}

TEST(RigidWall, InclinedPlaneSlidesOrHoldsAsCoulombSays) {
  log::set_quiet(true);
  // tan(theta) = g_t / g_n = 0.5: slides for mu = 0.3 at a = g_t - mu g_n, holds for mu = 0.6.
  // The loads grow over 2e-4 s, six periods of the block's lowest axial mode (4H/c = 3.4e-5 s),
  // so that it settles on the wall without bouncing off it.
  BlockOnWall c;
  c.g_tangential = 0.5 * c.g_normal;
  c.ramp = 2e-4;
  const Real end_time = 5e-4;
  // x(t) for an acceleration a r(t), r rising linearly to 1 at t_r: a t^3 / (6 t_r) up to t_r,
  // then a t_r^2 / 6 + a t_r (t - t_r) / 2 + a (t - t_r)^2 / 2.
  auto ramped_travel = [&](Real a, Real t) {
    const Real tr = c.ramp, late = t - tr;
    return t <= tr ? a * t * t * t / (6 * tr) : a * (tr * tr / 6 + tr * late / 2 + late * late / 2);
  };
  c.friction = 0.3;
  Scene sliding = block_on_wall(c, end_time);
  run_recorded(sliding.problem);
  const Real expected = ramped_travel(c.g_tangential - c.friction * c.g_normal, end_time);
  const Real travel = mean_displacement(sliding.problem.nodes).x();
  c.friction = 0.6;
  Scene holding = block_on_wall(c, end_time);
  run_recorded(holding.problem);
  const Real creep = mean_displacement(holding.problem.nodes).x();
  c.friction = 1.0;  // no sliding
  Scene stuck = block_on_wall(c, end_time);
  run_recorded(stuck.problem);
  std::printf("mu 0.3: travel %.4e m vs the ramped (g_t - mu g_n) %.4e (%+.2f %%); mu 0.6: %.3e m\n",
              travel, expected, 100 * (travel / expected - 1), creep);
  EXPECT_NEAR(travel / expected, 1.0, 0.03);
  // Held: the mean displacement is the block's elastic shear only, far below a slide.
  EXPECT_LT(std::abs(creep), 0.02 * expected);
  // FRIC = 1: no node slides while it is on the wall. A few corner particles lift off for a
  // moment as the block shears (then they are free), so the layer's largest slip is not exactly
  // zero, but it is tiny against the mu = 0.3 slide.
  const auto& nodes = stuck.problem.nodes;
  Real slip = 0;
  int on_wall = 0;
  for (Index i = 0; i < nodes.size(); ++i)
    if (nodes.x0[i].z() == 0.0) {
      ++on_wall;
      slip = std::max(slip, (nodes.x[i] - nodes.x0[i]).head<2>().norm());
    }
  std::printf("FRIC 1: largest slip of the %d particles on the wall %.3e m\n", on_wall, slip);
  EXPECT_EQ(on_wall, 100);
  EXPECT_LT(slip, 1e-3 * expected);
}

namespace {
// The bar at rest, `gap` in front of a wall of `mass_ratio` times its mass moving onto it at V0.
std::unique_ptr<model::Model> bar_struck_by_moving_wall(const BarImpact& bar, Real mass_ratio, Real gap,
                                                       Real end_time) {
  auto model = std::make_unique<model::Model>(*bar_impact(bar, end_time).model);
  for (auto& node : model->nodes) node.x.x() += gap;
  model->initial_velocities.clear();
  auto& wall = model->rigid_walls.front();
  wall.moving = true;
  wall.mass = mass_ratio * bar.density * bar.length * bar.width * bar.width;
  wall.v0 = bar.speed;
  return model;
}
}  // namespace

TEST(RigidWall, MovingWallConservesMomentum) {
  log::set_quiet(true);
  const BarImpact bar;
  const Real mass_ratio = 50;
  const Real gap = 0.0005;
  Scene scene = build(bar_struck_by_moving_wall(bar, mass_ratio, gap, gap / bar.speed + 1.5 * bar.contact_time()));
  const History h = run_recorded(scene.problem);
  const Real wall_mass = scene.model->rigid_walls.front().mass;
  const Real m = total_mass(scene.problem.nodes);
  const Real p0 = wall_mass * bar.speed;
  Real worst = 0;
  for (std::size_t k = 0; k < h.time.size(); ++k)
    worst = std::max(worst, std::abs(wall_mass * h.wall_velocity[k] + m * h.body_velocity[k].x() - p0));
  const auto& wall = scene.problem.rigid_walls.front();
  const Real bar_speed = mean_velocity(scene.problem.nodes).x();
  // An elastic bar struck by a rigid mass M leaves at most at 2 V0 / (1 + m/M), when no
  // vibration is left in it (Newton's law of an elastic collision).
  const Real elastic = 2 * bar.speed / (1 + m / wall_mass);
  std::printf("wall %.4f m/s, bar %.4f m/s (elastic collision %.4f, %+.2f %%); momentum error %.2e of "
              "%.4e; energy ratio %.6f\n",
              wall.velocity(), bar_speed, elastic, 100 * (bar_speed / elastic - 1), worst, p0,
              h.summary.energies.ratio());
  EXPECT_LT(worst, 1e-12 * p0);
  EXPECT_NEAR(bar_speed / elastic, 1.0, 0.10);
  EXPECT_LE(bar_speed, elastic * (1 + 1e-9));
  // The wall moved on by the impulse it gave: V0 - m v_bar / M.
  EXPECT_NEAR(wall.velocity(), bar.speed - m * bar_speed / wall_mass, 1e-12 * bar.speed);
  // The wall did work on the bar (external work), and the balance closes.
  EXPECT_GT(h.summary.energies.external_work(), 0.0);
  EXPECT_NEAR(h.summary.energies.ratio(), 1.0, 1e-3);
}

TEST(RigidWall, OneAndTwoThreadsGiveTheSameBits) {
  log::set_quiet(true);
  // A 32 x 32 x 4 particle plate sliding across a moving wall with friction that strikes it: every
  // loop of the wall runs, and in parallel (1024 particles pushed at once, enough for the wall's
  // loops to use threads), with the pushed nodes sorted by the moving wall; 20 steps.
  auto run_with = [&](int threads) {
    omp_set_num_threads(threads);
    test_support::ElasticBlock b;
    b.size = Vec3(0.32, 0.32, 0.04);
    b.spacing = 0.01;
    b.end_time = 4e-5;
    auto model = std::make_unique<model::Model>(test_support::elastic_block_model(b));
    for (auto& node : model->nodes) node.x.z() -= 0.5 * b.spacing;
    model::InitialVelocity across;
    across.v = Vec3(1.0, 0.5, 0);
    model->initial_velocities.push_back(across);
    model::RigidWallPlanar wall;
    wall.head = Vec3(0, 0, 1);
    wall.fric = 0.3;
    wall.moving = true;
    wall.mass = 10 * 7850 * 0.32 * 0.32 * 0.04;
    wall.v0 = 5;
    model->rigid_walls.push_back(wall);
    Scene scene = build(std::move(model));
    History h = run_recorded(scene.problem);
    return std::pair(std::move(scene), std::move(h));
  };
  const int before = omp_get_max_threads();
  const auto [one, h1] = run_with(1);
  const auto [two, h2] = run_with(2);
  omp_set_num_threads(before);
  EXPECT_EQ(one.problem.nodes.x, two.problem.nodes.x);
  EXPECT_EQ(one.problem.nodes.v, two.problem.nodes.v);
  EXPECT_EQ(h1.force, h2.force);
  EXPECT_EQ(h1.wall_velocity, h2.wall_velocity);
  // In contact, with friction acting: the wall's code ran.
  EXPECT_GT(h1.normal_force.front(), 0.0);
  EXPECT_GT(h1.force.front().x(), 0.0);  // the plate slides along +x and drags the wall with it
}

namespace {
// Particle k (deck node k + 1) sits 10 cm along x from the one before, `height` above z = 0.
Vec3 particle_at(int k, Real height) { return Vec3(0.1 * k, 0, height); }

model::NodeSet node_set(Id id, std::vector<Id> nodes) {
  model::NodeSet set;
  set.id = id;
  set.nodes = std::move(nodes);
  return set;
}

// A wall z = 0 (normal +z) for the nodes of set `nsid`.
model::RigidWallPlanar floor_for(Id nsid, Real fric) {
  model::RigidWallPlanar wall;
  wall.nsid = nsid;
  wall.head = Vec3(0, 0, 1);
  wall.fric = fric;
  return wall;
}
}  // namespace

// Single particles falling at 20 m/s onto walls z = 0. The kinematic law: the normal velocity is
// removed (the particle lands on the wall and stays), and friction takes at most mu times the
// normal impulse from the tangential velocity (Coulomb's law for an impact): 50 - 0.5 * 20 = 40.
TEST(RigidWall, SingleParticlesFollowTheContactLaw) {
  log::set_quiet(true);
  const Real vn = 20, vt = 50;
  std::vector<Vec3> x, v;
  for (int k = 0; k < 12; ++k) {
    x.push_back(particle_at(k, k == 9 || k == 11 ? 0.02 : 0.01));  // 9, 11 arrive at 1e-3 s
    v.push_back(Vec3(k < 3 ? vt : 0, 0, -vn));
  }
  auto model = particles(x, v, 1.5e-3);
  for (Id s = 1; s <= 12; ++s) model->node_sets[s] = node_set(s, {s});
  model->node_sets[20] = node_set(20, {4, 5});
  model->node_sets[21] = node_set(21, {5});
  model->node_sets[22] = node_set(22, {6, 7});
  model->node_sets[23] = node_set(23, {9, 10});
  model->node_sets[24] = node_set(24, {11, 12});
  auto& walls = model->rigid_walls;
  walls.push_back(floor_for(1, 0.0));   // 1: frictionless
  walls.push_back(floor_for(2, 0.5));   // 2: Coulomb
  walls.push_back(floor_for(3, 1.0));   // 3: no sliding
  walls.push_back(floor_for(20, 0.0));  // 4 tracked, 5 exempted (NSIDEX)
  walls.back().nsidex = 21;
  walls.push_back(floor_for(22, 0.0));  // finite: 0.05 x 0.05 around node 6, node 7 beside it
  walls.back().finite = true;
  walls.back().tail = particle_at(5, 0) - Vec3(0.025, 0.025, 0);
  walls.back().head = walls.back().tail + Vec3(0, 0, 1);
  walls.back().edge_head = walls.back().tail + Vec3(1, 0, 0);
  walls.back().lenl = walls.back().lenm = 0.05;
  walls.push_back(floor_for(8, 0.0));  // OFFSET 5 mm: node 8, 10 mm away, is not tracked
  walls.back().offset = 0.005;
  walls.push_back(floor_for(23, 0.0));  // born at 7.5e-4 s: node 9 (there at 5e-4) passes, 10 not
  walls.back().birth = 7.5e-4;
  walls.push_back(floor_for(24, 0.0));  // dead at 7.5e-4 s: node 11 stopped, 12 (1e-3) passes
  walls.back().death = 7.5e-4;
  Scene scene = build(std::move(model));
  const History h = run_recorded(scene.problem);
  const auto& nodes = scene.problem.nodes;
  auto node = [&](Id id) { return index_of(nodes, id); };
  const Real m = nodes.mass[node(1)];

  auto stopped_on_wall = [&](Id id) {
    const Index i = node(id);
    EXPECT_NEAR(nodes.x[i].z(), 0.0, 1e-15) << "node " << id;
    EXPECT_NEAR(nodes.v[i].z(), 0.0, 1e-12) << "node " << id;  // round-off of the landing
  };
  auto passed_through = [&](Id id) {
    EXPECT_LT(nodes.x[node(id)].z(), -0.005) << "node " << id;
    EXPECT_EQ(nodes.v[node(id)].z(), -vn) << "node " << id;
  };
  for (Id id : {1, 2, 3, 4, 6, 10, 11}) stopped_on_wall(id);
  for (Id id : {5, 7, 8, 9, 12}) passed_through(id);
  EXPECT_NEAR(nodes.v[node(1)].x(), vt, 1e-12);
  EXPECT_NEAR(nodes.v[node(2)].x(), vt - 0.5 * vn, 1e-12);
  EXPECT_EQ(nodes.v[node(3)].x(), 0.0);
  // The first wall took the particle's momentum m vn, all along its normal.
  const Vec3 impulse = impulse_on_wall(h);
  EXPECT_NEAR(impulse.z(), -m * vn, 1e-12 * m * vn);
  EXPECT_EQ(impulse.x(), 0.0);
  // Frictionless: the tangential velocity is kept, the particle slides on along the wall.
  EXPECT_NEAR(nodes.x[node(1)].x() - nodes.x0[node(1)].x(), vt * 1.5e-3, 1e-12);
}

// FRIC 2 and 3 with WVEL = 10 m/s: a particle that hits faster is welded and stays on the wall
// when a body load later pulls it away (FRIC 3 also stops its sliding); a slower one is not.
TEST(RigidWall, FastImpactsWeld) {
  log::set_quiet(true);
  auto model = particles({particle_at(0, 0.01), particle_at(1, 0.0025), particle_at(2, 0.01)},
                         {Vec3(0, 0, -20), Vec3(0, 0, -5), Vec3(30, 0, -20)}, 1.5e-3);
  model->node_sets[1] = node_set(1, {1, 2});
  model->node_sets[2] = node_set(2, {3});
  model->rigid_walls.push_back(floor_for(1, 2.0));
  model->rigid_walls.push_back(floor_for(2, 3.0));
  for (auto& wall : model->rigid_walls) wall.wvel = 10;
  // From 1e-3 s on, every particle is pulled away from the wall at 1000 m/s^2.
  model::Curve pull;
  pull.id = 1;
  pull.points = {{0.0, 0.0}, {1e-3, 0.0}, {1.001e-3, -1000.0}, {1.0, -1000.0}};
  model->curves[1] = pull;
  model::BodyLoad load;
  load.direction = 2;
  load.lcid = 1;
  model->body_loads.push_back(load);
  Scene scene = build(std::move(model));
  solver::run(scene.problem, {});
  const auto& nodes = scene.problem.nodes;
  const Index welded = index_of(nodes, 1), bounced = index_of(nodes, 2), stuck = index_of(nodes, 3);
  EXPECT_NEAR(nodes.x[welded].z(), 0.0, 1e-15);
  EXPECT_NEAR(nodes.v[welded].z(), 0.0, 1e-12);
  EXPECT_GT(nodes.x[bounced].z(), 1e-5);  // 1000 m/s^2 over 0.5 ms: 0.125 mm
  EXPECT_NEAR(nodes.x[stuck].z(), 0.0, 1e-15);
  EXPECT_EQ(nodes.v[stuck].x(), 0.0);
  // The rest of the run, the welded walls held the particles against the pull: a tension.
  EXPECT_LT(scene.problem.rigid_walls[0].normal_force(), 0.0);
}
