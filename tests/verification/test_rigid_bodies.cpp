// Rigid bodies (*MAT_RIGID parts; issue 33, fem-contact.md §2.5):
// - a brick spinning about its intermediate principal axis, barely perturbed, flips over and back
//   (the Dzhanibekov effect, the tennis-racket theorem: rotation about the intermediate axis is
//   unstable; Landau & Lifshitz, Mechanics §37), with its kinetic energy and angular momentum
//   kept to 1e-6 over 10^5 steps and its shape to round-off;
// - a prescribed rotation (DOF 7, VAD 0) and a prescribed plunge (DOF 3, VAD 2) move a body exactly
//   as their curves say, with *MAT_RIGID CMO 1 holding the other degrees of freedom;
// - two bodies merged by *CONSTRAINED_RIGID_BODIES turn as one about their common centre;
// - what Spall cannot run is refused at the card.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "unit/keyword_test_decks.hpp"

using namespace spall;

namespace {

// A brick a x b x c of nx x ny x nz hexahedra of *MAT_RIGID (part 1), centred at the origin.
model::Model rigid_brick(Vec3 size, std::array<int, 3> n, Real end_time, Real step) {
  model::Model m;
  m.parts.push_back({1, "brick", 1, 1, 0, 0, 0, {}, {}});
  m.sections[1] = model::SectionSolid{1, 1, 0, {}};
  model::Material mat;
  mat.id = 1;
  mat.keyword = "*MAT_RIGID";
  mat.params = model::MatRigid{7850, 2e11, 0.3};
  m.materials[1] = mat;
  const auto id = [&](int i, int j, int k) { return Id(1 + i + (n[0] + 1) * (j + (n[1] + 1) * k)); };
  for (int k = 0; k <= n[2]; ++k)
    for (int j = 0; j <= n[1]; ++j)
      for (int i = 0; i <= n[0]; ++i)
        m.nodes.push_back({id(i, j, k), Vec3(size.x() * (Real(i) / n[0] - 0.5), size.y() * (Real(j) / n[1] - 0.5),
                                             size.z() * (Real(k) / n[2] - 0.5)), 0, 0, {}});
  Id eid = 1;
  for (int k = 0; k < n[2]; ++k)
    for (int j = 0; j < n[1]; ++j)
      for (int i = 0; i < n[0]; ++i)
        m.solid_elements.push_back({eid++, 1,
                                    {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                                     id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)},
                                    {}});
  model::ControlTermination term;
  term.endtim = end_time;
  m.termination = term;
  // Nothing deformable limits the step: LCTM holds it at `step`.
  model::Curve limit;
  limit.id = 99;
  limit.points = {{0.0, step}, {1e6, step}};
  m.curves[99] = limit;
  m.timestep.lctm = 99;
  return m;
}

}  // namespace

