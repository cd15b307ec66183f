// Hooke's law in Jaumann rate form (Gray, Monaghan & Swift 2001): closed-form checks.
#include <gtest/gtest.h>

#include "spall/materials/elastic.hpp"

using namespace spall;

TEST(Elastic, ModuliFromYoungAndPoisson) {
  const auto c = materials::ElasticConstants::from_young_poisson(7850, 200e9, 0.3);
  EXPECT_NEAR(c.bulk_modulus, 200e9 / (3 * 0.4), 1);
  EXPECT_NEAR(c.shear_modulus, 200e9 / 2.6, 1);
  // P-wave speed sqrt(E (1 - nu) / ((1 + nu)(1 - 2 nu) rho)) (validation.md §4)
  EXPECT_NEAR(c.longitudinal_wave_speed(7850), std::sqrt(200e9 * 0.7 / (1.3 * 0.4 * 7850)), 1e-6);
}

TEST(Elastic, PureShearRateGivesTwoGTimesStrainRate) {
  const Real G = 80e9;
  Mat3 L = Mat3::Zero();
  L(0, 1) = L(1, 0) = 1e-3;  // pure shear, no spin
  const Mat3 rate = materials::jaumann_deviatoric_stress_rate(G, Mat3::Zero(), L);
  EXPECT_NEAR(rate(0, 1), 2 * G * 1e-3, 1e-3);
  EXPECT_NEAR(rate.trace(), 0, 1e-6);
}

TEST(Elastic, RigidRotationRotatesTheStressWithoutStraining) {
  // Under a spin W the Jaumann rate leaves the stress invariants unchanged: dS/dt = W S - S W
  // has zero trace product with S, so d(S:S)/dt = 0.
  Mat3 S;
  S << 1, 2, 0, 2, -3, 1, 0, 1, 2;
  Mat3 L = Mat3::Zero();
  L(0, 1) = -0.5;
  L(1, 0) = 0.5;
  const Mat3 rate = materials::jaumann_deviatoric_stress_rate(1e9, S, L);
  EXPECT_NEAR(S.cwiseProduct(rate).sum(), 0.0, 1e-12);
  EXPECT_GT(rate.norm(), 0.1);
}

TEST(Elastic, UniaxialStrainPressureAndVonMises) {
  const auto c = materials::ElasticConstants::from_young_poisson(1000, 1e9, 0.25);
  EXPECT_NEAR(materials::elastic_pressure(c, 1010), c.bulk_modulus * 0.01, 1e-3);
  Mat3 S = Mat3::Zero();
  S(0, 0) = 2, S(1, 1) = -1, S(2, 2) = -1;  // deviator of uniaxial stress 3
  EXPECT_NEAR(materials::von_mises(S), 3.0, 1e-14);
}
