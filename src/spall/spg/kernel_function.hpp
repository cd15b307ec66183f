#pragma once
// The kernel (window) functions of the RK shape functions, one per *SECTION_SOLID_SPG ISPLINE:
//   0  cubic B-spline, cubical (tensor-product) support:  phi(z_x) phi(z_y) phi(z_z), z_i = |y_i| / a_i
//   1  quadratic B-spline, cubical support:               same product with the quadratic spline
//   2  cubic B-spline, spherical support:                 phi(z), z = |(y_x / a_x, y_y / a_y, y_z / a_z)|
// with y = x - x_I and a_I the support size of particle I per direction (a sphere when the three
// sizes are equal). Every window vanishes for z >= 1. The scale of the window does not matter:
// the RK correction cancels it.
//   cubic:      phi(z) = 2/3 - 4 z^2 + 4 z^3 (z <= 1/2),  4/3 (1 - z)^3 (1/2 < z <= 1)
//   quadratic:  phi(z) = 3/4 - 9/4 z^2 (z <= 1/3),       9/8 (1 - z)^2 (1/3 < z <= 1)
// (the cubic and quadratic B-splines of unit support; spg.md §2.2 names the options, the formulas
// are the standard B-splines).
#include <cmath>

#include "spall/core/types.hpp"

namespace spall::spg {

enum class KernelShape { cubic_cubical = 0, quadratic_cubical = 1, cubic_spherical = 2 };

struct SplineValue {
  Real value = 0;
  Real derivative = 0;  // d phi / dz
};

inline SplineValue cubic_spline(Real z) {
  if (z >= 1) return {};
  if (z <= Real(0.5)) return {Real(2) / 3 - 4 * z * z + 4 * z * z * z, -8 * z + 12 * z * z};
  const Real t = 1 - z;
  return {Real(4) / 3 * t * t * t, -4 * t * t};
}

inline SplineValue quadratic_spline(Real z) {
  if (z >= 1) return {};
  if (z <= Real(1) / 3) return {Real(0.75) - Real(2.25) * z * z, Real(-4.5) * z};
  const Real t = 1 - z;
  return {Real(1.125) * t * t, Real(-2.25) * t};
}

struct KernelValue {
  Real value = 0;
  Vec3 gradient = Vec3::Zero();  // with respect to the evaluation point x (y = x - x_I)
};

// phi_a(y) and its gradient with respect to x, for support sizes a (all > 0).
inline KernelValue kernel_value(KernelShape shape, const Vec3& y, const Vec3& a) {
  KernelValue k;
  if (shape == KernelShape::cubic_spherical) {
    const Vec3 s = y.cwiseQuotient(a);
    const Real z = s.norm();
    const SplineValue p = cubic_spline(z);
    k.value = p.value;
    // d z / d x_i = s_i / (a_i z); the derivative of phi vanishes at z = 0.
    if (z > 0 && p.derivative != 0) k.gradient = (p.derivative / z) * s.cwiseQuotient(a);
    return k;
  }
  SplineValue p[3];
  for (int i = 0; i < 3; ++i) {
    const Real z = std::abs(y[i]) / a[i];
    p[i] = shape == KernelShape::cubic_cubical ? cubic_spline(z) : quadratic_spline(z);
    if (p[i].value == 0) return k;
  }
  k.value = p[0].value * p[1].value * p[2].value;
  for (int i = 0; i < 3; ++i) {
    const Real sign = y[i] > 0 ? 1 : (y[i] < 0 ? -1 : 0);
    const Real d = p[i].derivative * sign / a[i];
    k.gradient[i] = d * p[(i + 1) % 3].value * p[(i + 2) % 3].value;
  }
  return k;
}

// The largest distance |y| at which phi_a(y) can be non-zero: the corner of the cubical support,
// or the largest semi-axis of the spherical (ellipsoidal) one.
inline Real support_radius(KernelShape shape, const Vec3& a) {
  return shape == KernelShape::cubic_spherical ? a.maxCoeff() : a.norm();
}

}  // namespace spall::spg
