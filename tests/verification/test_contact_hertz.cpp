// An elastic sphere dropped on a fixed rigid plane, in penalty contact
// (*CONTACT_AUTOMATIC_NODES_TO_SURFACE: the sphere's nodes are the slave nodes, the plate's faces the
// master segments; issue 33, fem-contact.md §2.6-2.8), against Hertz's theory of elastic impact
// (Johnson, Contact Mechanics, Cambridge University Press 1985, §11.4; Goldsmith, Impact, Arnold
// 1960): a sphere of mass m and radius R that meets a rigid plane at speed v0 is compressed by at
// most d* = (15 m v0^2 / (16 E* R^(1/2)))^(2/5) and stays in contact for
//     t_c = 2.94 d* / v0 = 2.868 (m^2 / (R E*^2 v0))^(1/5),   E* = E / (1 - nu^2) (the plane rigid).
// Checked: t_c within 10 %; glstat's energy ratio within 1 % of 1 at every output through
// the bounce; the rebound speed of the sphere's centre of mass at least 0.9 v0 and at most v0 (see
// the test for why).
//
// Why a finite-element sphere: Hertz's law comes from a contact circle that grows smoothly from a
// point, a = (R d)^(1/2). A lattice of SPH particles cut to a sphere meets the plane with a flat
// facet of particles (24 of them at 16 particles across): a flat punch, stiffer than Hertz from the
// first touch (measured t_c = 0.52-0.62 of Hertz's at that resolution). The hexahedra here have their
// surface nodes on the sphere and a node at the pole, so the touching nodes come in rings (1, 5, 9,
// 13, 21 at the peak) as the contact circle grows. ELFORM 2 (selective-reduced, no hourglass control
// to take energy).
//
// The resolution: 16 hexahedra across, 0.1 R at the pole. v0 = 1 m/s gives d* = 0.042 R and a = 0.2
// R: the contact circle spans two rings of nodes. v0 / c = 0.01 and t_c is about seven times the
// sphere's transit time 2R / c: the quasi-static loading Hertz's impact theory assumes. The model's
// t_c is 4.2 % short of Hertz's; 4.4 % with 24 hexahedra across and 4.9 % with a penalty three
// times stiffer (TSSFAC 0.3), so neither the mesh nor the penalty makes it. The shortfall grows with
// a / R (1 % at v0 = 0.5 m/s, 7 % at v0 = 2 m/s), consistent with the error O(a / R) of the
// half-space idealisation: Hertz's approach d includes the half-space's displacement below the
// depth R, which the sphere does not have, so the sphere is a little stiffer than Hertz's law.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numbers>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "support/contact_decks.hpp"

using namespace spall;
using namespace spall::test_support;

namespace {

constexpr Real radius = 0.05;                               // m
constexpr Real density = 1000, young = 1e7, poisson = 0.3;  // a soft sphere: a long stable step
constexpr Real speed = 1.0;                                 // m/s, v0
constexpr Real gap = 0.0005;                                // m between the pole and the plane at t = 0
constexpr int across = 16;                                  // hexahedra across the sphere
// The penalty scale SFSA of the sphere's nodes: k = SLSFAC SFSA K V^(1/3) = 10 K V^(1/3) per node
// (SLSFAC 0.1 by default, K the bulk modulus, V = m / rho the node's volume), ten times the
// material's own stiffness K h. The 21 nodes touching at the peak then hold about 30 times Hertz's
// tangent stiffness there, 2 E* a = 2.2e5 N/m: the springs add about 3 % to the compliance and about
// 1 % to t_c. (The default SFSA 1 is 100 times softer: t_c came out 1.6 times Hertz's.) The rigid
// plate's segments (steel) are far stiffer, so PENOPT 1 takes the node's.
constexpr Real penalty_scale = 100;
// The step: the pole node's penalty frequency omega = sqrt(k / m) is about 7e4 /s; TSSFAC 0.6 keeps
// omega dt near 0.9, well below the central difference's limit 2 (TSSFAC 0.9 with SFSA 300 blew up,
// as omega dt = 2.3 there says). The test checks omega dt < 1.2.
constexpr Real tssfac = 0.6;
constexpr Real end_time = 0.0085;  // s: the approach gap / v0 = 0.5 ms, t_c = 6.2 ms, then the flight away

// The sphere (part 1, its pole `gap` above z = 0, moving down at v0) over a fixed rigid plate
// (part 2, its top z = 0, 2R x 2R), no gravity, no contact damping (VDC 0), no friction.
std::string hertz_deck() {
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)}) + "*CONTROL_TIMESTEP\n" +
                     row({"0.0", number(tssfac)}) + "*DATABASE_GLSTAT\n" + row({"1.0e-5"});
  deck += "*PART\nsphere\n" + row({"1", "1", "1"}) + "*SECTION_SOLID\n" + row({"1", "2"}) + "*MAT_ELASTIC\n" +
          row({"1", number(density), number(young), number(poisson)});
  deck += hex_ball(1, Vec3(0, 0, radius + gap), radius, across, 1, 1);
  deck += rigid_part(2, 7850, 2e11, 0.3, true) +
          hex_box(2, Vec3(-radius, -radius, -0.2 * radius), Vec3(2 * radius, 2 * radius, 0.2 * radius), {4, 4, 1},
                  100001, 100001);
  deck += "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID\n" + row({"1"}) + row({"1", "2", "3", "3"}) +
          row({"0.0", "0.0", "0.0", "0.0", "0.0"}) + row({number(penalty_scale), "1.0"});
  deck += "*INITIAL_VELOCITY_GENERATION\n" + row({"1", "2", "0.0", "0.0", "0.0", number(-speed)}) + row({});
  return deck + "*END\n";
}

