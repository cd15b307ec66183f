// Patch test of the SPG formulation on irregular particles (a hex mesh with jittered interior
// nodes): a linear displacement u = G X must give the exact constant strain at every particle and
// a zero internal force at every particle whose support does not reach the surface (the
// integration constraint, Chen, Wu, Yoon & You 2001; THEORY §9.4). Both stabilization variants
// (ITB 1, smoothed strain; ITB 2, unsmoothed).
#include <gtest/gtest.h>

#include "spall/core/log.hpp"
#include "spall/materials/elastic.hpp"
#include "spall/solver/problem.hpp"
#include "spall/spg/formulation.hpp"
#include "support/spg_block.hpp"

using namespace spall;

namespace {

struct PatchResult {
  Real worst_stress_error = 0;     // max |sigma - sigma_exact| / |sigma_exact|
  Real worst_interior_force = 0;   // max |f| / (|sigma| h^2) over interior particles
  Real largest_surface_force = 0;  // the same on the surface, which is not zero
  int interior_particles = 0;
};

struct Patch {
  int itb = 1;
  int ispline = 0;
  int elements = 12;  // per edge, h = 0.1
};

PatchResult patch_test(const Patch& patch) {
  const int itb = patch.itb;
  test_support::SpgBlock b;
  b.elements = {patch.elements, patch.elements, patch.elements};
  b.size = Vec3::Constant(0.1 * patch.elements);
  b.section.ispline = patch.ispline;
  b.jitter = 0.2;
  b.seed = 9;
  b.young = 2.0e11;
  b.poisson = 0.3;
  b.density = 7850;
  b.section.itb = itb;
  const model::Model m = test_support::spg_block_model(b);
  solver::Problem p = solver::build_problem(m);
  auto& nodes = p.nodes;
  auto& spg = *p.formulations[0];
  Mat3 G;
  G << 1.0, 2.0, 3.0, -1.0, 0.5, 2.0, 0.3, -2.0, 1.5;
  G *= 1e-3;
  // One step from rest that moves every particle by G X: the stress is the elastic response to the
  // homogeneous deformation F = I + G.
  const Real dt = 1e-6;
  for (auto& f : nodes.f) f.setZero();
  spg.compute_forces(nodes, 0);
  for (Index i = 0; i < nodes.size(); ++i) {
    const Vec3 u = G * nodes.x0[i];
    nodes.x[i] += u;
    nodes.v[i] = u / dt;
    nodes.f[i].setZero();
  }
  spg.compute_forces(nodes, dt);
  // Closed form: L = (G / dt) F^-1 over the step, S = dt 2 mu dev(sym L) (Jaumann rate from S = 0),
  // p = K (rho / rho_0 - 1) with rho / rho_0 = 1 / det F.
  const auto c = materials::ElasticConstants::from_young_poisson(b.density, b.young, b.poisson);
  const Mat3 F = Mat3::Identity() + G;
  const Mat3 L = (G / dt) * F.inverse();
  const Mat3 D = 0.5 * (L + L.transpose());
  const Mat3 S = dt * 2 * c.shear_modulus * (D - D.trace() / 3 * Mat3::Identity());
  const Real pressure = c.bulk_modulus * (1 / F.determinant() - 1);
  const Mat3 sigma = S - pressure * Mat3::Identity();
  const double exact[6] = {sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(2, 0)};

  discretization::FieldSet field_set(nodes.size());
  spg.write_fields(field_set, nodes);
  const auto& fields = field_set.node_fields();
  const auto stress = std::find_if(fields.begin(), fields.end(), [](const auto& f) { return f.name == "stress"; });
  const auto& values = std::get<std::vector<double>>(stress->values);
  const Real h = 0.1;
  const Real force_scale = sigma.norm() * h * h;
  PatchResult r;
  for (Index i = 0; i < nodes.size(); ++i) {
    Real error = 0;
    for (int k = 0; k < 6; ++k) error = std::max(error, std::abs(values[6 * i + k] - exact[k]));
    r.worst_stress_error = std::max(r.worst_stress_error, error / sigma.norm());
    // Interior: farther from the surface than the column of the operator reaches, two bonds for
    // the smoothed operator G A (ITB 1), one for G (ITB 2); a bond is at most as long as the
    // support radius (the corner of a cubical support), 1.6 x 1.3 h at most with the jitter.
    const Real bond = 1.6 * 1.3 * h * (patch.ispline == 2 ? 1.0 : std::sqrt(3.0));
    const Real reach = (itb == 1 ? 2 : 1) * bond;
    const Vec3 x = nodes.x0[i];
    const Real depth = std::min(x.minCoeff(), (b.size - x).minCoeff());
    const Real f = nodes.f[i].norm() / force_scale;
    if (depth > reach) {
      ++r.interior_particles;
      r.worst_interior_force = std::max(r.worst_interior_force, f);
    } else {
      r.largest_surface_force = std::max(r.largest_surface_force, f);
    }
  }
  return r;
}

}  // namespace

TEST(SpgPatchTest, LinearDisplacementOnIrregularParticles) {
  log::set_quiet(true);
  // The smoothed operator's column reaches twice as far: a larger block keeps interior particles.
  const Patch patches[] = {{1, 2, 12}, {2, 0, 12}, {1, 0, 18}};
  for (const Patch& patch : patches) {
    const PatchResult r = patch_test(patch);
    std::printf("ITB %d ISPLINE %d: stress error %.2e, interior force %.2e sigma h^2 (%d particles), surface %.2e\n",
                patch.itb, patch.ispline, r.worst_stress_error, r.worst_interior_force, r.interior_particles,
                r.largest_surface_force);
    // Exact constant strain: round-off of F - I = 1e-3 computed from coordinates of order 1.
    EXPECT_LT(r.worst_stress_error, 1e-10) << "ITB " << patch.itb;
    EXPECT_GE(r.interior_particles, 8);
    // Zero interior residual: round-off against forces of order sigma h^2.
    EXPECT_LT(r.worst_interior_force, 1e-9) << "ITB " << patch.itb;
    // The surface particles carry the traction of the constant stress: far from zero.
    EXPECT_GT(r.largest_surface_force, 0.1) << "ITB " << patch.itb;
  }
}
