// SPG tensile bar with Johnson-Cook plasticity and bond failure (issue 5; the coarse version of
// examples/spg_tension): a 4340 steel bar 10 x 2 x 2 mm (20 x 4 x 4 elements, the section 3 %
// narrower in the middle), ends pulled apart at 20 m/s each, FS 0.6, STRETCH 1.2. It must
//   - neck: plastic strain localizes in the middle, the ends stay near the uniform strain;
//   - contract at the neck as plastic flow conserves volume: half-width / initial half-width =
//     exp(-eps_p / 2) for the lateral surface of a uniaxially stretched section (plastic
//     incompressibility, Hill 1950), here within 10 % (the discrete surface and the elastic part
//     of the strain);
//   - separate: bonds break across the neck and the two halves move apart (a gap wider than the
//     particle spacing between them).
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "spall/spg/formulation.hpp"
#include "support/spg_block.hpp"

using namespace spall;

TEST(SpgTension, JohnsonCookBarNecksAndSeparates) {
  log::set_quiet(true);
  const Real L = 10e-3, W = 2e-3, V = 20, taper = 0.03;
  const int nx = 20, ny = 4;
  test_support::SpgBlock b;
  b.size = Vec3(L, W, W);
  b.elements = {nx, ny, ny};
  b.section.fs = 0.6;
  b.section.stretch = 1.2;
  b.end_time = 8e-5;
  model::Model m = test_support::spg_block_model(b);
  auto initial_half_width = [&](Real x) { return 0.5 * W * (1 - taper * 0.5 * (1 + std::cos(2 * M_PI * (x / L - 0.5)))); };
  for (auto& node : m.nodes) {
    const Real s = initial_half_width(node.x.x()) / (0.5 * W);
    node.x.y() = 0.5 * W + (node.x.y() - 0.5 * W) * s;
    node.x.z() = 0.5 * W + (node.x.z() - 0.5 * W) * s;
  }
  // Johnson & Cook 1985, 4340 steel.
  model::MatJohnsonCook jc;
  jc.ro = 7830;
  jc.g = 77e9;
  jc.e = 200e9;
  jc.pr = 0.29;
  jc.a = 792e6;
  jc.b = 510e6;
  jc.n = 0.26;
  jc.c = 0.014;
  jc.m = 1.03;
  jc.tm = 1793;
  jc.tr = 293;
  jc.epso = 1;
  jc.cp = 477;
  jc.pc = -1e20;  // no spall: the bond failure separates the bar
  m.materials[1].keyword = "*MAT_JOHNSON_COOK";
  m.materials[1].params = jc;
  model::Curve ramp;
  ramp.id = 1;
  ramp.points = {{0, 0}, {1e-5, 1}, {1, 1}};
  m.curves[1] = ramp;
  for (const auto& node : m.nodes) {
    if (node.x.x() != 0 && node.x.x() != L) continue;
    model::PrescribedMotion pm;
    pm.id = node.id;
    pm.dof = 1;
    pm.lcid = 1;
    pm.sf = node.x.x() == 0 ? -V : V;
    m.prescribed_motions.push_back(pm);
  }
  solver::Problem p = solver::build_problem(m);
  const auto summary = solver::run(p, {});
  const auto& spg = dynamic_cast<const spg::SpgFormulation&>(*p.formulations[0]);
  discretization::FieldSet field_set(p.nodes.size());
  spg.write_fields(field_set, p.nodes);
  const auto& fields = field_set.node_fields();
  const auto& eps = std::get<std::vector<double>>(
      std::find_if(fields.begin(), fields.end(), [](const auto& f) { return f.name == "effective_plastic_strain"; })->values);

  // Per layer of the mesh (by first position): the largest plastic strain, and at the middle of
  // each lateral face (the particle at y = max, z = W/2) the half-width and the plastic strain.
  std::vector<Real> layer_strain(nx + 1, 0), face_strain(nx + 1, 0), face_half_width(nx + 1, 0);
  for (Index i = 0; i < p.nodes.size(); ++i) {
    const Vec3 x0 = p.nodes.x0[i];
    const int layer = static_cast<int>(std::lround(x0.x() / (L / nx)));
    layer_strain[layer] = std::max(layer_strain[layer], eps[i]);
    if (std::abs(x0.z() - 0.5 * W) < 1e-9 && x0.y() - 0.5 * W > 0.9 * initial_half_width(x0.x())) {
      face_half_width[layer] = p.nodes.x[i].y() - 0.5 * W;
      face_strain[layer] = eps[i];
    }
  }
  const int middle = nx / 2;
  const int peak = static_cast<int>(std::max_element(layer_strain.begin(), layer_strain.end()) - layer_strain.begin());
  std::printf("%lld steps; plastic strain: ends %.3f, peak %.3f at layer %d of %d; %zu broken bonds\n", summary.steps,
              layer_strain[0], layer_strain[peak], peak, nx, spg.parts()[0].broken_pairs().size());
  EXPECT_LE(std::abs(peak - middle), 1);
  EXPECT_LT(layer_strain[0], 0.2 * layer_strain[peak]);
  // Incompressible plastic flow at the layers beside the fracture (the fracture layer itself is
  // detached debris).
  for (int layer : {middle - 1, middle + 1}) {
    const Real ratio = face_half_width[layer] / initial_half_width(L * layer / nx);
    const Real expected = std::exp(-0.5 * face_strain[layer]);
    std::printf("layer %d: half-width ratio %.3f, exp(-eps_p / 2) = %.3f (eps_p %.3f)\n", layer, ratio, expected,
                face_strain[layer]);
    EXPECT_NEAR(ratio / expected, 1.0, 0.10);
    EXPECT_LT(ratio, 0.9);  // a real neck, not the uniform contraction
  }
  // Separated: between the particles left and right of the middle plane, a gap wider than the
  // particle spacing (0.5 mm).
  Real gap = std::numeric_limits<Real>::infinity();
  for (Index i = 0; i < p.nodes.size(); ++i)
    for (Index j = 0; j < p.nodes.size(); ++j)
      if (p.nodes.x0[i].x() < 0.5 * L - 1e-9 && p.nodes.x0[j].x() > 0.5 * L + 1e-9)
        gap = std::min(gap, (p.nodes.x[i] - p.nodes.x[j]).norm());
  std::printf("gap across the middle %.3f mm, energy ratio %.6f\n", 1e3 * gap, summary.energies.ratio());
  EXPECT_GT(gap, L / nx);
  EXPECT_NEAR(summary.energies.ratio(), 1.0, 0.01);
}
