// Properties every SPH kernel must have, for every kernel (SPHKERN) and every dimension:
// normalisation (integral one), compact support, exact gradient antisymmetry, zero mean gradient
// on a symmetric lattice, derivative consistent with the value, W decreasing in r. Plus the cubic
// spline's values against seed 000 eq. 3.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/kernels/kernel.hpp"

using spall::Real;
using spall::Vec3;
namespace kernels = spall::kernels;

namespace {

// The lattice point (i, j, k) in Dim dimensions (unused components zero).
template <int Dim>
Vec3 lattice_point(int i, int j, int k, Real spacing) {
  return spacing * Vec3(i, Dim > 1 ? j : 0, Dim > 2 ? k : 0);
}

template <int Dim, typename Visit>
void for_each_lattice_point(int n, Visit&& visit) {
  for (int i = -n; i <= n; ++i)
    for (int j = (Dim > 1 ? -n : 0); j <= (Dim > 1 ? n : 0); ++j)
      for (int k = (Dim > 2 ? -n : 0); k <= (Dim > 2 ? n : 0); ++k) visit(i, j, k);
}

template <typename K>
class KernelProperties : public ::testing::Test {};

using AllKernels =
    ::testing::Types<kernels::CubicSpline<1>, kernels::CubicSpline<2>, kernels::CubicSpline<3>,
                     kernels::QuinticSpline<1>, kernels::QuinticSpline<2>, kernels::QuinticSpline<3>,
                     kernels::WendlandC2<1>, kernels::WendlandC2<2>, kernels::WendlandC2<3>>;
TYPED_TEST_SUITE(KernelProperties, AllKernels);

}  // namespace

// Riemann sum over a lattice with H/dx = 40: exact to well below 1e-4 for kernels that are C2 at
// the support edge (all three are).
TYPED_TEST(KernelProperties, IntegratesToOne) {
  using K = TypeParam;
  constexpr int Dim = K::dimension;
  const Real H = 1.7, dx = H / 40;
  Real sum = 0;
  for_each_lattice_point<Dim>(41, [&](int i, int j, int k) {
    sum += K::value(lattice_point<Dim>(i, j, k, dx).norm(), H);
  });
  EXPECT_NEAR(sum * std::pow(dx, Dim), 1.0, 1e-4);
}

TYPED_TEST(KernelProperties, HasCompactSupport) {
  using K = TypeParam;
  const Real H = 0.8;
  EXPECT_GT(K::value(0.999 * H, H), 0.0);
  EXPECT_EQ(K::value(H, H), 0.0);
  EXPECT_EQ(K::value(1.3 * H, H), 0.0);
  EXPECT_EQ(K::derivative(H, H), 0.0);
  EXPECT_EQ(K::derivative(2 * H, H), 0.0);
}

TYPED_TEST(KernelProperties, DecreasesAndMatchesItsDerivative) {
  using K = TypeParam;
  const Real H = 1.3, e = 1e-6;
  for (Real q = 0.02; q < 1; q += 0.0625) {
    const Real r = q * H;
    const Real fd = (K::value(r + e, H) - K::value(r - e, H)) / (2 * e);
    EXPECT_NEAR(K::derivative(r, H), fd, 1e-6 * std::abs(fd) + 1e-9) << "q = " << q;
    EXPECT_LT(K::derivative(r, H), 0.0) << "q = " << q;
  }
}

// The pair loops' gradient_factor(r, 1/r, 1/H) is derivative(r, H) / r rewritten without a
// division: equal to a few rounding errors (1e-13 relative) over the whole support.
TYPED_TEST(KernelProperties, GradientFactorIsTheDerivativeOverR) {
  using K = TypeParam;
  const Real H = 1.3;
  for (Real q = 0.01; q < 1; q += 0.0307) {
    const Real r = q * H;
    const Real expected = K::derivative(r, H) / r;
    EXPECT_NEAR(K::gradient_factor(r, 1 / r, 1 / H), expected, 1e-13 * std::abs(expected)) << "q = " << q;
  }
}

TYPED_TEST(KernelProperties, GradientIsExactlyAntisymmetric) {
  using K = TypeParam;
  constexpr int Dim = K::dimension;
  const Vec3 xa = lattice_point<Dim>(1, -3, 5, 0.1) + Vec3(0.013, 0, 0);
  const Vec3 xb = lattice_point<Dim>(4, 1, 2, 0.1);
  const Vec3 xab = xa - xb, xba = xb - xa;
  const Vec3 gab = K::gradient(xab, xab.norm(), 1.0);
  const Vec3 gba = K::gradient(xba, xba.norm(), 1.0);
  EXPECT_EQ(gab, -gba);  // bitwise: pair forces cancel exactly
  EXPECT_LT(gab.dot(xab), 0.0);
}

