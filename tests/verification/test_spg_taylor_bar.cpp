// An SPG Taylor bar at 350 m/s (issue 36): a steel rod, *MAT_PLASTIC_KINEMATIC (7.85 t/m^3, E 210 GPa,
// nu 0.3, yield 300 MPa, tangent modulus 1 GPa), a quarter of it meshed as the public LS-PrePost
// Taylor-bar mesh is (shared/decks/public/ansys-example-data_taylor_bar_mesh.k: 768 hexahedra, an
// O-grid of 16 per layer, 48 layers, 8 mm across and 30 mm long), symmetry planes by SPC, a rigid wall,
// t-mm-s units, through the keyword reader. rho v^2 / Y = 3.2: the foot spreads to 1.8 times its radius
// and the plastic strain there reaches 2 to 3.
//
// Before the KERNEL 1 and 2 windows widened with the stretch (THEORY §9.7), the particles of the
// spreading foot lost their neighbours across (windows of the first spacing), their moment matrices
// went ill-conditioned and a node ran away (exit 3) at 300, 325 and 350 m/s; KERNEL 0 inverted at
// 14 us (its conditioning was measured with one scale for windows the material had stretched); KERNEL 2
// then inverted at the axis under the foot at 13 us (a step on the first spacing: its first bonds,
// squeezed ten times, steepen the gradients).
//
// Checks, for each KERNEL with the manual's defaults (KERNEL 1 with seed 001's card: DX 1.5, SMSTEP 5):
// the run reaches 60 us (the rod has stopped and rebounds); the energy balance closes to 1 %; no node is
// faster than the impact speed at the end; and the final length and the widest foot agree with Spall's
// one-point hexahedra on the same mesh (ELFORM 1, verified against Wilkins & Guinan in
// test_fem_taylor_bar) within 3 % and 8 %, on the test's own O-grid and on the public mesh (when
// ../shared is there). Measured: own mesh L/L0 0.568, 0.566, 0.568 (FEM 0.567), widest R/R0 1.887,
// 1.881, 1.860 (FEM 1.847); public mesh L/L0 0.567, 0.562, 0.562 (FEM 0.569), R/R0 1.84, 1.80, 1.79
// (FEM 1.83). KERNEL 2 takes 5 times the steps (its step follows the squeezed first spacing).
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fmt/format.h>
#include <map>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "unit/keyword_test_decks.hpp"

using namespace spall;
using test::DeckFolder;
using test::node_list;
using test::row;

