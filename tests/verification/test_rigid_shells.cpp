// Rigid bodies meshed with shells (issue 33: "*MAT_RIGID parts meshed with solids or shells"):
// *SECTION_SHELL and *ELEMENT_SHELL give a rigid part its mass (RO t A + MAREA A) and its contact
// surface (fem-contact.md §1.3, §1.6-1.7; docs/THEORY.md §11-12).
//  - A thin-walled cube of side a: mass RO t 6 a^2 (exact for flat shells), inertia 5/18 m a^2
//    about its centre (each face's integral of r^2 dm; any table of moments of inertia, e.g.
//    Meriam & Kraige, Dynamics, Appendix D, summed over the six faces), to 1 % on a 12 x 12 mesh of
//    each face (the lumped nodal masses integrate r^2 with the trapezoid rule: an O(h^2) error).
//  - A block sliding on a rigid shell plate stops after v0^2 / (2 mu g), to 3 % (issue 33's bound).
//  - An elastic block launched at a rigid shell plate rebounds at its impact speed (St-Venant's
//    free rod on a rigid wall: the whole momentum is returned in 2 L / c; Goldsmith, Impact, 1960,
//    §3.4), to 10 %: the automatic contact meets the shell from either side at half its thickness
//    off the mid-surface; the old node-to-surface type on its normal's side, at the mid-surface.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/field_output.hpp"
#include "spall/solver/simulation.hpp"
#include "support/contact_decks.hpp"

using namespace spall;
using namespace spall::test_support;

namespace {

// The problem of `deck`, over `model` (which it points into: the caller keeps it).
solver::Problem build(const std::string& deck, test::DeckFolder& folder, model::Model& model) {
  log::set_quiet(true);
  model = io::keyword::read_deck(folder.write("shells.k", deck));
  io::keyword::validate(model);
  return solver::build_problem(model);
}

// The surface of the cube [0, a]^3 as n x n quadrilaterals a face (part 1), node (i, j, k) of the
// (n + 1)^3 lattice numbered 1 + i + (n + 1) (j + (n + 1) k), only those on the surface written.
std::string cube_surface(Real a, int n) {
  const auto id = [&](int i, int j, int k) { return 1 + i + (n + 1) * (j + (n + 1) * k); };
  std::string deck = "*NODE\n";
  for (int k = 0; k <= n; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i)
        if (i == 0 || j == 0 || k == 0 || i == n || j == n || k == n)
          deck += row({std::to_string(id(i, j, k)), coordinate(a * i / n), coordinate(a * j / n),
                       coordinate(a * k / n)},
                      {8, 16, 16, 16});
  deck += "*ELEMENT_SHELL\n";
  int eid = 1;
  for (int d = 0; d < 3; ++d)
    for (int side : {0, n})
      for (int v = 0; v < n; ++v)
        for (int u = 0; u < n; ++u) {
          // Lattice point (u, v) of the face normal to axis d at index `side`.
          const auto corner = [&](int du, int dv) {
            std::array<int, 3> p;
            p[d] = side, p[(d + 1) % 3] = u + du, p[(d + 2) % 3] = v + dv;
            return std::to_string(id(p[0], p[1], p[2]));
          };
          deck += row({std::to_string(eid++), "1", corner(0, 0), corner(1, 0), corner(1, 1), corner(0, 1)},
                      {8, 8, 8, 8, 8, 8});
        }
  return deck;
}

TEST(RigidShells, ThinWalledCubeHasItsMassAndInertia) {
  const Real a = 0.2, t = 0.002, density = 7800, marea = 1.5;
  const int n = 12;
  test::DeckFolder folder;
  const std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"1e-3"}) +
                           rigid_shell_part(1, density, 2e11, 0.3, t, false, marea) + cube_surface(a, n) + "*END\n";
  model::Model model;
  const solver::Problem problem = build(deck, folder, model);
  ASSERT_EQ(problem.rigid_bodies.bodies().size(), 1u);
  const rigid::RigidBody& body = problem.rigid_bodies.bodies()[0];
  const Real mass = (density * t + marea) * 6 * a * a;
  EXPECT_NEAR(body.mass / mass, 1.0, 1e-12);
  EXPECT_NEAR((body.centre - Vec3::Constant(a / 2)).norm(), 0.0, 1e-12 * a);
  std::printf("thin-walled cube: mass %.15f of RO t A, inertia %.5f %.5f %.5f of 5/18 m a^2\n", body.mass / mass,
              body.inertia(0, 0) / (5.0 / 18 * mass * a * a), body.inertia(1, 1) / (5.0 / 18 * mass * a * a),
              body.inertia(2, 2) / (5.0 / 18 * mass * a * a));
  for (int d = 0; d < 3; ++d) {
    EXPECT_NEAR(body.inertia(d, d) / (5.0 / 18 * mass * a * a), 1.0, 0.01) << "axis " << d;
    EXPECT_NEAR(body.inertia(d, (d + 1) % 3) / (mass * a * a), 0.0, 1e-12);
  }

  // The field output draws the shells: one quadrilateral cell per element, with its ID.
  const auto snapshot = solver::snapshot_fields(problem);
  const auto quads = std::find_if(snapshot.cell_blocks.begin(), snapshot.cell_blocks.end(), [](const auto& b) {
    return b.shape == discretization::CellShape::quadrilateral;
  });
  ASSERT_NE(quads, snapshot.cell_blocks.end());
  EXPECT_EQ(quads->cell_count(), std::size_t(6 * n * n));
  const auto& ids = std::get<std::vector<std::int64_t>>(quads->fields.at(0).values);
  EXPECT_EQ(quads->fields.at(0).name, "element_id");
  EXPECT_EQ(ids.front(), 1);
  EXPECT_EQ(ids.back(), 6 * n * n);
}