TEST(RigidBodies, IntermediateAxisFlipsWithEnergyAndMomentumKept) {
  log::set_quiet(true);
  // Lumped, this brick's principal moments are 0.045, 0.070, 0.085 (x, y, z; per unit mass and
  // m^2): a perturbation of 1e-3 grows at lambda = omega sqrt((I2 - I1)(I3 - I2) / (I1 I3)) =
  // 3.13 /s, and the body turns over after about ln(2e3) / lambda = 2.4 s.
  const Real end = 6.0;
  model::Model m = rigid_brick(Vec3(0.3, 0.2, 0.1), {3, 2, 1}, end, end / 1e5);
  // omega = 10 rad/s about y (the intermediate axis), perturbed by 1e-3 of it about x and z.
  const Vec3 omega(1e-2, 10, 1e-2);
  for (const auto& node : m.nodes) m.initial_velocity_nodes.push_back({node.id, omega.cross(node.x), Vec3::Zero(), 0, {}});
  solver::Problem p = solver::build_problem(m);
  ASSERT_EQ(p.rigid_bodies.bodies().size(), 1u);
  p.controls.glstat_dt = end / 300;
  const auto& body = p.rigid_bodies.bodies()[0];
  const Real energy0 = 0.5 * body.angular_velocity.dot(body.angular_momentum);
  const Vec3 momentum0 = body.angular_momentum;
  Real worst_energy = 0, worst_momentum = 0, lowest_alignment = 1, worst_shape = 0;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo& step, const discretization::EnergyLedger&) {
    if (step.step == 0) return;
    const Real energy = 0.5 * body.angular_velocity.dot(body.angular_momentum);
    worst_energy = std::max(worst_energy, std::abs(energy / energy0 - 1));
    worst_momentum = std::max(worst_momentum, (body.angular_momentum - momentum0).norm() / momentum0.norm());
    // The body's y axis against the angular momentum: +1 at the start, -1 once flipped.
    lowest_alignment = std::min(lowest_alignment, (body.rotation * Vec3::UnitY()).dot(momentum0.normalized()));
    // Rigid: every distance between two nodes as at the start.
    for (Index i = 0; i < p.nodes.size(); ++i)
      for (Index j = 0; j < i; ++j)
        worst_shape = std::max(worst_shape, std::abs((p.nodes.x[i] - p.nodes.x[j]).norm() -
                                                     (p.nodes.x0[i] - p.nodes.x0[j]).norm()));
  };
  const auto summary = solver::run(p, observer);
  std::printf("%lld steps: energy within %.2e, angular momentum within %.2e, y axis . L down to %.4f, shape within %.2e m\n",
              summary.steps, worst_energy, worst_momentum, lowest_alignment, worst_shape);
  EXPECT_GE(summary.steps, 100000);
  EXPECT_LT(worst_energy, 1e-6);
  EXPECT_LT(worst_momentum, 1e-6);
  EXPECT_LT(lowest_alignment, -0.9);  // flipped over
  EXPECT_LT(worst_shape, 1e-14);
  // The ledger agrees: the nodes' kinetic energy is the body's, and the rigid constraint does no
  // work.
  std::printf("ledger: kinetic %.9g J (body %.9g J), energy ratio %.9f\n", summary.energies.kinetic(), energy0,
              summary.energies.ratio());
  EXPECT_NEAR(summary.energies.ratio(), 1.0, 1e-6);
}

TEST(RigidBodies, PrescribedRotationAndPlungeFollowTheirCurves) {
  log::set_quiet(true);
  const Real end = 0.01, omega = 314.16;  // 3000 rpm
  model::Model m = rigid_brick(Vec3(0.02, 0.02, 0.04), {2, 2, 4}, end, end / 2000);
  auto& card = std::get<model::MatRigid>(m.materials[1].params);
  card.cmo = 1, card.con1 = 4, card.con2 = 4;  // x and y held, and the tilts
  model::Curve spin, plunge;
  spin.id = 1, spin.points = {{0.0, 1.0}, {1.0, 1.0}};
  plunge.id = 2, plunge.points = {{0.0, 0.0}, {0.01, -0.002}};  // 2 mm down over 10 ms
  m.curves[1] = spin, m.curves[2] = plunge;
  m.prescribed_motions.push_back({model::Target::part, 1, 7, 0, 1, omega, 0, 1e28, 0, {}});
  m.prescribed_motions.push_back({model::Target::part, 1, 3, 2, 2, 1.0, 0, 1e28, 0, {}});
  // A sideways kick that the CMO constraints must cancel.
  for (const auto& node : m.nodes) m.initial_velocity_nodes.push_back({node.id, Vec3(1, 0, 0), Vec3::Zero(), 0, {}});
  solver::Problem p = solver::build_problem(m);
  const Vec3 corner0 = p.nodes.x0[0];
  solver::run(p, {});
  const auto& body = p.rigid_bodies.bodies().at(0);
  // The corner turned by omega t about z through the centre, and moved down with the plunge.
  const Real angle = omega * end;
  const Vec3 expected(std::cos(angle) * corner0.x() - std::sin(angle) * corner0.y(),
                      std::sin(angle) * corner0.x() + std::cos(angle) * corner0.y(), corner0.z() - 0.002);
  std::printf("corner at %.9f %.9f %.9f, expected %.9f %.9f %.9f; centre %.3e %.3e %.9f\n", p.nodes.x[0].x(),
              p.nodes.x[0].y(), p.nodes.x[0].z(), expected.x(), expected.y(), expected.z(), body.centre.x(),
              body.centre.y(), body.centre.z());
  EXPECT_LT((p.nodes.x[0] - expected).norm(), 1e-9);
  EXPECT_NEAR(body.centre.x(), 0, 1e-15);
  EXPECT_NEAR(body.centre.y(), 0, 1e-15);
  EXPECT_NEAR(body.centre.z(), -0.002, 1e-12);
  EXPECT_NEAR(body.angular_velocity.z(), omega, 1e-9);
}

