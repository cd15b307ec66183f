// The quantities *SECTION_SOLID_SPG IDAM 2 and 3 judge bonds on (spg/bond_failure.hpp), against
// closed forms: the largest eigenvalue of a rotated diagonal stress, and the maximum tensorial
// shear (eps_1 - eps_3) / 2 of the logarithmic strain for simple shear (principal stretches
// lambda = gamma / 2 + sqrt(1 + gamma^2 / 4), so eps_1 = -eps_3 = asinh(gamma / 2)) and for an
// isochoric uniaxial stretch (lambda, lambda^-1/2, lambda^-1/2: 3/4 ln lambda), invariant under a
// rotation of the deformed configuration.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/spg/bond_failure.hpp"

using namespace spall;

namespace {

Mat3 rotation() {
  return (Eigen::AngleAxis<Real>(0.7, Vec3(1, 2, 3).normalized()) *
          Eigen::AngleAxis<Real>(-1.1, Vec3(0, 1, 0)))
      .toRotationMatrix();
}

}  // namespace

TEST(SpgBondFailureQuantity, MaximumPrincipalStressOfARotatedStress) {
  const Mat3 R = rotation();
  const Mat3 diagonal = Vec3(-3.0e8, 1.25e8, 0.5e8).asDiagonal();
  EXPECT_NEAR(spg::max_principal_stress(R * diagonal * R.transpose()), 1.25e8, 1e-6);
  EXPECT_NEAR(spg::max_principal_stress(-2.0e5 * Mat3::Identity()), -2.0e5, 1e-9);
}

TEST(SpgBondFailureQuantity, MaximumShearStrainOfSimpleShear) {
  for (Real gamma : {1e-4, 0.1, 1.0, 3.0}) {
    Mat3 F = Mat3::Identity();
    F(0, 1) = gamma;
    EXPECT_NEAR(spg::max_shear_strain(F), std::asinh(gamma / 2), 1e-12 * (1 + gamma)) << "gamma " << gamma;
    EXPECT_NEAR(spg::max_shear_strain(rotation() * F), std::asinh(gamma / 2), 1e-12 * (1 + gamma));
  }
}

TEST(SpgBondFailureQuantity, MaximumShearStrainOfIsochoricStretchAndNoneForRotation) {
  const Real lambda = 1.3;
  const Mat3 U = Vec3(1 / std::sqrt(lambda), lambda, 1 / std::sqrt(lambda)).asDiagonal();
  EXPECT_NEAR(spg::max_shear_strain(rotation() * U), 0.75 * std::log(lambda), 1e-13);
  EXPECT_NEAR(spg::max_shear_strain(rotation()), 0.0, 1e-13);
}
