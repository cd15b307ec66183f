// The public Taylor-bar mesh (shared/decks/public/ansys-example-data_taylor_bar_mesh.k: a quarter
// of a rod 30 mm long (y from 10 to 40 mm) and 8 mm across, 768 hexahedra written by LS-PrePost in the ten-node format,
// before its nodes) run as LS-DYNA users run it: a deck that *INCLUDEs the mesh and adds the part,
// *SECTION_SOLID ELFORM 1, a material, the symmetry planes, the initial velocity and a rigid wall,
// in t-mm-s units. The material and speed are Wilkins & Guinan's test 1 (OFHC copper, Johnson &
// Cook's constants, 210 m/s). The checks: the deck runs; the mass is rho times the mesh's volume;
// the energy balance closes to 1 %; the symmetry planes hold; and the rod shortens to L/L0 within
// 5 % of the 0.630 measured by Wilkins & Guinan for a rod of L0/D0 = 3.1 (this one has 3.75) (Taylor's one-dimensional
// theory makes L/L0 a function of rho v^2 / Y alone; Wilkins & Guinan 1973 report it independent
// of L0/D0 over their tests). Skipped without ../shared.
#include <gtest/gtest.h>

#include <filesystem>
#include <fmt/format.h>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "unit/keyword_test_decks.hpp"

using namespace spall;
using test::DeckFolder;
using test::node_list;
using test::row;

namespace {

const std::filesystem::path mesh =
    std::filesystem::path(SPALL_SHARED_DIR) / "decks" / "public" / "ansys-example-data_taylor_bar_mesh.k";

}  // namespace

TEST(FemPublicTaylorMesh, RunsAsFiniteElementsAndShortensAsWilkinsGuinan) {
  if (!std::filesystem::exists(mesh)) GTEST_SKIP() << mesh.string() << " is absent (a clone without ../shared): skipped";
  log::set_quiet(true);
  // The symmetry planes x = 0 and z = 0 from the mesh itself.
  const model::Model alone = io::keyword::read_deck(mesh);
  std::vector<Id> all, on_x, on_z;
  for (const auto& node : alone.nodes) {
    all.push_back(node.id);
    if (std::abs(node.x.x()) < 1e-9) on_x.push_back(node.id);
    if (std::abs(node.x.z()) < 1e-9) on_z.push_back(node.id);
  }
  ASSERT_FALSE(on_x.empty());
  ASSERT_FALSE(on_z.empty());
  DeckFolder folder;
  const std::string deck =
      "*KEYWORD\n*INCLUDE\n" + mesh.string() + "\n*PART\ncopper rod\n" + row({"1", "1", "1"}) + "*SECTION_SOLID\n" +
      row({"1", "1"}) + "*MAT_JOHNSON_COOK\n" + row({"1", "8.96e-9", "46269.", "124000.", "0.34"}) +
      row({"90.", "292.", "0.31", "0.025", "1.09", "1356.", "298.", "1.0"}) + row({"3.83e8", "-1000.", "1"}) +
      row({}) + node_list(1, all) + node_list(2, on_x) + node_list(3, on_z) +
      "*BOUNDARY_SPC_SET\n" + row({"2", "0", "1"}) + "*BOUNDARY_SPC_SET\n" + row({"3", "0", "0", "0", "1"}) +
      "*INITIAL_VELOCITY\n" + row({"1"}) + row({"0.", "-2.1e5", "0."}) + "*RIGIDWALL_PLANAR\n" + row({}) +
      row({"0.", "10.", "0.", "0.", "11.", "0."}) + "*CONTROL_TERMINATION\n" + row({"8.0e-5"}) + "*END\n";
  const model::Model model = io::keyword::read_deck(folder.write("taylor.k", deck));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  ASSERT_EQ(problem.formulations.size(), 1u);
  EXPECT_STREQ(problem.formulations[0]->name(), "FEM");
  // The rod's length along y (its foot on the wall at y = 10 mm).
  const auto length_of = [&](const std::vector<Vec3>& x) {
    Real low = x[0].y(), high = x[0].y();
    for (const Vec3& p : x) low = std::min(low, p.y()), high = std::max(high, p.y());
    return high - low;
  };
  const Real length0 = length_of(problem.nodes.x0);
  Real mass = 0;
  for (Real m : problem.nodes.mass) mass += m;
  // A quarter of the rod, its circle as the mesh's polygon: the mass of a quarter cylinder to 1 %.
  EXPECT_NEAR(length0, 30.0, 1e-9);
  EXPECT_NEAR(mass, 8.96e-9 * M_PI * 4 * 4 * 30 / 4, 0.01 * mass);
  const auto summary = solver::run(problem, {});
  const Real length = length_of(problem.nodes.x);
  Real off_plane = 0;
  for (Index i = 0; i < problem.nodes.size(); ++i) {
    if (std::abs(problem.nodes.x0[i].x()) < 1e-9) off_plane = std::max(off_plane, std::abs(problem.nodes.x[i].x()));
    if (std::abs(problem.nodes.x0[i].z()) < 1e-9) off_plane = std::max(off_plane, std::abs(problem.nodes.x[i].z()));
  }
  std::printf("public Taylor mesh, ELFORM 1: L/L0 %.4f (Wilkins & Guinan 0.630, %+.1f %%), energy ratio %.4f, "
              "%lld steps\n", length / length0, 100 * (length / length0 / 0.630 - 1), summary.energies.ratio(),
              summary.steps);
  EXPECT_NEAR(length / length0, 0.630, 0.05 * 0.630);
  EXPECT_NEAR(summary.energies.ratio(), 1.0, 0.01);
  EXPECT_EQ(off_plane, 0.0);
}
