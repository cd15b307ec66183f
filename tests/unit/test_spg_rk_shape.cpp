// RK shape functions with a linear basis (spg.md §2.1) on irregular particle sets, for the three
// ISPLINE kernels: partition of unity and linear reproduction of Psi and of its gradient
// (sum Psi_I = 1, sum Psi_I x_I = x, sum grad Psi_I = 0, sum grad Psi_I (x) x_I = I) to 1e-10,
// the gradient against central differences of Psi, and the refusal of a singular moment matrix.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include "spall/spg/rk_shape.hpp"

using namespace spall;
using namespace spall::spg;

namespace {

// A jittered 5 x 5 x 5 lattice of spacing h (each particle moved by up to 0.3 h per axis).
std::vector<Vec3> irregular_cloud(Real h, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<Real> jitter(-0.3 * h, 0.3 * h);
  std::vector<Vec3> x;
  for (int k = 0; k < 5; ++k)
    for (int j = 0; j < 5; ++j)
      for (int i = 0; i < 5; ++i) x.emplace_back(h * i + jitter(rng), h * j + jitter(rng), h * k + jitter(rng));
  return x;
}

struct Evaluation {
  std::vector<Real> psi;
  std::vector<Vec3> grad;
  Real rcond = 0;
};

// Shape functions of all particles at point p, supports dilation * h with a per-particle spread.
Evaluation evaluate(KernelShape shape, const std::vector<Vec3>& x, const Vec3& p, Real h,
                    const Vec3& dilation) {
  std::vector<KernelSample> samples(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    samples[i].y = p - x[i];
    samples[i].support = dilation * h * (1.0 + 0.05 * Real(i % 3));  // supports differ per particle
  }
  Evaluation e;
  e.psi.resize(x.size());
  e.grad.resize(x.size());
  e.rcond = rk_shape_functions(shape, samples, dilation * h, e.psi, e.grad);
  return e;
}

const KernelShape all_shapes[] = {KernelShape::cubic_cubical, KernelShape::quadratic_cubical,
                                  KernelShape::cubic_spherical};

}  // namespace

TEST(SpgRkShape, PartitionOfUnityAndLinearReproductionOnIrregularParticles) {
  const Real h = 0.1;
  const auto x = irregular_cloud(h, 7);
  const Vec3 dilation(1.6, 1.5, 1.8);
  std::mt19937 rng(11);
  std::uniform_real_distribution<Real> inside(1.2 * h, 2.8 * h);
  for (KernelShape shape : all_shapes) {
    for (int trial = 0; trial < 20; ++trial) {
      // Evaluation points both at particles and between them.
      const Vec3 p = trial % 2 == 0 ? x[31 + trial] : Vec3(inside(rng), inside(rng), inside(rng));
      const Evaluation e = evaluate(shape, x, p, h, dilation);
      ASSERT_GE(e.rcond, min_moment_rcond);
      Real sum = 0;
      Vec3 first = Vec3::Zero(), dsum = Vec3::Zero();
      Mat3 dfirst = Mat3::Zero();
      for (std::size_t i = 0; i < x.size(); ++i) {
        sum += e.psi[i];
        first += e.psi[i] * x[i];
        dsum += e.grad[i];
        dfirst += x[i] * e.grad[i].transpose();  // d/dx_j sum Psi_I x_I,k = delta_jk
      }
      EXPECT_NEAR(sum, 1.0, 1e-10);
      EXPECT_LT((first - p).norm() / h, 1e-10);
      EXPECT_LT(dsum.norm() * h, 1e-10);
      EXPECT_LT((dfirst - Mat3::Identity()).norm(), 1e-10);
    }
  }
}

TEST(SpgRkShape, GradientMatchesCentralDifferences) {
  const Real h = 0.1;
  const auto x = irregular_cloud(h, 3);
  const Vec3 dilation(1.7, 1.7, 1.7);
  const Vec3 p(0.21 * 1, 0.19, 0.23);
  const Real step = 1e-6 * h;
  for (KernelShape shape : all_shapes) {
    const Evaluation e = evaluate(shape, x, p, h, dilation);
    for (int j = 0; j < 3; ++j) {
      const Evaluation plus = evaluate(shape, x, p + step * Vec3::Unit(j), h, dilation);
      const Evaluation minus = evaluate(shape, x, p - step * Vec3::Unit(j), h, dilation);
      for (std::size_t i = 0; i < x.size(); ++i) {
        const Real fd = (plus.psi[i] - minus.psi[i]) / (2 * step);
        // Central differences of a C1 function: error O(step^2) plus round-off ~1e-16 / step.
        EXPECT_NEAR(e.grad[i][j] * h, fd * h, 1e-6) << "shape " << int(shape) << " particle " << i;
      }
    }
  }
}