namespace {

constexpr Real radius = 4, length = 30, foot = 10;  // mm; the foot on the wall y = 10
constexpr int layers = 48;

// A quarter disc (x >= 0, z >= 0) as an O-grid: a 2 x 2 block around the axis with corners (0, 0),
// (b, 0), (c, c), (0, b), and two 2 x 3 blocks between it and the arc. Returns the nodes of one layer
// (x, z) and its quadrilaterals.
struct Layer {
  std::vector<std::pair<Real, Real>> points;
  std::vector<std::array<int, 4>> quads;
};

Layer quarter_disc() {
  Layer layer;
  std::map<std::pair<long, long>, int> index;
  auto point = [&](Real x, Real z) {
    const std::pair<long, long> key{std::lround(x * 1e6), std::lround(z * 1e6)};
    if (auto it = index.find(key); it != index.end()) return it->second;
    layer.points.push_back({x, z});
    return index[key] = static_cast<int>(layer.points.size()) - 1;
  };
  using P = Eigen::Vector2d;
  const Real b = 0.4 * radius, c = 0.34 * radius;
  // The central block: bilinear between its four corners.
  const P corner[4] = {P(0, 0), P(b, 0), P(c, c), P(0, b)};
  auto block = [&](Real u, Real v) {
    return (1 - u) * (1 - v) * corner[0] + u * (1 - v) * corner[1] + u * v * corner[2] + (1 - u) * v * corner[3];
  };
  std::vector<int> grid(9);
  for (int j = 0; j <= 2; ++j)
    for (int i = 0; i <= 2; ++i) {
      const P p = block(i / 2.0, j / 2.0);
      grid[i + 3 * j] = point(p.x(), p.y());
    }
  for (int j = 0; j < 2; ++j)
    for (int i = 0; i < 2; ++i)
      layer.quads.push_back({grid[i + 3 * j], grid[i + 1 + 3 * j], grid[i + 1 + 3 * (j + 1)], grid[i + 3 * (j + 1)]});
  // The outer blocks: straight lines from the block's outer edges to the arc.
  for (int side = 0; side < 2; ++side) {
    const P from = side == 0 ? corner[1] : corner[2], to = side == 0 ? corner[2] : corner[3];
    const Real angle0 = side == 0 ? 0 : M_PI / 4;
    int ring[4][3];
    for (int r = 0; r <= 3; ++r)
      for (int s = 0; s <= 2; ++s) {
        const P inner = from + (to - from) * (s / 2.0);
        const Real angle = angle0 + (M_PI / 4) * (s / 2.0);
        const P outer(radius * std::cos(angle), radius * std::sin(angle));
        const P p = inner + (outer - inner) * (r / 3.0);
        ring[r][s] = point(p.x(), p.y());
      }
    for (int r = 0; r < 3; ++r)
      for (int s = 0; s < 2; ++s)
        layer.quads.push_back({ring[r][s], ring[r + 1][s], ring[r + 1][s + 1], ring[r][s + 1]});
  }
  return layer;
}

// A rod mesh and its node sets: all nodes, those on the plane x = 0 and those on z = 0.
struct RodMesh {
  std::string text;  // *NODE and *ELEMENT_SOLID, or an *INCLUDE of them
  std::vector<Id> all, on_x, on_z;
};

// The quarter rod as an O-grid (quarter_disc), 48 layers.
RodMesh own_mesh() {
  const Layer layer = quarter_disc();
  const Id per_layer = static_cast<Id>(layer.points.size());
  const auto id = [&](int point, int k) { return Id(1 + point + per_layer * k); };
  RodMesh mesh;
  mesh.text = "*NODE\n";
  for (int k = 0; k <= layers; ++k)
    for (int p = 0; p < per_layer; ++p) {
      const auto [x, z] = layer.points[p];
      mesh.text += fmt::format("{:>8}{:>16.8f}{:>16.8f}{:>16.8f}\n", id(p, k), x, foot + length * k / layers, z);
      mesh.all.push_back(id(p, k));
      if (std::abs(x) < 1e-9) mesh.on_x.push_back(id(p, k));
      if (std::abs(z) < 1e-9) mesh.on_z.push_back(id(p, k));
    }
  mesh.text += "*ELEMENT_SOLID\n";
  Id eid = 1;
  for (int k = 0; k < layers; ++k)
    for (const auto& q : layer.quads) {
      // The base p0 p1 p2 p3 must turn about +y (towards the next layer) for a positive volume: the y
      // component of (p1 - p0) x (p3 - p0) in (x, y, z) is dz1 dx3 - dx1 dz3.
      const auto [x0, z0] = layer.points[q[0]];
      const auto [x1, z1] = layer.points[q[1]];
      const auto [x3, z3] = layer.points[q[3]];
      const bool turns_about_y = (z1 - z0) * (x3 - x0) - (x1 - x0) * (z3 - z0) > 0;
      const std::array<int, 4> base = turns_about_y ? q : std::array<int, 4>{q[0], q[3], q[2], q[1]};
      mesh.text += fmt::format("{:>8}{:>8}", eid++, 1);
      for (int p : base) mesh.text += fmt::format("{:>8}", id(p, k));
      for (int p : base) mesh.text += fmt::format("{:>8}", id(p, k + 1));
      mesh.text += "\n";
    }
  return mesh;
}

// The public mesh, included as users include it, its symmetry planes found from its nodes.
RodMesh public_mesh(const std::filesystem::path& path) {
  RodMesh mesh;
  mesh.text = "*INCLUDE\n" + path.string() + "\n";
  for (const auto& node : io::keyword::read_deck(path).nodes) {
    mesh.all.push_back(node.id);
    if (std::abs(node.x.x()) < 1e-9) mesh.on_x.push_back(node.id);
    if (std::abs(node.x.z()) < 1e-9) mesh.on_z.push_back(node.id);
  }
  return mesh;
}

// The deck: the mesh, the part with `section` (its keyword and cards), the steel, the symmetry planes,
// 350 m/s towards the wall, 60 us.
std::string taylor_deck(const RodMesh& mesh, const std::string& section) {
  return "*KEYWORD\n" + mesh.text + "*PART\nsteel rod\n" + row({"1", "1", "1"}) + section +
         "*MAT_PLASTIC_KINEMATIC\n" + row({"1", "7.85e-9", "2.1e5", "0.3", "300.", "1000."}) + node_list(1, mesh.all) +
         node_list(2, mesh.on_x) + node_list(3, mesh.on_z) + "*BOUNDARY_SPC_SET\n" + row({"2", "0", "1"}) +
         "*BOUNDARY_SPC_SET\n" + row({"3", "0", "0", "0", "1"}) + "*INITIAL_VELOCITY\n" + row({"1"}) +
         row({"0.", "-3.5e5", "0."}) + "*RIGIDWALL_PLANAR\n" + row({}) + row({"0.", "10.", "0.", "0.", "11.", "0."}) +
         "*CONTROL_TERMINATION\n" + row({"6.0e-5"}) + "*END\n";
}

struct Outcome {
  Real length_ratio = 0, radius_ratio = 0, energy_ratio = 0, fastest = 0;
};

Outcome run_deck(const DeckFolder& folder, const std::string& name, const RodMesh& mesh, const std::string& section) {
  const model::Model model = io::keyword::read_deck(folder.write(name, taylor_deck(mesh, section)));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  EXPECT_EQ(model.solid_elements.size(), 768u);
  // The rod's length along y and the widest radius (the foot's).
  const auto extent = [&](const std::vector<Vec3>& x) {
    Real low = x[0].y(), high = x[0].y(), widest = 0;
    for (const Vec3& p : x) {
      low = std::min(low, p.y()), high = std::max(high, p.y());
      widest = std::max(widest, std::hypot(p.x(), p.z()));
    }
    return std::pair{high - low, widest};
  };
  const auto [length0, radius0] = extent(problem.nodes.x0);
  Real widest = radius0;
  solver::Observer observer;
  problem.controls.glstat_dt = 1e-6;
  observer.on_history = [&](const solver::StepInfo&, const discretization::EnergyLedger&) {
    widest = std::max(widest, extent(problem.nodes.x).second);
  };
  const auto summary = solver::run(problem, observer);
  Outcome out{extent(problem.nodes.x).first / length0, widest / radius0, summary.energies.ratio(), 0};
  for (const Vec3& v : problem.nodes.v) out.fastest = std::max(out.fastest, v.norm());
  std::printf("%s: L/L0 %.4f, widest foot R/R0 %.4f, energy ratio %.6f, fastest node %.0f m/s, %lld steps\n",
              name.c_str(), out.length_ratio, out.radius_ratio, out.energy_ratio, out.fastest / 1000, summary.steps);
  return out;
}

// Runs the rod as ELFORM 1 hexahedra and as SPG with each KERNEL given, and compares.
void expect_spg_matches_fem(const RodMesh& mesh, const std::vector<std::array<std::string, 3>>& kernels) {
  DeckFolder folder;
  const Outcome fem = run_deck(folder, "fem.k", mesh, "*SECTION_SOLID\n" + row({"1", "1"}));
  for (const auto& [kernel, dx, smstep] : kernels) {
    const std::string section = "*SECTION_SOLID_SPG\n" + row({"1", "47", "0"}) +
                                row({dx, dx, dx, "0", kernel, "", smstep}) + row({"1", "10"});
    const Outcome spg = run_deck(folder, "spg_kernel_" + kernel + ".k", mesh, section);
    EXPECT_NEAR(spg.energy_ratio, 1.0, 0.01) << "KERNEL " << kernel;
    EXPECT_LT(spg.fastest, 3.5e5) << "KERNEL " << kernel;
    EXPECT_NEAR(spg.length_ratio, fem.length_ratio, 0.03 * fem.length_ratio) << "KERNEL " << kernel;
    EXPECT_NEAR(spg.radius_ratio, fem.radius_ratio, 0.08 * fem.radius_ratio) << "KERNEL " << kernel;
  }
}

// KERNEL, DX, SMSTEP: the manual's defaults, and seed 001's card for the Eulerian kernel.
const std::array<std::string, 3> updated_lagrangian{"0", "1.6", "15"}, eulerian{"1", "1.5", "5"},
    pseudo_lagrangian{"2", "1.5", "30"};

}  // namespace

TEST(SpgTaylorBar, SteelAt350MetresPerSecondOnAQuarterOGridWithEveryKernel) {
  log::set_quiet(true);
  expect_spg_matches_fem(own_mesh(), {updated_lagrangian, eulerian, pseudo_lagrangian});
}

TEST(SpgTaylorBar, SteelAt350MetresPerSecondOnThePublicMeshWithEveryKernel) {
  const auto path =
      std::filesystem::path(SPALL_SHARED_DIR) / "decks" / "public" / "ansys-example-data_taylor_bar_mesh.k";
  if (!std::filesystem::exists(path))
    GTEST_SKIP() << path.string() << " is absent (a clone without ../shared): skipped";
  log::set_quiet(true);
  expect_spg_matches_fem(public_mesh(path), {updated_lagrangian, eulerian, pseudo_lagrangian});
}
