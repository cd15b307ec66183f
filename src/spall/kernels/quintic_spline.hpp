#pragma once
// Quintic spline (Morris, Fox & Zhu 1997), rescaled to the support radius H used by every Spall
// kernel, so that *SECTION_SPH CSLH gives the same neighbours whatever SPHKERN says. In Morris'
// variable t = 3 r / H (support t <= 3):
//   W = sigma / (H/3)^d * [ (3 - t)^5 - 6 (2 - t)^5 + 15 (1 - t)^5 ],  each bracket only while > 0,
// sigma = 1/120 (1D), 7/(478 pi) (2D), 1/(120 pi) (3D) (the lattice-integral test checks each).
#include <numbers>

#include "spall/core/simd.hpp"
#include "spall/kernels/support_power.hpp"

namespace spall::kernels {

template <int Dim>
struct QuinticSpline {
  static_assert(Dim >= 1 && Dim <= 3);
  static constexpr int dimension = Dim;

  static constexpr Real normalisation() {
    constexpr Real pi = std::numbers::pi_v<Real>;
    if constexpr (Dim == 1) return Real(3) / 120;                      // 3^1 / 120
    if constexpr (Dim == 2) return Real(9) * 7 / (478 * pi);           // 3^2 * 7 / (478 pi)
    return Real(27) / (120 * pi);                                      // 3^3 / (120 pi)
  }

  static Real power(Real support) { return support_power<Dim>(support); }

  static Real value(Real r, Real support) {
    const Real t = 3 * r / support;
    if (t >= 3) return 0;
    auto p5 = [](Real u) { return u > 0 ? u * u * u * u * u : Real(0); };
    return normalisation() / power(support) * (p5(3 - t) - 6 * p5(2 - t) + 15 * p5(1 - t));
  }

  static Real derivative(Real r, Real support) {
    const Real t = 3 * r / support;
    if (t >= 3) return 0;
    auto p4 = [](Real u) { return u > 0 ? u * u * u * u : Real(0); };
    return normalisation() / (power(support) * support) * 3 *
           (-5 * p4(3 - t) + 30 * p4(2 - t) - 75 * p4(1 - t));
  }

  // (dW/dr) / r for 0 < r < H, from 1/r and 1/H without a division (the pair loops' form; T = Real
  // or simd::Pack). A bracket (u)^4 counts only while u > 0: max(u, 0)^4.
  template <typename T>
  static T gradient_factor(T r, T inverse_r, T inverse_support) {
    using simd::max;
    const T t = T(3) * r * inverse_support;
    auto p4 = [](T u) {
      const T m = max(u, T(0));
      return m * m * m * m;
    };
    return T(normalisation()) * support_power<Dim>(inverse_support) * inverse_support * T(3) *
           (T(-5) * p4(T(3) - t) + T(30) * p4(T(2) - t) - T(75) * p4(T(1) - t)) * inverse_r;
  }

  static Vec3 gradient(const Vec3& xab, Real r, Real support) {
    if (r <= 0 || r >= support) return Vec3::Zero();
    return gradient_factor(r, 1 / r, 1 / support) * xab;
  }
};

}  // namespace spall::kernels