TEST(SpgRkShape, WindowMapMakesTheSupportFollowTheMaterial) {
  // A window evaluated through map = F^-1 on particles moved by the homogeneous deformation F
  // gives the same weights as the undeformed cloud, and the functions still reproduce linear
  // fields in the deformed configuration.
  const Real h = 0.1;
  const auto X = irregular_cloud(h, 5);
  Mat3 F;
  F << 1.8, 0.6, 0.0, 0.0, 0.7, 0.2, 0.1, 0.0, 1.2;
  const Vec3 P = X[62];
  std::vector<KernelSample> samples(X.size());
  for (std::size_t i = 0; i < X.size(); ++i) {
    samples[i].y = F * (P - X[i]);
    samples[i].support = Vec3::Constant(1.6 * h);
    samples[i].map = F.inverse();
  }
  std::vector<Real> psi(X.size());
  std::vector<Vec3> grad(X.size());
  ASSERT_GE(rk_shape_functions(KernelShape::cubic_cubical, samples, Vec3::Constant(1.6 * h), psi, grad), min_moment_rcond);
  Vec3 first = Vec3::Zero();
  Mat3 dfirst = Mat3::Zero();
  for (std::size_t i = 0; i < X.size(); ++i) {
    first += psi[i] * (F * X[i]);
    dfirst += (F * X[i]) * grad[i].transpose();
  }
  EXPECT_LT((first - F * P).norm() / h, 1e-10);
  EXPECT_LT((dfirst - Mat3::Identity()).norm(), 1e-10);
}

TEST(SpgRkShape, TooFewNeighboursGiveASingularMomentMatrix) {
  // Three particles in a line and a fourth in their plane: no linear field in 3D is determined.
  const Real h = 0.1;
  const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(h, 0, 0), Vec3(-h, 0, 0), Vec3(0, h, 0)};
  for (KernelShape shape : all_shapes) {
    const Evaluation e = evaluate(shape, x, x[0], h, Vec3::Constant(1.6));
    EXPECT_LT(e.rcond, min_moment_rcond);
  }
  // An isolated particle: the moment matrix has rank one. Shepard functions still exist.
  std::vector<KernelSample> alone(1);
  alone[0].support = Vec3::Constant(0.16);
  std::vector<Real> psi(1);
  std::vector<Vec3> grad(1);
  EXPECT_LT(rk_shape_functions(KernelShape::cubic_cubical, alone, Vec3::Constant(0.16), psi, grad), min_moment_rcond);
  ASSERT_TRUE(shepard_shape_functions(KernelShape::cubic_cubical, alone, psi, grad));
  EXPECT_EQ(psi[0], 1.0);
  EXPECT_EQ(grad[0], Vec3::Zero());
}

TEST(SpgRkShape, WindowsVanishOutsideTheirSupportAndPeakAtTheCentre) {
  const Vec3 a(0.2, 0.3, 0.4);
  for (KernelShape shape : all_shapes) {
    EXPECT_GT(kernel_value(shape, Vec3::Zero(), a).value, 0);
    EXPECT_EQ(kernel_value(shape, Vec3(0.2, 0, 0), a).value, 0);
    EXPECT_EQ(kernel_value(shape, Vec3(0, 0, -0.4), a).value, 0);
    EXPECT_EQ(kernel_value(shape, Vec3::Zero(), a).gradient, Vec3::Zero());
  }
  // Continuity of value and slope where the spline pieces meet (z = 1/2 cubic, z = 1/3 quadratic).
  EXPECT_NEAR(cubic_spline(0.5 - 1e-12).value, cubic_spline(0.5 + 1e-12).value, 1e-10);
  EXPECT_NEAR(cubic_spline(0.5 - 1e-12).derivative, cubic_spline(0.5 + 1e-12).derivative, 1e-10);
  EXPECT_NEAR(quadratic_spline(1.0 / 3 - 1e-12).value, quadratic_spline(1.0 / 3 + 1e-12).value, 1e-10);
  EXPECT_NEAR(quadratic_spline(1.0 / 3 - 1e-12).derivative, quadratic_spline(1.0 / 3 + 1e-12).derivative, 1e-10);
}