TEST(RigidBodies, ConstrainedRigidBodiesMoveAsOne) {
  log::set_quiet(true);
  // Two bricks side by side with no node in common (part 2 a copy of part 1 moved along x),
  // merged by *CONSTRAINED_RIGID_BODIES; the lead turns at 100 rad/s about z, and the pair turns
  // as one body about their common centre, every distance kept.
  const Real end = 0.02;
  model::Model m = rigid_brick(Vec3(0.02, 0.02, 0.02), {1, 1, 1}, end, end / 1000);
  m.parts.push_back({2, "second brick", 1, 1, 0, 0, 0, {}, {}});
  const std::size_t node_count = m.nodes.size();
  for (std::size_t k = 0; k < node_count; ++k) {
    model::Node copy = m.nodes[k];
    copy.id += 100;
    copy.x.x() += 0.05;
    m.nodes.push_back(copy);
  }
  model::ElementSolid second = m.solid_elements[0];
  second.eid = 2, second.pid = 2;
  for (Id& n : second.n) n += 100;
  m.solid_elements.push_back(second);
  m.merged_rigid_bodies.push_back({1, 2, {}});
  model::Curve spin;
  spin.id = 1, spin.points = {{0.0, 100.0}, {1.0, 100.0}};
  m.curves[1] = spin;
  m.prescribed_motions.push_back({model::Target::part, 1, 7, 0, 1, 1.0, 0, 1e28, 0, {}});
  solver::Problem p = solver::build_problem(m);
  ASSERT_EQ(p.rigid_bodies.bodies().size(), 1u);
  const auto& body = p.rigid_bodies.bodies()[0];
  EXPECT_EQ(body.node.size(), 16u);
  EXPECT_NEAR(body.centre.x(), 0.025, 1e-15);  // between the two bricks
  solver::run(p, {});
  Real worst = 0;
  for (Index i = 0; i < p.nodes.size(); ++i)
    for (Index j = 0; j < i; ++j)
      worst = std::max(worst, std::abs((p.nodes.x[i] - p.nodes.x[j]).norm() - (p.nodes.x0[i] - p.nodes.x0[j]).norm()));
  // The second brick's centre went round the common centre by 100 rad/s x 20 ms = 2 rad.
  Vec3 second_centre = Vec3::Zero();
  for (Index i = 0; i < p.nodes.size(); ++i)
    if (p.nodes.id[i] > 100) second_centre += p.nodes.x[i] / 8;
  const Vec3 expected = body.centre + 0.025 * Vec3(std::cos(2.0), std::sin(2.0), 0);
  std::printf("merged pair: distances kept to %.2e m, second centre off by %.2e m\n", worst,
              (second_centre - expected).norm());
  EXPECT_LT(worst, 1e-15);
  EXPECT_LT((second_centre - expected).norm(), 1e-12);
  // The constrained part's own prescribed motion is refused: the lead's moves the body.
  m.prescribed_motions.back().id = 2;
  EXPECT_NE(test::input_error_of([&] { solver::build_problem(m); }).find("PID 2: merged into the body of part 1"),
            std::string::npos);
}

TEST(RigidBodies, ConstrainedRigidBodiesCardsAreRead) {
  test::DeckFolder folder;
  const auto m = io::keyword::read_deck(
      folder.write("merge.k", "*CONSTRAINED_RIGID_BODIES\n" + test::row({"1", "2"}) + test::row({"1", "3", "0"}) + "*END\n"));
  ASSERT_EQ(m.merged_rigid_bodies.size(), 2u);
  EXPECT_EQ(m.merged_rigid_bodies[1].lead, 1);
  EXPECT_EQ(m.merged_rigid_bodies[1].constrained, 3);
  const auto bad = folder.write("bad.k", "*CONSTRAINED_RIGID_BODIES\n" + test::row({"1", "2", "1"}) + "*END\n");
  EXPECT_NE(test::input_error_of([&] { io::keyword::read_deck(bad); }).find("field IFLAG: '1': only 0 is supported"),
            std::string::npos);
}

