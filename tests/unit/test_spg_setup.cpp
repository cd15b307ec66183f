// SPG parts built from a solid mesh: nodal volumes and lumped masses from the elements (spg.md §6:
// M_I = rho_0 V_I), supports DX x nodal spacing, and every *SECTION_SOLID_SPG field the solver
// cannot run refused by name.
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "spall/solver/problem.hpp"
#include "spall/spg/formulation.hpp"
#include "spall/spg/nodal_volumes.hpp"
#include "spall/spg/setup.hpp"
#include "support/spg_block.hpp"

using namespace spall;

namespace {

spg::HexCorners unit_cube() {
  return {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0),
          Vec3(0, 0, 1), Vec3(1, 0, 1), Vec3(1, 1, 1), Vec3(0, 1, 1)};
}

// The message of the InputError that building the problem throws ("" if none).
std::string build_error(const model::Model& m) {
  try {
    solver::build_problem(m);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(SpgNodalVolumes, ParallelepipedGivesAnEighthToEachCorner) {
  // A sheared box: volume = |det [a b c]| = 2 * 3 * 4 (shear does not change it).
  spg::HexCorners x;
  const Vec3 a(2, 0, 0), b(0.5, 3, 0), c(0.3, -0.2, 4);
  const Vec3 o(1, 1, 1);
  x = {o, o + a, o + a + b, o + b, o + c, o + a + c, o + a + b + c, o + b + c};
  const auto v = spg::hex_volumes(x);
  EXPECT_NEAR(v.total, 24.0, 1e-12);
  for (Real corner : v.corner) EXPECT_NEAR(corner, 3.0, 1e-12);
  EXPECT_GT(v.min_jacobian, 0);
}

TEST(SpgNodalVolumes, DegenerateHexahedraHaveTheVolumeOfTheirShape) {
  // Wedge (prism over the triangle (0,0) (1,0) (0,1), height 1): N3 = N4, N7 = N8; volume 1/2.
  auto cube = unit_cube();
  spg::HexCorners wedge = cube;
  wedge[2] = cube[3];
  wedge[6] = cube[7];
  const auto w = spg::hex_volumes(wedge);
  EXPECT_NEAR(w.total, 0.5, 1e-12);
  // Tetrahedron in LS-DYNA's form N1 N2 N3 N4 N4 N4 N4 N4 with corners (0,0,0) (1,0,0) (0,1,0)
  // (0,0,1): volume 1/6, a quarter at each corner (the trilinear map of that node list would give
  // 1/12).
  spg::HexCorners tet;
  tet = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(0, 1, 0), Vec3(0, 0, 1),
         Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1), Vec3(0, 0, 1)};
  const auto t = spg::hex_volumes(tet);
  EXPECT_NEAR(t.total, 1.0 / 6, 1e-12);
  Real apex = 0;
  for (int a = 3; a < 8; ++a) apex += t.corner[a];
  EXPECT_NEAR(apex, 1.0 / 24, 1e-12);
  EXPECT_NEAR(t.corner[0], 1.0 / 24, 1e-12);
  // Pyramid N1..N4 base (unit square), N5 = ... = N8 apex at height 1: volume 1/3.
  spg::HexCorners pyramid = cube;
  for (int a = 4; a < 8; ++a) pyramid[a] = Vec3(0.5, 0.5, 1);
  EXPECT_NEAR(spg::hex_volumes(pyramid).total, 1.0 / 3, 1e-12);
  // A frustum of a square pyramid (base side 2, top side 1, height 1): the trilinear element is
  // exactly the frustum, of volume h/3 (A1 + A2 + sqrt(A1 A2)) = 7/3.
  const spg::HexCorners frustum = {Vec3(-1, -1, 0),     Vec3(1, -1, 0),    Vec3(1, 1, 0),
                                   Vec3(-1, 1, 0),      Vec3(-0.5, -0.5, 1), Vec3(0.5, -0.5, 1),
                                   Vec3(0.5, 0.5, 1),   Vec3(-0.5, 0.5, 1)};
  const auto f = spg::hex_volumes(frustum);
  EXPECT_NEAR(f.total, 7.0 / 3, 1e-12);
  Real sum = 0;
  for (Real c : f.corner) sum += c;
  EXPECT_NEAR(sum, f.total, 1e-12);
  EXPECT_GT(f.corner[0], f.corner[4]);  // the wide base carries more of the volume
}

