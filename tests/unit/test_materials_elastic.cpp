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

TEST(Elastic, JaumannRotationOfPrincipalStressesUnderASpin) {
  // A spin omega about z turns principal stresses s1, s2 on x and y: (W S - S W)_xy =
  // omega (s1 - s2), the diagonal unchanged (the rate of a tensor carried by a rigid rotation,
  // Belytschko, Liu & Moran, Nonlinear Finite Elements, §3.7).
  const Real omega = 3, s1 = 5, s2 = -2;
  Mat3 L = Mat3::Zero();
  L(1, 0) = omega;  // v = omega e_z x x: v_y = omega x
  L(0, 1) = -omega;
  const Mat3 S = Vec3(s1, s2, 0).asDiagonal();
  const Mat3 R = materials::jaumann_rotation(L, S);
  EXPECT_DOUBLE_EQ(R(0, 1), omega * (s1 - s2));
  EXPECT_DOUBLE_EQ(R(1, 0), omega * (s1 - s2));
  EXPECT_EQ(R.diagonal(), Vec3::Zero());
  EXPECT_EQ(R(0, 2), 0);
  EXPECT_EQ(R(1, 2), 0);
}

TEST(Elastic, JaumannRotationIsTheCommutatorOfSpinAndStress) {
  // Its six entries written out against the two matrix products W S - S W, for a general L
  // (stretch and spin) and symmetric S, to round-off.
  Mat3 L;
  L << 0.3, -1.2, 0.7, 2.1, -0.4, -0.9, 0.2, 1.6, 0.1;
  Mat3 S;
  S << 4, -1, 2, -1, -3, 0.5, 2, 0.5, -1;
  const Mat3 W = Real(0.5) * (L - L.transpose());
  const Mat3 expected = W * S - S * W;
  const Mat3 R = materials::jaumann_rotation(L, S);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) EXPECT_NEAR(R(i, j), expected(i, j), 1e-14) << i << ", " << j;
}

TEST(Elastic, UniaxialStrainPressureAndVonMises) {
  const auto c = materials::ElasticConstants::from_young_poisson(1000, 1e9, 0.25);
  EXPECT_NEAR(materials::elastic_pressure(c, 1010), c.bulk_modulus * 0.01, 1e-3);
  Mat3 S = Mat3::Zero();
  S(0, 0) = 2, S(1, 1) = -1, S(2, 2) = -1;  // deviator of uniaxial stress 3
  EXPECT_NEAR(materials::von_mises(S), 3.0, 1e-14);
}