TEST(RigidShells, ElementThicknessOverridesTheSection) {
  // One 1 x 2 quadrilateral of THIC 0.1 at every corner, in a section of T1 0.5: mass RO 0.1 * 2.
  test::DeckFolder folder;
  const std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"1e-3"}) +
                           rigid_shell_part(1, 1000, 2e11, 0.3, 0.5, false) + "*NODE\n" +
                           row({"1", "0", "0", "0"}, {8, 16, 16, 16}) + row({"2", "1", "0", "0"}, {8, 16, 16, 16}) +
                           row({"3", "1", "2", "0"}, {8, 16, 16, 16}) + row({"4", "0", "2", "0"}, {8, 16, 16, 16}) +
                           row({"5", "3", "0", "0"}, {8, 16, 16, 16}) + "*ELEMENT_SHELL_THICKNESS\n" +
                           row({"1", "1", "1", "2", "3", "4"}, {8, 8, 8, 8, 8, 8}) +
                           row({"0.1", "0.1", "0.1", "0.1"}, {16, 16, 16, 16}) +
                           // A triangle (N4 = N3) of the section's thickness: area 2 (legs 2 and 2).
                           row({"2", "1", "2", "5", "3", "3"}, {8, 8, 8, 8, 8, 8}) + row({}) + "*END\n";
  model::Model model;
  const solver::Problem problem = build(deck, folder, model);
  EXPECT_NEAR(problem.rigid_bodies.bodies().at(0).mass, 1000 * (0.1 * 2 + 0.5 * 2), 1e-9);
}

constexpr Real gravity = 9.81, speed = 1.0, density = 1000, young = 1e6;

// A 0.1 x 0.1 x 0.04 m block of hexahedra (part 1) on a fixed rigid plate of shells of thickness t
// (part 2) whose mid-surface is z = -t / 2: the automatic contact's surface is z = 0.
TEST(RigidShells, BlockSlidingOnAShellPlateStopsAfterVSquaredOverTwoMuG) {
  const Real mu = 0.3, t = 0.01, end_time = 0.45;
  const Real expected = speed * speed / (2 * mu * gravity);
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)});
  deck += deformable_part(Body::fem, 1, density, young, 0.3) +
          hex_box(1, Vec3(0, 0, 0), Vec3(0.1, 0.1, 0.04), {10, 10, 4}, 1, 1);
  deck += rigid_shell_part(2, density, young, 0.3, t, true) +
          shell_rectangle(2, Vec3(-0.1, -0.1, -t / 2), Vec3(0.8, 0, 0), Vec3(0, 0.3, 0), {8, 3}, 10001, 10001);
  deck += "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID\n" + row({"1"}) + row({"1", "2", "3", "3"}) +
          row({number(mu), number(mu), "0.0", "0.0", "20.0"}) + row({});
  deck += "*DEFINE_CURVE\n" + row({"1"}) + row({"0.0", "1.0"}, {20, 20}) + row({"10.0", "1.0"}, {20, 20});
  deck += "*LOAD_BODY_Z\n" + row({"1", number(gravity)});
  deck += "*INITIAL_VELOCITY_GENERATION\n" + row({"1", "2", "0.0", number(speed)}) + row({}) + "*END\n";
  test::DeckFolder folder;
  model::Model model;
  solver::Problem problem = build(deck, folder, model);
  const auto& nodes = problem.nodes;
  const auto centre_x = [&] {
    Real m = 0, x = 0;
    for (Index i = 0; i < nodes.size(); ++i)
      if (problem.nodes.part[i] == 1) m += nodes.mass[i], x += nodes.mass[i] * nodes.x[i].x();
    return x / m;
  };
  const Real x0 = centre_x();
  Real ratio = 0;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo&, const discretization::EnergyLedger& e) { ratio = e.ratio(); };
  solver::run(problem, observer);
  EXPECT_NEAR((centre_x() - x0) / expected, 1.0, 0.03);
  EXPECT_NEAR(ratio, 1.0, 0.01);
  Real lowest = 1;
  for (Index i = 0; i < nodes.size(); ++i)
    if (problem.nodes.part[i] == 1) lowest = std::min(lowest, nodes.x[i].z());
  std::printf("sliding on shells: %.5f m (%.5f of v0^2/(2 mu g)), lowest node %.3g t, energy ratio %.6f\n",
              centre_x() - x0, (centre_x() - x0) / expected, lowest / t, ratio);
  // On the offset surface z = 0 (the weight presses it in by m g / k, far below 0.1 t), not on the
  // mid-surface -t / 2.
  EXPECT_GT(lowest, -0.1 * t);
  EXPECT_LT(lowest, 0.1 * t);
}