TEST(SpgNodalVolumes, InvertedElementHasNegativeJacobian) {
  auto x = unit_cube();
  std::swap(x[0], x[4]);
  std::swap(x[1], x[5]);
  std::swap(x[2], x[6]);
  std::swap(x[3], x[7]);  // top and bottom exchanged: inside out
  EXPECT_LT(spg::hex_volumes(x).min_jacobian, 0);
}

TEST(SpgSetup, MassesAndSupportsFromTheMesh) {
  log::set_quiet(true);
  test_support::SpgBlock b;
  b.size = Vec3(0.4, 0.2, 0.3);
  b.elements = {4, 2, 3};  // h = 0.1 in every direction
  const model::Model m = test_support::spg_block_model(b);
  const solver::Problem p = solver::build_problem(m);
  ASSERT_EQ(p.formulations.size(), 1u);
  const auto& spg = dynamic_cast<const spg::SpgFormulation&>(*p.formulations[0]);
  EXPECT_STREQ(spg.name(), "SPG");
  EXPECT_EQ(spg.particle_count(), 5 * 3 * 4);
  Real total = 0;
  for (Index i = 0; i < p.nodes.size(); ++i) total += p.nodes.mass[i];
  EXPECT_NEAR(total, b.density * 0.4 * 0.2 * 0.3, 1e-9 * total);
  const Real element_mass = b.density * 1e-3;
  for (Index i = 0; i < p.nodes.size(); ++i) {
    const Vec3 x = p.nodes.x0[i];
    // Elements around a node: 2 per direction inside, 1 on a face.
    int count = 1;
    for (int d = 0; d < 3; ++d) {
      const bool on_face = std::abs(x[d]) < 1e-12 || std::abs(x[d] - b.size[d]) < 1e-12;
      count *= on_face ? 1 : 2;
    }
    EXPECT_NEAR(p.nodes.mass[i], count * element_mass / 8, 1e-12 * element_mass) << "node " << p.nodes.id[i];
    EXPECT_EQ(p.nodes.part[i], 1);
  }
  // Bonds of an interior particle: DX 1.6 with cubical support reaches the 26 lattice neighbours.
  const auto& part = spg.parts().front();
  Index max_bonds = 0;
  for (Index i = 0; i < part.particle_count(); ++i) max_bonds = std::max(max_bonds, part.bonds().count(i));
  EXPECT_EQ(max_bonds, 26);
}

TEST(SpgSetup, KernelDefaultsGoThroughToTheSolver) {
  log::set_quiet(true);
  test_support::SpgBlock b;
  b.elements = {4, 2, 2};
  b.size = Vec3(0.4, 0.2, 0.2);
  b.section.kernel = 2;
  b.section.itb = 2;
  b.section.smstep = 30;
  b.section.ispline = 2;
  b.section.dx = b.section.dy = b.section.dz = 1.5;
  const solver::Problem p = solver::build_problem(test_support::spg_block_model(b));
  const auto& settings = dynamic_cast<const spg::SpgFormulation&>(*p.formulations[0]).parts()[0].settings();
  EXPECT_EQ(settings.kernel_update, spg::KernelUpdate::pseudo_lagrangian);
  EXPECT_EQ(settings.stabilization, spg::Stabilization::simplified_fluid_particle);
  EXPECT_EQ(settings.update_interval, 30);
  EXPECT_EQ(settings.shape, spg::KernelShape::cubic_spherical);
  EXPECT_EQ(settings.dilation, Vec3::Constant(1.5));
}

