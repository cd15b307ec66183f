#pragma once
// The kernel a *SECTION_SPH asks for (SPHKERN), and a dispatcher that hands a computation the
// kernel type at compile time so that the pair loops inline it.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <stdexcept>

#include "spall/kernels/cubic_spline.hpp"
#include "spall/kernels/quintic_spline.hpp"
#include "spall/kernels/wendland_c2.hpp"

namespace spall::kernels {

// SPHKERN 0 and 1 are LS-DYNA's codes; 4 is a Spall extension (LS-DYNA's 2 quadratic and
// 3 quartic are not implemented).
enum class KernelKind { cubic_spline = 0, quintic_spline = 1, wendland_c2 = 4 };

// The kernel of a *SECTION_SPH SPHKERN code, if Spall has it; kernel_codes names those it has,
// for the message that refuses another.
inline std::optional<KernelKind> kernel_of_code(int sphkern) {
  switch (sphkern) {
    case 0: return KernelKind::cubic_spline;
    case 1: return KernelKind::quintic_spline;
    case 4: return KernelKind::wendland_c2;
    default: return std::nullopt;
  }
}
inline constexpr const char* kernel_codes = "0 cubic spline, 1 quintic spline, 4 Wendland C2";

// Calls f(K{}) with K the kernel of `kind` in `dimension` (2 or 3) space dimensions.
template <typename F>
decltype(auto) with_kernel(KernelKind kind, int dimension, F&& f) {
  switch (kind) {
    case KernelKind::cubic_spline:
      return dimension == 2 ? f(CubicSpline<2>{}) : f(CubicSpline<3>{});
    case KernelKind::quintic_spline:
      return dimension == 2 ? f(QuinticSpline<2>{}) : f(QuinticSpline<3>{});
    case KernelKind::wendland_c2:
      return dimension == 2 ? f(WendlandC2<2>{}) : f(WendlandC2<3>{});
  }
  throw std::logic_error("with_kernel: unknown kernel");
}

// H times the integral of |grad W| over the support: H sum_b V_b |grad_a W_ab| for a full support
// of particles, the row sum of the plain SPH gradient operator that the SPH solid's stable step
// compares with (docs/THEORY.md §3). Midpoint rule in r = q H, H = 1 (the integrand is a
// piecewise polynomial: the error is below 1e-6).
template <typename Kernel>
Real gradient_norm_integral() {
  constexpr int steps = 4096;
  constexpr Real pi = std::numbers::pi_v<Real>;
  Real sum = 0;
  for (int i = 0; i < steps; ++i) {
    const Real r = (i + Real(0.5)) / steps;
    const Real shell = Kernel::dimension == 3 ? 4 * pi * r * r : Kernel::dimension == 2 ? 2 * pi * r : 2;
    sum += std::abs(Kernel::derivative(r, 1)) * shell;
  }
  return sum / steps;
}

// H max_k k W^(k), W^ the kernel's Fourier transform in its dimension: the continuity and
// pressure-gradient sums of weakly compressible SPH each differentiate the field smoothed by W,
// so an acoustic wave of wavenumber k runs at w = c k W^(k), and this is the fastest mode's w in
// units of c / H (3D: cubic spline 2.19, quintic 2.64, Wendland C2 2.32). The transform by the
// midpoint rule in r = q H, H = 1 (512 steps: W is a piecewise polynomial), the maximum over k up
// to 12 / H in steps of 1 / 20 (the maxima lie at k H = 3.5 to 4.3).
template <typename Kernel>
Real fastest_acoustic_mode() {
  constexpr int steps = 512;
  constexpr Real pi = std::numbers::pi_v<Real>;
  Real fastest = 0;
  for (int j = 1; j <= 240; ++j) {
    const Real k = j / Real(20);
    Real transform = 0;
    for (int i = 0; i < steps; ++i) {
      const Real r = (i + Real(0.5)) / steps;
      const Real w = Kernel::value(r, 1);
      if constexpr (Kernel::dimension == 3) transform += 4 * pi * w * r * std::sin(k * r) / k;
      if constexpr (Kernel::dimension == 2) transform += 2 * pi * w * r * std::cyl_bessel_j(Real(0), k * r);
      if constexpr (Kernel::dimension == 1) transform += 2 * w * std::cos(k * r);
    }
    fastest = std::max(fastest, k * transform / steps);
  }
  return fastest;
}

}  // namespace spall::kernels