TEST(HertzImpact, SphereOnRigidPlane) {
  log::set_quiet(true);
  test::DeckFolder folder;
  const model::Model model = io::keyword::read_deck(folder.write("hertz.k", hertz_deck()));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  const auto& nodes = problem.nodes;

  // The sphere's mass as meshed (its facets cut 0.4 % off the ball's), and its pole node.
  Real mass = 0;
  Index pole = 0;
  for (Index i = 0; i < nodes.size(); ++i)
    if (problem.nodes.part[i] == 1) {
      mass += nodes.mass[i];
      if (nodes.x[i].z() < nodes.x[pole].z() || problem.nodes.part[pole] != 1) pole = i;
    }
  const Real e_star = young / (1 - poisson * poisson);
  const Real hertz = 2.868 * std::pow(mass * mass / (radius * e_star * e_star * speed), 0.2);

  // Contact while side A (the sphere) feels a force, sampled at every step: it starts between the
  // last step without force and the first with, and ends between the last with and the next without.
  Real before = 0, first = -1, last = -1, after = -1, dt_in_contact = 0, ratio_low = 2, ratio_high = 0;
  long long steps_in_contact = 0;
  Index most_touching = 0;
  solver::Observer observer;
  observer.on_step = [&](const solver::StepInfo& step) {
    const auto& contact = problem.contacts[0];
    if (contact.side_a().force.norm() > 0) {
      if (first < 0) first = step.time;
      last = step.time;
      after = -1;
      ++steps_in_contact;
      dt_in_contact = step.dt;
      most_touching = std::max(most_touching, contact.touching());
    } else if (first < 0) {
      before = step.time;
    } else if (after < 0) {
      after = step.time;
    }
  };
  observer.on_history = [&](const solver::StepInfo&, const discretization::EnergyLedger& e) {
    ratio_low = std::min(ratio_low, e.ratio());
    ratio_high = std::max(ratio_high, e.ratio());
  };
  solver::run(problem, observer);

  ASSERT_GT(first, 0) << "the sphere never touched the plate";
  ASSERT_GT(after, last) << "the sphere had not left the plate by the end";
  const Real duration = 0.5 * (last + after) - 0.5 * (before + first);
  Vec3 momentum = Vec3::Zero();
  for (Index i = 0; i < nodes.size(); ++i)
    if (problem.nodes.part[i] == 1) momentum += nodes.mass[i] * nodes.v[i];
  const Real rebound = momentum.z() / mass / speed;
  const Real bulk_modulus = young / (3 * (1 - 2 * poisson));
  const Real pole_stiffness = 0.1 * penalty_scale * bulk_modulus * std::cbrt(nodes.mass[pole] / density);
  const Real omega_dt = std::sqrt(pole_stiffness / nodes.mass[pole]) * dt_in_contact;
  std::printf("contact %.4e s vs Hertz %.4e s (%+.2f %%) over %lld steps, up to %d nodes touching; energy ratio "
              "in [%.5f, %.5f]; rebound %.4f v0; pole omega dt %.2f\n",
              duration, hertz, 100 * (duration / hertz - 1), steps_in_contact, static_cast<int>(most_touching),
              ratio_low, ratio_high, rebound, omega_dt);

  // Hertz's contact time, within 10 %.
  EXPECT_NEAR(duration / hertz, 1.0, 0.10);
  // The contact resolved in time (at least 200 steps) and the penalty springs well inside their
  // stable range.
  EXPECT_GE(steps_in_contact, 200);
  EXPECT_LT(omega_dt, 1.2);
  // The energy balance closes through the bounce: the penalty springs' work is booked as
  // contact_energy, the bulk viscosity's as artificial_viscosity_energy; within 1 %.
  EXPECT_NEAR(ratio_low, 1.0, 0.01);
  EXPECT_NEAR(ratio_high, 1.0, 0.01);
  // The rebound: the sphere leaves with the kinetic energy of its centre of mass, less what stays in
  // its vibrations (the impact excites its modes; with t_c several times its transit time the
  // loading is nearly quasi-static, so little does) and what the bulk viscosity took. Energy
  // conservation bounds it above by v0 (sqrt(1.01) v0 with the ratio's 1 %); 0.9 v0 below leaves up
  // to 19 % of the energy in vibration and damping.
  EXPECT_GT(rebound, 0.9);
  EXPECT_LT(rebound, std::sqrt(1.01));
}

}  // namespace
