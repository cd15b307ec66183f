// *PART_INERTIA (issue 33: a rigid body's "mass, centre of mass and inertia tensor from the elements
// (or *PART_INERTIA)"; fem-contact.md §1.5): the card's TM, centre and tensor replace the elements'.
//  - A brick of hexahedra given the inertia of a symmetric top, A = B = 0.1, C = 0.15 kg m^2 about
//    axes turned 30 degrees from the world's (IRCS 1), spun with VRX..VRZ off its symmetry axis,
//    precesses regularly: its symmetry axis turns about the fixed angular momentum L at |L| / A
//    (Landau & Lifshitz, Mechanics §33). The brick's own (lumped) inertia would give another rate.
//    Over 10^4 steps the angle turned matches |L| T / A to 1e-4, and L and the kinetic energy
//    1/2 omega . J omega (the ledger's) stay within 1e-6.
//  - The nodes carry the mass TM with its centre at XC YC ZC: a body load acts on TM at the centre.
//  - What Spall cannot run is refused at the card.
#include <gtest/gtest.h>

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

const Real angle = std::numbers::pi / 6;  // the local axes: the world's turned 30 degrees about x
const Vec3 local_x(1, 0, 0), local_y(0, std::cos(angle), std::sin(angle));

// A 0.3 x 0.2 x 0.1 m brick of 3 x 2 x 1 hexahedra of steel (part 1, centred at the origin) with a
// *PART_INERTIA of mass `tm`, centre `centre`, the symmetric top's tensor in the turned axes and
// the angular velocity `omega` (world axes), card 6 the axes unless `card6` is given; LCTM holds the
// step at 1e-5 s.
std::string top_deck(Real tm, const Vec3& centre, const Vec3& omega, Real end_time, const std::string& extra = "",
                     const std::string& card6 = "") {
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)}) + "*CONTROL_TIMESTEP\n" +
                     row({"", "", "", "", "", "9"}) + "*DEFINE_CURVE\n" + row({"9"}) +
                     row({"0.0", "1e-5"}, {20, 20}) + row({"100.0", "1e-5"}, {20, 20});
  deck += "*PART_INERTIA\ntop\n" + row({"1", "1", "1"}) +
          row({number(centre.x()), number(centre.y()), number(centre.z()), number(tm), "1"}) +
          row({"0.1", "0.0", "0.0", "0.1", "0.0", "0.15"}) +
          row({"0.0", "0.0", "0.0", number(omega.x()), number(omega.y()), number(omega.z())}) +
          (card6.empty() ? row({number(local_x.x()), number(local_x.y()), number(local_x.z()), number(local_y.x()),
                                number(local_y.y()), number(local_y.z())})
                         : card6);
  deck += "*SECTION_SOLID\n" + row({"1", "1"}) + "*MAT_RIGID\n" + row({"1", "7850", "2e11", "0.3"}) + row({});
  deck += hex_box(1, Vec3(-0.15, -0.1, -0.05), Vec3(0.3, 0.2, 0.1), {3, 2, 1}, 1, 1);
  return deck + extra + "*END\n";
}

TEST(PartInertia, SymmetricTopPrecessesAboutItsAngularMomentumAtLOverA) {
  log::set_quiet(true);
  const Real T = 0.1, A = 0.1, C = 0.15;
  // omega = 1 rad/s along the local x axis and 5 along the local z (the symmetry) axis.
  const Vec3 local_z = local_x.cross(local_y);
  const Vec3 omega0 = 1.0 * local_x + 5.0 * local_z;
  test::DeckFolder folder;
  const model::Model model = io::keyword::read_deck(folder.write("top.k", top_deck(10, Vec3::Zero(), omega0, T)));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  const rigid::RigidBody& body = problem.rigid_bodies.bodies().at(0);
  EXPECT_NEAR(body.mass, 10.0, 1e-12);
  const Vec3 L0 = A * 1.0 * local_x + C * 5.0 * local_z;
  // The deck's axes and angular velocity have nine digits.
  EXPECT_NEAR((body.angular_momentum - L0).norm() / L0.norm(), 0.0, 1e-8);
  Real kinetic0 = 0, kinetic = 0;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo& step, const discretization::EnergyLedger& e) {
    (step.step == 0 ? kinetic0 : kinetic) = e.kinetic();
  };
  solver::run(problem, observer);
  EXPECT_NEAR(kinetic0 / (0.5 * (A * 1.0 + C * 25.0)), 1.0, 1e-6);  // 1/2 omega . J omega
  EXPECT_NEAR(kinetic / kinetic0, 1.0, 1e-6);
  EXPECT_NEAR((body.angular_momentum - L0).norm() / L0.norm(), 0.0, 1e-6);
  // The symmetry axis, projected on the plane normal to L, turned by |L| T / A.
  const Vec3 n = L0.normalized();
  const Vec3 turned_z = body.rotation * local_z;
  const Vec3 axis0 = local_z - local_z.dot(n) * n, axis = turned_z - turned_z.dot(n) * n;
  const Real turned = std::atan2(n.dot(axis0.cross(axis)), axis0.dot(axis));
  std::printf("symmetric top: turned %.6f rad, |L| T / A = %.6f; kinetic energy %.9f of the start, L within %.2g\n",
              turned, L0.norm() * T / A, kinetic / kinetic0, (body.angular_momentum - L0).norm() / L0.norm());
  EXPECT_NEAR(turned / (L0.norm() * T / A), 1.0, 1e-4) << turned << " rad";
}

