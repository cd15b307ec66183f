#pragma once
// Wendland C2 kernel (Wendland 1995; normalisations from Dehnen & Aly 2012), support radius H,
// s = r / H:
//   2D, 3D: W = sigma / H^d (1 - s)^4 (1 + 4 s),  sigma = 7/pi (2D), 21/(2 pi) (3D)
//   1D:     W = sigma / H   (1 - s)^3 (1 + 3 s),  sigma = 5/4
// It has no negative Fourier modes, so it does not pair particles (Dehnen & Aly 2012).
#include <numbers>

#include "spall/core/simd.hpp"
#include "spall/kernels/support_power.hpp"

namespace spall::kernels {

template <int Dim>
struct WendlandC2 {
  static_assert(Dim >= 1 && Dim <= 3);
  static constexpr int dimension = Dim;

  static constexpr Real normalisation() {
    constexpr Real pi = std::numbers::pi_v<Real>;
    if constexpr (Dim == 1) return Real(5) / 4;
    if constexpr (Dim == 2) return Real(7) / pi;
    return Real(21) / (2 * pi);
  }

  static Real power(Real support) { return support_power<Dim>(support); }

  static Real value(Real r, Real support) {
    const Real s = r / support;
    if (s >= 1) return 0;
    const Real u = 1 - s;
    if constexpr (Dim == 1) return normalisation() / support * u * u * u * (1 + 3 * s);
    return normalisation() / power(support) * u * u * u * u * (1 + 4 * s);
  }

  static Real derivative(Real r, Real support) {
    const Real s = r / support;
    if (s >= 1) return 0;
    const Real u = 1 - s;
    if constexpr (Dim == 1) return normalisation() / (support * support) * (-12 * s * u * u);
    return normalisation() / (power(support) * support) * (-20 * s * u * u * u);
  }

  // (dW/dr) / r for r < H, from 1/H: the factor s = r/H of the derivative cancels the 1/r, which
  // is not needed (the argument is there for the pair loops' common form; T = Real or
  // simd::Pack).
  template <typename T>
  static T gradient_factor(T r, T /*inverse_r*/, T inverse_support) {
    const T u = T(1) - r * inverse_support;
    const T i2 = inverse_support * inverse_support;
    if constexpr (Dim == 1) return T(normalisation()) * i2 * inverse_support * (T(-12) * u * u);
    return T(normalisation()) * support_power<Dim>(inverse_support) * i2 * (T(-20) * u * u * u);
  }

  static Vec3 gradient(const Vec3& xab, Real r, Real support) {
    if (r <= 0 || r >= support) return Vec3::Zero();
    return gradient_factor(r, 1 / r, 1 / support) * xab;
  }
};

}  // namespace spall::kernels
