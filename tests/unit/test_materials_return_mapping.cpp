// The radial return (Wilkins 1964; Simo & Hughes 1998 §3.3) lands on the yield surface to
// round-off for every strength model: after a plastic step, sigma_eq(S - alpha) equals the yield
// radius at the new plastic strain (and rate, temperature) within 1e-12 of it. The radius is
// evaluated here from each model's formula (LS-DYNA keyword manual), not by the library.
#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "spall/materials/elastic.hpp"
#include "spall/materials/material.hpp"

namespace spall::materials {
namespace {

constexpr Real young = 200e9, poisson = 0.3;
constexpr Real shear = young / (2 * (1 + poisson));

Material with_strength(Strength strength, Real g = shear) {
  Material m;
  m.density = 7850;
  m.shear_modulus = g;
  m.strength = std::move(strength);
  m.eos = LinearBulk{young / (3 * (1 - 2 * poisson))};
  return m;
}

// Random strain-rate tensors D (symmetric, with a volumetric part) large enough to yield, from
// random starting states that are already plastic. Deterministic seed.
// A material point with the back stress its formulation would keep beside it (zero unless the
// material keeps one).
struct Point {
  PointState state;
  Mat3 back_stress;
};

template <class Check>
void for_random_plastic_steps(const Material& material, Real strain_scale, Check check) {
  std::mt19937_64 random(20240601);
  std::uniform_real_distribution<Real> uniform(-1, 1);
  const auto random_rate = [&] {
    Mat3 a;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) a(i, j) = uniform(random);
    return Mat3(strain_scale * (a + a.transpose()) / 2);
  };
  const Real dt = 1e-6;
  int plastic_steps = 0;
  for (int trial = 0; trial < 200; ++trial) {
    Point point{initial_state(material), Mat3::Zero()};
    // Two steps: the first makes a plastic (and, with BETA < 1, back-stressed) start.
    for (int k = 0; k < 2; ++k) {
      const Point before = point;
      const Mat3 d = random_rate() / dt;
      update_deviatoric_stress(material, point.state, d, dt, material.density, 0.0,
                               keeps_back_stress(material) ? &point.back_stress : nullptr);
      if (point.state.plastic_strain > before.state.plastic_strain) {
        ++plastic_steps;
        check(before, point, d, dt);
      }
    }
  }
  EXPECT_GT(plastic_steps, 300);  // most steps are plastic: the check ran
}

Real relative_equivalent(const Point& p) {
  return von_mises(p.state.deviatoric_stress - p.back_stress);
}

TEST(materials_return_mapping, PlasticKinematicIsotropicKinematicMixedWithRate) {
  for (const Real beta : {1.0, 0.0, 0.4}) {
    const Real sigy = 250e6, ep = 1.5e9;
    // Cowper-Symonds with the usual mild-steel constants C = 40.4 /s, P = 5 (Jones, Structural
    // Impact, 1989).
    const CowperSymonds rate{40.4, 5};
    const Material material = with_strength(PlasticKinematic{sigy, ep, beta, rate, 0});
    for_random_plastic_steps(
        material, 1e-2,
        [&](const Point& before, const Point& after, const Mat3& d, Real dt) {
          // R = [1 + (eps_rate/C)^(1/P)] (SIGY + BETA Ep eps_p), eps_rate = sqrt(2/3 D:D)
          const Real eps_rate = std::sqrt(2.0 / 3.0 * d.cwiseProduct(d).sum());
          const Real factor = 1 + std::pow(eps_rate / 40.4, 1 / 5.0);
          const Real radius = factor * (sigy + beta * ep * after.state.plastic_strain);
          ASSERT_NEAR(relative_equivalent(after), radius, 1e-12 * radius) << "beta " << beta;
          // Linear hardening: dp = (q_trial - R_n) / (3G + (1 - BETA) Ep + factor BETA Ep) exactly.
          const Mat3 dev = d - d.trace() / 3 * Mat3::Identity();
          const Real q_trial =
              von_mises(before.state.deviatoric_stress + 2 * shear * dt * dev - before.back_stress);
          const Real expected_dp = (q_trial - factor * (sigy + beta * ep * before.state.plastic_strain)) /
                                   (3 * shear + (1 - beta) * ep + factor * beta * ep);
          ASSERT_NEAR(after.state.plastic_strain - before.state.plastic_strain, expected_dp,
                      1e-12 * expected_dp);
          (void)dt;
        });
  }
}

TEST(materials_return_mapping, PiecewiseLinearCurveWithRate) {
  // Three slopes, so that one return may cross from one segment into the next.
  const std::vector<std::pair<Real, Real>> points = {
      {0, 300e6}, {0.01, 350e6}, {0.05, 360e6}, {0.2, 420e6}};
  PiecewiseLinear strength;
  strength.curve = HardeningCurve(points);
  strength.rate = {6500, 4};  // aluminium-like Cowper-Symonds constants
  const Material material = with_strength(strength);
  // Linear interpolation, first/last slope beyond the ends.
  const auto sigma_y = [&](Real eps) {
    std::size_t k = 1;
    while (k + 1 < points.size() && eps > points[k].first) ++k;
    const auto [x0, y0] = points[k - 1];
    const auto [x1, y1] = points[k];
    return y0 + (y1 - y0) / (x1 - x0) * (eps - x0);
  };
  for_random_plastic_steps(
      material, 2e-2, [&](const Point&, const Point& after, const Mat3& d, Real) {
        const Real factor =
            1 + std::pow(std::sqrt(2.0 / 3.0 * d.cwiseProduct(d).sum()) / 6500, 1 / 4.0);
        const Real radius = factor * sigma_y(after.state.plastic_strain);
        ASSERT_NEAR(von_mises(after.state.deviatoric_stress), radius, 1e-12 * radius);
      });
}

// OFHC copper, Johnson-Cook (validation.md §1(b)): A 90 MPa, B 292 MPa, N 0.31, C 0.025, M 1.09.
Material johnson_cook_copper() {
  JohnsonCook jc;
  jc.a = 90e6, jc.b = 292e6, jc.n = 0.31, jc.c = 0.025, jc.m = 1.09;
  jc.melt_temperature = 1356, jc.room_temperature = 298, jc.reference_rate = 1.0;
  jc.heat_capacity = 383;
  Material material = with_strength(jc, 46.3e9);
  material.density = 8960;
  material.initial_temperature = 298;
  return material;
}

TEST(materials_return_mapping, JohnsonCookWithRateFromTheIncrement) {
  // Rate term on the increment's own plastic strain rate.
  const Material material = johnson_cook_copper();
  for_random_plastic_steps(
      material, 3e-3, [&](const Point& before, const Point& after, const Mat3&, Real dt) {
        // sigma_y = (A + B eps_p^N)(1 + C ln max(eps_rate/EPSO, 1))(1 - T*^M), T at the step start
        const Real dp = after.state.plastic_strain - before.state.plastic_strain;
        const Real rate = std::max(dp / dt / 1.0, 1.0);
        const Real t_star = (before.state.temperature - 298) / (1356 - 298);
        const Real radius = (90e6 + 292e6 * std::pow(after.state.plastic_strain, 0.31)) *
                            (1 + 0.025 * std::log(rate)) * (1 - std::pow(t_star, 1.09));
        ASSERT_NEAR(von_mises(after.state.deviatoric_stress), radius, 1e-12 * radius);
      });
}

TEST(materials_return_mapping, JohnsonCookSmallIncrementsOfAStrainedPoint) {
  // Steady flow of a strained point (eps_p from 0.4, 10^3 /s, dt 100 ns): dp (about 10^-4) stays
  // below 2^-7 eps_p, where the return takes (1 + dp/eps_p)^N and the rate logarithm from series
  // (johnson_cook.cpp). It must land on the yield surface as exactly as with pow and log.
  const Material material = johnson_cook_copper();
  PointState state = initial_state(material);
  state.plastic_strain = 0.4;
  Mat3 d;
  d << 1, 0.3, 0, 0.3, -0.5, 0.2, 0, 0.2, -0.5;
  d *= 1e3 / effective_strain_rate(d);
  const Real dt = 1e-7;
  int series_steps = 0;
  for (int step = 0; step < 300; ++step) {
    const PointState before = state;
    update_deviatoric_stress(material, state, d, dt, material.density, 0.0);
    // dp as the difference of two plastic strains near 0.4 carries an error of ulp(0.4), which
    // the rate term C ln(dp / dt) turns into 0.025 ulp(0.4) / dp: below 1e-6 (the step into yield)
    // that exceeds the tolerance and the step is not checked.
    const Real dp = state.plastic_strain - before.plastic_strain;
    if (!(dp > 1e-6)) continue;
    series_steps += dp <= 0x1p-7 * before.plastic_strain;
    const Real t_star = (before.temperature - 298) / (1356 - 298);
    const Real radius = (90e6 + 292e6 * std::pow(state.plastic_strain, 0.31)) *
                        (1 + 0.025 * std::log(std::max(dp / dt, 1.0))) * (1 - std::pow(t_star, 1.09));
    ASSERT_NEAR(von_mises(state.deviatoric_stress), radius, 1e-12 * radius) << "step " << step;
  }
  EXPECT_GT(series_steps, 200);
}

TEST(materials_return_mapping, JohnsonCookStateChangedByHandBetweenSteps) {
  // eps_p^N and T*^M follow by series from pow anchors kept in the state (johnson_cook.cpp): a state
  // whose plastic strain and temperature are then set by hand, near the anchors (within their
  // series' reach) and far from them, must still land on the yield surface of its new values.
  const Material material = johnson_cook_copper();
  Mat3 d;
  d << 1, 0.3, 0, 0.3, -0.5, 0.2, 0, 0.2, -0.5;
  d *= 1e3 / effective_strain_rate(d);
  const Real dt = 1e-7;
  for (const Real scale : {1.001, 1.5}) {
    PointState state = initial_state(material);
    state.plastic_strain = 0.3;
    state.temperature = 400;
    for (int step = 0; step < 20; ++step) update_deviatoric_stress(material, state, d, dt, material.density, 0.0);
    state.plastic_strain *= scale;
    state.temperature *= scale;
    const PointState before = state;
    update_deviatoric_stress(material, state, d, dt, material.density, 0.0);
    const Real dp = state.plastic_strain - before.plastic_strain;
    ASSERT_GT(dp, 1e-6) << "scale " << scale;
    const Real t_star = (before.temperature - 298) / (1356 - 298);
    const Real radius = (90e6 + 292e6 * std::pow(state.plastic_strain, 0.31)) * (1 + 0.025 * std::log(dp / dt)) *
                        (1 - std::pow(t_star, 1.09));
    EXPECT_NEAR(von_mises(state.deviatoric_stress), radius, 1e-12 * radius) << "scale " << scale;
  }
}

// Normality: the isotropic return keeps the direction of the trial deviator.
TEST(materials_return_mapping, ReturnIsRadial) {
  const Material material = with_strength(PlasticKinematic{250e6, 1e9, 1.0, {}, 0});
  PointState state;
  Mat3 d;
  d << 1, 2, 0.5, 2, -3, 1, 0.5, 1, 4;
  d *= 1e-3;
  update_deviatoric_stress(material, state, d, 1.0, material.density, 0.0);
  const Mat3 dev = d - d.trace() / 3 * Mat3::Identity();
  const Mat3 direction = state.deviatoric_stress / state.deviatoric_stress.norm();
  EXPECT_NEAR((direction - dev / dev.norm()).norm(), 0, 1e-14);
  EXPECT_GT(state.plastic_strain, 0);
}

}  // namespace
}  // namespace spall::materials