struct Rebound {
  Real velocity = 0;  // of the block's centre along z at the end
  Real highest = 0;   // the highest z any block node reached
  Real ratio = 0;
};

// The block (5 x 5 x 2 hexahedra, 0.1 x 0.1 x 0.04 m, top at z = 0) launched up at 0.3 m/s at a
// fixed plate of shells (thickness t, mid-surface z = gap), no gravity, no friction, no damping. The
// penalty spring of a top node (SLSFAC K V^(1/3), 830 N/m, on 4 g) stops it within 0.3 m/s / 455
// rad/s = 0.7 mm, less than the release depth of a 6 mm shell (2.4 mm): at 1 m/s a thin shell lets
// this soft block through, as it would in LS-DYNA (SOFT 1 or a larger SFS is the users' remedy).
constexpr Real launch = 0.3;
Rebound rebound(const std::string& contact, bool normal_up, Real t, Real gap) {
  const Real end_time = 0.03;  // 2 mm to the surface in 7 ms, half the spring's period (7 ms) on it, and back
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)});
  deck += deformable_part(Body::fem, 1, density, young, 0.3) +
          hex_box(1, Vec3(0, 0, -0.04), Vec3(0.1, 0.1, 0.04), {5, 5, 2}, 1, 1);
  // e1 x e2 is the shells' normal.
  const Vec3 e1(0.3, 0, 0), e2(0, 0.3, 0);
  deck += rigid_shell_part(2, density, young, 0.3, t, true) +
          (normal_up ? shell_rectangle(2, Vec3(-0.1, -0.1, gap), e1, e2, {6, 6}, 10001, 10001)
                     : shell_rectangle(2, Vec3(-0.1, -0.1, gap), e2, e1, {6, 6}, 10001, 10001));
  deck += contact + "\n" + row({"1", "2", "3", "3"}) + row({}) + row({});
  deck += "*INITIAL_VELOCITY_GENERATION\n" + row({"1", "2", "0.0", "0.0", "0.0", number(launch)}) + row({}) + "*END\n";
  test::DeckFolder folder;
  model::Model model;
  solver::Problem problem = build(deck, folder, model);
  const auto& nodes = problem.nodes;
  Rebound r;
  r.highest = -1;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo&, const discretization::EnergyLedger& e) { r.ratio = e.ratio(); };
  observer.on_step = [&](const solver::StepInfo&) {
    for (Index i = 0; i < nodes.size(); ++i)
      if (problem.nodes.part[i] == 1) r.highest = std::max(r.highest, nodes.x[i].z());
  };
  solver::run(problem, observer);
  Real m = 0, p = 0;
  for (Index i = 0; i < nodes.size(); ++i)
    if (problem.nodes.part[i] == 1) m += nodes.mass[i], p += nodes.mass[i] * nodes.v[i].z();
  r.velocity = p / m;
  return r;
}

TEST(RigidShells, AutomaticContactMeetsAShellFromEitherSideAtHalfItsThickness) {
  const Real t = 0.006, gap = t / 2 + 0.002;
  for (bool normal_up : {true, false}) {
    const Rebound r = rebound("*CONTACT_AUTOMATIC_NODES_TO_SURFACE", normal_up, t, gap);
    std::printf("automatic, normal %s: rebound %.4f v0, turned %.3f t from the offset surface, energy ratio %.6f\n",
                normal_up ? "up" : "down", r.velocity / launch, (r.highest - (gap - t / 2)) / t, r.ratio);
    EXPECT_NEAR(r.velocity / launch, -1.0, 0.1) << (normal_up ? "normal up" : "normal down");
    EXPECT_NEAR(r.ratio, 1.0, 0.01);
    // It turned on the surface t / 2 below the mid-surface: it reached it (to 0.1 t) and went no
    // deeper than the release depth (PENMAX 0.4 t).
    EXPECT_GT(r.highest, gap - t / 2 - 0.1 * t);
    EXPECT_LT(r.highest, gap - t / 2 + 0.4 * t);
  }
}

TEST(RigidShells, OldNodesToSurfaceMeetsTheShellOnItsNormalsSideAtTheMidSurface) {
  const Real t = 0.006, gap = 0.002;
  const Rebound r = rebound("*CONTACT_NODES_TO_SURFACE", false, t, gap);
  std::printf("old type: rebound %.4f v0, turned %.3f t from the mid-surface, energy ratio %.6f\n", r.velocity / launch,
              (r.highest - gap) / t, r.ratio);
  EXPECT_NEAR(r.velocity / launch, -1.0, 0.1);
  EXPECT_NEAR(r.ratio, 1.0, 0.01);
  EXPECT_GT(r.highest, gap - 0.1 * t);
  EXPECT_LT(r.highest, gap + 0.4 * t);
}

}  // namespace