TEST(PartInertia, NodesCarryTheMassWithItsCentre) {
  log::set_quiet(true);
  test::DeckFolder folder;
  const Vec3 centre(0.02, -0.01, 0.005);
  const model::Model model =
      io::keyword::read_deck(folder.write("top.k", top_deck(4.5, centre, Vec3::Zero(), 1e-3)));
  solver::Problem problem = solver::build_problem(model);
  Real m = 0;
  Vec3 first = Vec3::Zero();
  for (Index i = 0; i < problem.nodes.size(); ++i)
    m += problem.nodes.mass[i], first += problem.nodes.mass[i] * problem.nodes.x[i];
  EXPECT_NEAR(m, 4.5, 1e-12);
  EXPECT_NEAR((first / m - centre).norm(), 0.0, 1e-12);
  EXPECT_NEAR((problem.rigid_bodies.bodies().at(0).centre - centre).norm(), 0.0, 1e-15);
}

TEST(PartInertia, LocalAxesFromACoordinateSystem) {
  // IRCS 1 with CID: the axes of a *DEFINE_COORDINATE_VECTOR instead of XL..ZLIP give the same tensor.
  log::set_quiet(true);
  test::DeckFolder folder;
  const auto inertia_of = [&](const std::string& deck) {
    const model::Model model = io::keyword::read_deck(folder.write("top.k", deck));
    return solver::build_problem(model).rigid_bodies.bodies().at(0).inertia;
  };
  const Mat3 by_vectors = inertia_of(top_deck(10, Vec3::Zero(), Vec3::Zero(), 1e-3));
  const std::string system =
      "*DEFINE_COORDINATE_VECTOR\n" + row({"5", number(local_x.x()), number(local_x.y()), number(local_x.z()),
                                           number(local_y.x()), number(local_y.y()), number(local_y.z())});
  const Mat3 by_system =
      inertia_of(top_deck(10, Vec3::Zero(), Vec3::Zero(), 1e-3, system, row({"", "", "", "", "", "", "5"})));
  EXPECT_NEAR((by_system - by_vectors).norm() / by_vectors.norm(), 0.0, 1e-12);
  EXPECT_GT((by_vectors - Mat3(Vec3(0.1, 0.1, 0.15).asDiagonal())).norm(), 0.01);  // turned: not the global axes
}

TEST(PartInertia, WhatSpallCannotRunIsRefused) {
  log::set_quiet(true);
  test::DeckFolder folder;
  const auto message = [&](const std::string& deck) {
    return test::input_error_of([&] {
      const model::Model model = io::keyword::read_deck(folder.write("bad.k", deck));
      io::keyword::validate(model);
      solver::build_problem(model);
    });
  };
  const std::string where = (folder.path() / "bad.k").lexically_normal().string() + ":";
  // The centre 1 m off a 0.3 m brick: its nodes cannot carry it there with positive masses.
  EXPECT_EQ(message(top_deck(10, Vec3(1.0, 0, 0), Vec3::Zero(), 1e-3)),
            where + "13: *PART_INERTIA: XC YC ZC (1, 0, 0): the part's nodes cannot carry the mass TM 10 with its "
                    "centre there (a centre outside the part's elements, or off the plane of a flat part)");
  std::string deck = top_deck(10, Vec3::Zero(), Vec3::Zero(), 1e-3);
  const std::string top = row({"0.1", "0.0", "0.0", "0.1", "0.0", "0.15"});
  deck.replace(deck.find(top), top.size(), row({"0.1", "0.0", "0.0", "0.1", "0.0", "0.5"}));
  EXPECT_EQ(message(deck), where + "13: *PART_INERTIA: IXX..IZZ: principal moments 0.1 0.1 0.5: an inertia "
                                   "tensor's are positive and each at most the sum of the other two");
  deck = top_deck(10, Vec3::Zero(), Vec3::Zero(), 1e-3);
  deck.replace(deck.find("*MAT_RIGID"), 10, "*MAT_ELASTIC");
  EXPECT_EQ(message(deck), where + "13: *PART_INERTIA: part 1: material 1 is not *MAT_RIGID: Spall takes given mass "
                                   "properties for rigid bodies only");
}

}  // namespace