TEST(RigidBodies, WhatSpallCannotRunIsRefused) {
  log::set_quiet(true);
  const auto error_of = [](const model::Model& m) {
    return test::input_error_of([&] { solver::build_problem(m); });
  };
  model::Model m = rigid_brick(Vec3(0.1, 0.1, 0.1), {1, 1, 1}, 1e-3, 1e-5);
  model::Curve c;
  c.id = 1, c.points = {{0.0, 1.0}, {1.0, 1.0}};
  m.curves[1] = c;
  m.prescribed_motions.push_back({model::Target::part, 1, -4, 0, 1, 1.0, 0, 1e28, 0, {}});
  EXPECT_NE(error_of(m).find("DOF -4: only translations"), std::string::npos) << error_of(m);
  m.prescribed_motions.back().dof = 8;
  EXPECT_NE(error_of(m).find("VID 0: DOF 8 takes its direction from a *DEFINE_VECTOR"), std::string::npos)
      << error_of(m);
  m.prescribed_motions.back().dof = 7, m.prescribed_motions.back().vad = 3;
  EXPECT_NE(error_of(m).find("VAD 3"), std::string::npos);
  m.prescribed_motions.back().vad = 0, m.prescribed_motions.back().id = 5;
  EXPECT_NE(error_of(m).find("PID 5: not a rigid part"), std::string::npos);
  m.prescribed_motions.back().id = 1;
  auto& card = std::get<model::MatRigid>(m.materials[1].params);
  card.cmo = 1, card.con2 = 6;  // z and x rotations held: DOF 7 cannot be prescribed
  EXPECT_NE(error_of(m).find("DOF 7: part 1's *MAT_RIGID (CMO 1, CON2 6) holds that degree of freedom"),
            std::string::npos) << error_of(m);
  m.prescribed_motions.clear();
  card.cmo = -1;
  EXPECT_NE(error_of(m).find("CMO -1"), std::string::npos);
}

TEST(RigidBodies, PrescribedMotionAlongAVector) {
  // DOF 8 turns a cube at 2 rad/s about the *DEFINE_VECTOR (1, 1, 0) (tail (1, 1, 1), head
  // (2, 2, 1)) through its centre, and DOF 4 with VAD 2 moves its centre 3 mm along (0, 3, 4) / 5 by
  // t = T: after T the centre is 3 mm along that direction (the motion normal to it is free and
  // nothing pushes it), and a corner r0 is at x_c + R r0 with R the rotation by 2 T about the axis
  // (Rodrigues' formula). A cube, whose lumped inertia is isotropic: about an axis that is not
  // principal the free rotation normal to it would wobble, as it should.
  log::set_quiet(true);
  const Real T = 0.01;
  model::Model m = rigid_brick(Vec3(0.1, 0.1, 0.1), {2, 2, 2}, T, 1e-5);
  m.vectors[3] = model::Vector{3, Vec3(1, 1, 1), Vec3(2, 2, 1), 0, {}};
  m.vectors[4] = model::Vector{4, Vec3::Zero(), Vec3(0, 3, 4), 0, {}};
  model::Curve spin, plunge;
  spin.id = 1, spin.points = {{0.0, 2.0}, {1.0, 2.0}};
  plunge.id = 2, plunge.points = {{0.0, 0.0}, {T, 0.003}, {1.0, 0.003}};
  m.curves[1] = spin, m.curves[2] = plunge;
  m.prescribed_motions.push_back({model::Target::part, 1, 8, 0, 1, 1.0, 3, 1e28, 0, {}});
  m.prescribed_motions.push_back({model::Target::part, 1, 4, 2, 2, 1.0, 4, 1e28, 0, {}});
  solver::Problem p = solver::build_problem(m);
  const Vec3 corner0 = p.nodes.x[0];
  solver::run(p, solver::Observer{});
  const rigid::RigidBody& body = p.rigid_bodies.bodies().at(0);
  EXPECT_NEAR((body.centre - 0.003 * Vec3(0, 0.6, 0.8)).norm(), 0.0, 1e-12);
  const Vec3 axis = Vec3(1, 1, 0).normalized();
  const Vec3 expected = body.centre + rigid::rotation_of(2.0 * T * axis) * corner0;
  EXPECT_NEAR((p.nodes.x[0] - expected).norm(), 0.0, 1e-9) << p.nodes.x[0].transpose() << " vs "
                                                           << expected.transpose();
}