// sum_b V_b grad_a W_ab = 0 at an interior lattice point, and sum_b V_b (x_b - x_a) (x) grad W
// = I (the first moment that the gradient correction restores where it is not).
TYPED_TEST(KernelProperties, ZeroMeanGradientAndUnitFirstMomentOnALattice) {
  using K = TypeParam;
  constexpr int Dim = K::dimension;
  const Real dx = 0.1, H = 2.4 * dx, volume = std::pow(dx, Dim);
  Vec3 sum = Vec3::Zero();
  spall::Mat3 moment = spall::Mat3::Zero();
  for_each_lattice_point<Dim>(3, [&](int i, int j, int k) {
    const Vec3 xab = -lattice_point<Dim>(i, j, k, dx);
    const Vec3 grad = K::gradient(xab, xab.norm(), H);
    sum += volume * grad;
    moment -= volume * xab * grad.transpose();
  });
  EXPECT_LT(sum.norm(), 1e-12);
  // Coarse lattice (H/dx = 2.4): the moment is the identity only to a few per cent.
  for (int d = 0; d < Dim; ++d) EXPECT_NEAR(moment(d, d), 1.0, 0.05) << "d = " << d;
}

TEST(CubicSpline, MatchesSeedEquation3) {
  using K = kernels::CubicSpline<3>;
  const Real H = 2.0, s = 8 / M_PI / (H * H * H);
  EXPECT_DOUBLE_EQ(K::value(0, H), s);                        // 6q^3 - 6q^2 + 1 at q = 0
  EXPECT_DOUBLE_EQ(K::value(0.5 * H, H), s * 0.25);           // both branches give 1/4 at q = 1/2
  EXPECT_DOUBLE_EQ(K::value(0.75 * H, H), s * 2 * 0.015625);  // 2 (1 - q)^3
}

TEST(KernelDispatch, HandsTheRequestedKernelAndDimension) {
  using kernels::KernelKind;
  auto dim = [](auto k) { return decltype(k)::dimension; };
  EXPECT_EQ(kernels::with_kernel(KernelKind::wendland_c2, 2, dim), 2);
  EXPECT_EQ(kernels::with_kernel(KernelKind::quintic_spline, 3, dim), 3);
  const Real w = kernels::with_kernel(KernelKind::wendland_c2, 3, [](auto k) {
    return decltype(k)::value(0.0, 1.0);
  });
  EXPECT_DOUBLE_EQ(w, 21 / (2 * M_PI));
}

// H times the integral of |grad W| (the stable step's reference row sum, docs/THEORY.md §3). In 1D
// W decreases from W(0) to 0 on each side, so the integral is 2 W(0) exactly, for every kernel.
TYPED_TEST(KernelProperties, GradientNormIntegralIn1DIsTwiceTheCentralValue) {
  using K = TypeParam;
  if constexpr (K::dimension == 1) {
    EXPECT_NEAR(kernels::gradient_norm_integral<K>(), 2 * K::value(0, 1), 1e-6);
  }
}

// The cubic spline of seed 000 eq. 3, integrated by hand: |f'(q)| = 12q - 18q^2 below 1/2 and
// 6(1 - q)^2 above, so H int |grad W| dV = sigma int_0^1 |f'(q)| S(q) dq with the shell S = 2 pi q
// (2D) or 4 pi q^2 (3D): 0.375 * 2 pi * 40/(7 pi) = 30/7 and 0.175 * 4 pi * 8/pi = 28/5.
TEST(KernelGradientNormIntegral, CubicSplineByHand) {
  EXPECT_NEAR(kernels::gradient_norm_integral<kernels::CubicSpline<2>>(), 30.0 / 7, 1e-6);
  EXPECT_NEAR(kernels::gradient_norm_integral<kernels::CubicSpline<3>>(), 28.0 / 5, 1e-6);
}

// The fastest acoustic mode of weakly compressible SPH, w = c max_k k W^(k) (the fluid's stable
// step). In 1D the cubic spline of support H is the B-spline M4 of spacing H/4, whose transform is
// sinc^4(k H / 4): H max_k k W^(k) = max_u 4 u sinc^4(u), found here by a fine scan of the closed
// form. In 3D, by the radial transform of each kernel (computed independently with scipy, 4 096
// steps in r, k to 40 / H): cubic spline 2.1871, quintic 2.6413, Wendland C2 2.3227.
TEST(KernelFastestAcousticMode, CubicSplineIn1DIsTheBSplinesClosedForm) {
  Real closed_form = 0;
  for (int i = 1; i <= 200000; ++i) {
    const Real u = i * 1e-5, sinc = std::sin(u) / u;
    closed_form = std::max(closed_form, 4 * u * sinc * sinc * sinc * sinc);
  }
  // The scan's k steps of 1/20 lie within 0.025 / H of the peak: a relative error of about 1e-4.
  EXPECT_NEAR(kernels::fastest_acoustic_mode<kernels::CubicSpline<1>>(), closed_form, 1e-3 * closed_form);
}

TEST(KernelFastestAcousticMode, ThreeDimensionalKernelsMatchAnIndependentTransform) {
  EXPECT_NEAR(kernels::fastest_acoustic_mode<kernels::CubicSpline<3>>(), 2.1871, 2e-3);
  EXPECT_NEAR(kernels::fastest_acoustic_mode<kernels::QuinticSpline<3>>(), 2.6413, 2e-3);
  EXPECT_NEAR(kernels::fastest_acoustic_mode<kernels::WendlandC2<3>>(), 2.3227, 2e-3);
}