TEST(SpgSetup, FieldsWithoutAnImplementationAreRefusedByName) {
  log::set_quiet(true);
  test_support::SpgBlock base;
  base.elements = {4, 2, 2};
  base.size = Vec3(0.4, 0.2, 0.2);
  ASSERT_EQ(build_error(test_support::spg_block_model(base)), "");
  struct Case {
    const char* field;
    void (*set)(model::SectionSolidSpg&);
  };
  const Case cases[] = {
      {"AET", [](model::SectionSolidSpg& s) { s.aet = 4; }},
      {"COHOFF", [](model::SectionSolidSpg& s) { s.cohoff = 0.5; }},
      {"GASKETT", [](model::SectionSolidSpg& s) { s.gaskett = 0.1; }},
      {"LSCALE", [](model::SectionSolidSpg& s) { s.lscale = 0.2; }},
      {"SWTIME", [](model::SectionSolidSpg& s) { s.column8 = 1e-3; }},
      {"ITB 3", [](model::SectionSolidSpg& s) { s.itb = 3; }},
      {"IDAM 5", [](model::SectionSolidSpg& s) { s.idam = 5; }},
      {"STRETCH", [](model::SectionSolidSpg& s) { s.stretch = 0.8; }},
      {"MSFAC", [](model::SectionSolidSpg& s) { s.msfac = 0.75; }},
      {"ISC", [](model::SectionSolidSpg& s) { s.isc = 1; }},
      {"BOXID", [](model::SectionSolidSpg& s) { s.boxid = 3; }},
      {"PDAMP", [](model::SectionSolidSpg& s) { s.pdamp = -0.01; }},
  };
  for (const auto& c : cases) {
    test_support::SpgBlock b = base;
    c.set(b.section);
    const std::string message = build_error(test_support::spg_block_model(b));
    EXPECT_NE(message.find("*SECTION_SOLID_SPG"), std::string::npos) << message;
    EXPECT_NE(message.find(c.field), std::string::npos) << c.field << ": " << message;
  }
}

TEST(SpgSetup, TooSmallSupportIsASingularMomentMatrixAtTheSection) {
  log::set_quiet(true);
  // DX 1.0 on a regular mesh: the support ends exactly at the neighbours, where the window is 0.
  const std::string message = build_error(test_support::spg_block_model(test_support::support_too_small(2)));
  EXPECT_NE(message.find("*SECTION_SOLID_SPG"), std::string::npos) << message;
  EXPECT_NE(message.find("singular moment matrix"), std::string::npos) << message;
  EXPECT_NE(message.find("node 1 "), std::string::npos) << message;
}

TEST(SpgSetup, InvertedElementsAreRefusedAndARigidMaterialMakesARigidBody) {
  log::set_quiet(true);
  test_support::SpgBlock b;
  b.elements = {2, 2, 2};
  b.size = Vec3(0.2, 0.2, 0.2);
  // *MAT_RIGID on a *SECTION_SOLID_SPG part: a rigid body, as in LS-DYNA (the section then only
  // gives the geometry), not SPG particles.
  model::Model rigid = test_support::spg_block_model(b);
  rigid.materials[1].keyword = "*MAT_RIGID";
  rigid.materials[1].params = model::MatRigid{7850, 2e11, 0.3};
  const solver::Problem p = solver::build_problem(rigid);
  EXPECT_TRUE(p.formulations.empty());
  ASSERT_EQ(p.rigid_bodies.bodies().size(), 1u);
  EXPECT_NEAR(p.rigid_bodies.bodies()[0].mass, 7850 * 0.008, 1e-12);
  model::Model inverted = test_support::spg_block_model(b);
  auto& n = inverted.solid_elements[0].n;
  std::swap(n[0], n[4]);
  std::swap(n[1], n[5]);
  std::swap(n[2], n[6]);
  std::swap(n[3], n[7]);
  EXPECT_NE(build_error(inverted).find("inverted"), std::string::npos);
}
