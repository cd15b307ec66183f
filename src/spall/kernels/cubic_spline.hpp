#pragma once
// Cubic spline kernel in the form of seed 000 eq. 3, written with the support radius H
// (W = 0 for r > H). LS-DYNA's smoothing length h is half of it: H = 2h.
//   W(q) = sigma / H^d * { 6q^3 - 6q^2 + 1   0 <= q <= 1/2
//                        { 2(1 - q)^3         1/2 < q <= 1,      q = r / H
// with sigma = 4/3 (1D), 40/(7 pi) (2D), 8/pi (3D), so that W integrates to one.
#include <numbers>

#include "spall/core/simd.hpp"
#include "spall/kernels/support_power.hpp"

namespace spall::kernels {

template <int Dim>
struct CubicSpline {
  static_assert(Dim >= 1 && Dim <= 3);
  static constexpr int dimension = Dim;

  static constexpr Real normalisation() {
    if constexpr (Dim == 1) return Real(4) / 3;
    if constexpr (Dim == 2) return Real(40) / (7 * std::numbers::pi_v<Real>);
    return Real(8) / std::numbers::pi_v<Real>;
  }

  static Real power(Real support) { return support_power<Dim>(support); }

  // W(r, H)
  static Real value(Real r, Real support) {
    const Real q = r / support;
    if (q >= 1) return 0;
    const Real s = normalisation() / power(support);
    if (q <= Real(0.5)) return s * (6 * q * q * q - 6 * q * q + 1);
    const Real t = 1 - q;
    return s * 2 * t * t * t;
  }

  // dW/dr(r, H)
  static Real derivative(Real r, Real support) {
    const Real q = r / support;
    if (q >= 1) return 0;
    const Real s = normalisation() / (power(support) * support);
    if (q <= Real(0.5)) return s * (18 * q * q - 12 * q);
    const Real t = 1 - q;
    return -s * 6 * t * t;
  }

  // (dW/dr) / r for 0 < r < H, from 1/r and 1/H without a division: the pair loops compute the
  // two reciprocals a pack of pairs at a time (T = simd::Pack). Inside q = 1/2 the 1/r cancels
  // against q = r/H.
  template <typename T>
  static T gradient_factor(T r, T inverse_r, T inverse_support) {
    using simd::select;
    const T q = r * inverse_support;
    const T s = T(normalisation()) * support_power<Dim>(inverse_support) * inverse_support;  // sigma / H^(d+1)
    const T near = s * inverse_support * (T(18) * q - T(12));
    const T t = T(1) - q;
    const T far = -s * T(6) * t * t * inverse_r;
    return select(q <= T(0.5), near, far);
  }

  // grad_a W(x_a - x_b, H) = dW/dr * (x_a - x_b) / r; exactly antisymmetric in a and b, because
  // r and the factor depend on |x_a - x_b| only. Zero at r = 0 and for r >= H.
  static Vec3 gradient(const Vec3& xab, Real r, Real support) {
    if (r <= 0 || r >= support) return Vec3::Zero();
    return gradient_factor(r, 1 / r, 1 / support) * xab;
  }
};

}  // namespace spall::kernels
