// A block launched along a rigid plane under gravity, in penalty contact with Coulomb friction
// (issue 33; fem-contact.md §2.6-2.8): friction decelerates it at mu g, so its centre stops after
// v0^2 / (2 mu g) (a particle sliding on a rough plane: any mechanics text, e.g. Meriam & Kraige,
// Dynamics, §3/4); without friction it keeps its speed. The block is FEM hexahedra, SPG particles
// or SPH particles: the slave nodes of *CONTACT_AUTOMATIC_NODES_TO_SURFACE against the rigid
// plate's faces. Tolerances: 3 % on the distance, 0.5 % on the frictionless speed (issue 33).
#include <gtest/gtest.h>

#include <cmath>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "support/contact_decks.hpp"

using namespace spall;
using namespace spall::test_support;

namespace {

constexpr Real gravity = 9.81, speed = 1.0;
constexpr Real spacing = 0.01;                   // m: the block's element size or particle spacing
constexpr Real density = 1000, young = 1e6;      // a soft block: a long stable step, a small sag

// The block (part 1, 0.1 x 0.1 x 0.04 m, its bottom on z = 0, moving along x at `speed`) on a fixed
// rigid plate (part 2, its top z = 0), with friction mu and 20 % normal damping.
std::string sliding_deck(Body kind, Real mu, Real end_time) {
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)}) + "*DATABASE_GLSTAT\n" +
                     row({number(end_time / 50)});
  deck += deformable_part(kind, 1, density, young, 0.3);
  if (kind == Body::sph)
    deck += sph_lattice(1, Vec3(0, 0, 0), spacing, {11, 11, 5}, density, 1);
  else
    deck += hex_box(1, Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.04), {10, 10, 4}, 1, 1);
  deck += rigid_part(2, density, young, 0.3, true) +
          hex_box(2, Vec3(-0.1, -0.1, -0.02), Vec3(0.8, 0.3, 0.02), {8, 3, 1}, 10001, 10001);
  deck += "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID\n" + row({"1"}) + row({"1", "2", "3", "3"}) +
          row({number(mu), number(mu), "0.0", "0.0", "20.0"}) + row({});
  deck += "*DEFINE_CURVE\n" + row({"1"}) + row({"0.0", "1.0"}, {20, 20}) + row({"10.0", "1.0"}, {20, 20});
  deck += "*LOAD_BODY_Z\n" + row({"1", number(gravity)});
  deck += "*INITIAL_VELOCITY_GENERATION\n" + row({"1", "2", "0.0", number(speed)}) + row({});
  return deck + "*END\n";
}

struct Slide {
  Real distance = 0;      // of the block's centre of mass along x
  Real velocity = 0;      // of the block along x at the end
  Real friction_energy = 0, kinetic0 = 0, ratio = 0;
  Real lowest = 0;        // the lowest block node's z at the end
};

Slide slide(Body kind, Real mu, Real end_time) {
  log::set_quiet(true);
  test::DeckFolder folder;
  const model::Model model = io::keyword::read_deck(folder.write("slide.k", sliding_deck(kind, mu, end_time)));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  const auto& nodes = problem.nodes;
  auto centre = [&] {
    Real m = 0;
    Vec3 x = Vec3::Zero(), v = Vec3::Zero();
    for (Index i = 0; i < nodes.size(); ++i)
      if (problem.nodes.part[i] == 1) m += nodes.mass[i], x += nodes.mass[i] * nodes.x[i], v += nodes.mass[i] * nodes.v[i];
    return std::pair{x / m, v / m};
  };
  const Real x0 = centre().first.x();
  Slide s;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo& step, const discretization::EnergyLedger& e) {
    if (step.step == 0) s.kinetic0 = e.kinetic();
    s.friction_energy = e.value(contact::PenaltyContact::friction_energy);
    s.ratio = e.ratio();
  };
  solver::run(problem, observer);
  const auto [x, v] = centre();
  s.distance = x.x() - x0;
  s.velocity = v.x();
  s.lowest = 1;
  for (Index i = 0; i < nodes.size(); ++i)
    if (problem.nodes.part[i] == 1) s.lowest = std::min(s.lowest, nodes.x[i].z());
  return s;
}

class SlidingBlock : public ::testing::TestWithParam<Body> {};

TEST_P(SlidingBlock, StopsAfterVSquaredOverTwoMuG) {
  const Real mu = 0.3;
  const Real expected = speed * speed / (2 * mu * gravity);  // 0.170 m, after v0 / (mu g) = 0.34 s
  const Slide s = slide(GetParam(), mu, 0.45);
  EXPECT_NEAR(s.distance / expected, 1.0, 0.03) << body_name(GetParam()) << ": " << s.distance << " m";
  EXPECT_NEAR(s.velocity, 0.0, 0.01 * speed);
  // Friction took the kinetic energy (the block's sag and the damping of its bounce, a little).
  EXPECT_NEAR(s.friction_energy / s.kinetic0, 1.0, 0.03);
  EXPECT_NEAR(s.ratio, 1.0, 0.01);
  EXPECT_GT(s.lowest, -0.2 * 0.02);  // no node further into the plate than its release depth
}

TEST_P(SlidingBlock, KeepsItsSpeedWithoutFriction) {
  const Slide s = slide(GetParam(), 0.0, 0.2);
  EXPECT_NEAR(s.velocity / speed, 1.0, 0.005) << body_name(GetParam());
  EXPECT_NEAR(s.distance / (0.2 * speed), 1.0, 0.005);
}

INSTANTIATE_TEST_SUITE_P(Bodies, SlidingBlock, ::testing::Values(Body::fem, Body::spg, Body::sph),
                         [](const auto& info) { return std::string(body_name(info.param)); });

}  // namespace
