// Properties of the cubic spline of seed 000 eq. 3 (support radius H): normalisation, compact
// support, gradient antisymmetry and consistency with the derivative.
#include <gtest/gtest.h>

#include "spall/kernels/cubic_spline.hpp"

using spall::Real;
using spall::Vec3;

namespace {

// Riemann sum of W over a fine lattice: the integral of W over space, which must be one.
template <int Dim>
Real lattice_integral(Real support, Real spacing) {
  using K = spall::kernels::CubicSpline<Dim>;
  const int n = static_cast<int>(std::ceil(support / spacing)) + 1;
  Real sum = 0;
  for (int i = -n; i <= n; ++i)
    for (int j = (Dim > 1 ? -n : 0); j <= (Dim > 1 ? n : 0); ++j)
      for (int k = (Dim > 2 ? -n : 0); k <= (Dim > 2 ? n : 0); ++k) {
        const Real r = spacing * std::sqrt(Real(i * i + j * j + k * k));
        sum += K::value(r, support);
      }
  return sum * std::pow(spacing, Dim);
}

}  // namespace

TEST(CubicSpline, IntegratesToOneInEveryDimension) {
  // Tolerance: the Riemann sum of a C2 kernel at H/dx = 40 is exact to well below 1e-4.
  EXPECT_NEAR(lattice_integral<1>(1.3, 1.3 / 40), 1.0, 1e-4);
  EXPECT_NEAR(lattice_integral<2>(0.7, 0.7 / 40), 1.0, 1e-4);
  EXPECT_NEAR(lattice_integral<3>(2.0, 2.0 / 40), 1.0, 1e-4);
}

TEST(CubicSpline, MatchesSeedEquation3) {
  using K = spall::kernels::CubicSpline<3>;
  const Real H = 2.0, s = 8 / M_PI / (H * H * H);
  EXPECT_DOUBLE_EQ(K::value(0, H), s);                       // 6q^3 - 6q^2 + 1 at q = 0
  EXPECT_DOUBLE_EQ(K::value(0.5 * H, H), s * 0.25);          // both branches give 1/4 at q = 1/2
  EXPECT_DOUBLE_EQ(K::value(0.75 * H, H), s * 2 * 0.015625);  // 2 (1 - q)^3
  EXPECT_EQ(K::value(H, H), 0.0);
  EXPECT_EQ(K::value(1.5 * H, H), 0.0);
  EXPECT_EQ(K::derivative(1.01 * H, H), 0.0);
}

TEST(CubicSpline, DerivativeMatchesFiniteDifference) {
  using K = spall::kernels::CubicSpline<3>;
  const Real H = 1.7, e = 1e-6;
  for (Real q : {0.05, 0.2, 0.45, 0.55, 0.8, 0.97}) {
    const Real r = q * H;
    const Real fd = (K::value(r + e, H) - K::value(r - e, H)) / (2 * e);
    EXPECT_NEAR(K::derivative(r, H), fd, 1e-6 * std::abs(fd) + 1e-9) << "q = " << q;
  }
}

TEST(CubicSpline, GradientIsExactlyAntisymmetric) {
  using K = spall::kernels::CubicSpline<3>;
  const Vec3 xa(0.1, -0.37, 0.52), xb(0.43, 0.11, 0.2);
  const Vec3 xab = xa - xb, xba = xb - xa;
  const Vec3 gab = K::gradient(xab, xab.norm(), 1.0);
  const Vec3 gba = K::gradient(xba, xba.norm(), 1.0);
  EXPECT_EQ(gab, -gba);  // bitwise: the pair forces cancel exactly
  EXPECT_LT(gab.dot(xab), 0.0);  // W decreases with distance
}

TEST(CubicSpline, GradientSumsToZeroOnASymmetricLattice) {
  // sum_b V_b grad W_ab = 0 at an interior lattice point (zero mean gradient).
  using K = spall::kernels::CubicSpline<3>;
  const Real dx = 0.1, H = 2.4 * dx;
  Vec3 sum = Vec3::Zero();
  for (int i = -3; i <= 3; ++i)
    for (int j = -3; j <= 3; ++j)
      for (int k = -3; k <= 3; ++k) {
        const Vec3 xab = -dx * Vec3(i, j, k);
        sum += K::gradient(xab, xab.norm(), H) * dx * dx * dx;
      }
  EXPECT_LT(sum.norm(), 1e-12);
}