TEST(RigidBodies, CmoMinusOneHoldsAlongItsSystemsAxes) {
  // A cube (its lumped inertia isotropic, so a free spin keeps its axis) with *MAT_RIGID CMO -1,
  // CON1 a system whose x axis is (1, 1, 0) / sqrt 2 and y (-1, 1, 0) / sqrt 2, CON2 100010: the
  // translation along local x and the rotation about local y held. Under a base acceleration g
  // along global x (a force -m g x) the centre moves in the plane normal to local x,
  // v = -g t (x - (x . e) e) = -g t (1/2, -1/2, 0); a spin of 1 rad/s about global x keeps only its
  // component about local x, (x . e) e = (1/2, 1/2, 0) rad/s.
  log::set_quiet(true);
  const Real T = 1e-3, g = 9.81;
  model::Model m = rigid_brick(Vec3(0.1, 0.1, 0.1), {2, 2, 2}, T, 1e-5);
  model::CoordinateSystem system;
  system.id = 5, system.keyword = "*DEFINE_COORDINATE_VECTOR";
  system.axis = Vec3(1, 1, 0), system.in_plane = Vec3(-1, 1, 0);
  m.coordinate_systems[5] = system;
  auto& card = std::get<model::MatRigid>(m.materials[1].params);
  card.cmo = -1, card.con1 = 5, card.con2 = 100010;
  model::Curve one;
  one.id = 1, one.points = {{0.0, 1.0}, {1.0, 1.0}};
  m.curves[1] = one;
  m.body_loads.push_back({0, 1, g, 0, Vec3::Zero(), 0, {}});
  model::InitialVelocityGeneration spin;
  spin.id = 1, spin.styp = 2, spin.omega = 1.0, spin.axis = Vec3(1, 0, 0);
  m.initial_velocity_generations.push_back(spin);
  solver::Problem p = solver::build_problem(m);
  solver::run(p, solver::Observer{});
  const rigid::RigidBody& body = p.rigid_bodies.bodies().at(0);
  EXPECT_NEAR((body.velocity - (-g * T) * Vec3(0.5, -0.5, 0)).norm(), 0.0, 1e-12 * g * T) << body.velocity.transpose();
  EXPECT_NEAR((body.angular_velocity - Vec3(0.5, 0.5, 0)).norm(), 0.0, 1e-12) << body.angular_velocity.transpose();
}

TEST(RigidBodies, HistoryRowsAtTheRbdoutInterval) {
  // *DATABASE_RBDOUT DT: rbdout.csv rows at t = 0, DT, 2 DT ... and at the end (docs/OUTPUT.md),
  // whatever the GLSTAT interval; without the card, GLSTAT's interval.
  log::set_quiet(true);
  for (const bool card : {true, false}) {
    model::Model m = rigid_brick(Vec3(0.3, 0.2, 0.1), {3, 2, 1}, 1.0, 1e-3);
    if (card) m.rbdout = model::OutputInterval{0.25, 0, 0, 0, 1, {}};
    m.glstat = model::OutputInterval{0.1, 0, 0, 0, 1, {}};
    solver::Problem p = solver::build_problem(m);
    std::vector<Real> times;
    solver::Observer observer;
    observer.on_rigid_bodies = [&](const solver::StepInfo& step, const rigid::RigidBodies& bodies) {
      EXPECT_EQ(bodies.bodies().size(), 1u);
      times.push_back(step.time);
    };
    solver::run(p, observer);
    const std::vector<Real> expected = card ? std::vector<Real>{0, 0.25, 0.5, 0.75, 1.0}
                                            : std::vector<Real>{0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9, 1.0};
    ASSERT_EQ(times.size(), expected.size()) << (card ? "RBDOUT" : "GLSTAT");
    for (std::size_t k = 0; k < times.size(); ++k) EXPECT_NEAR(times[k], expected[k], 1e-9);
  }
}
