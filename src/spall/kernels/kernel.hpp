#pragma once
// The kernel a *SECTION_SPH asks for (SPHKERN), and a dispatcher that hands a computation the
// kernel type at compile time so that the pair loops inline it.
#include <stdexcept>

#include "spall/kernels/cubic_spline.hpp"
#include "spall/kernels/quintic_spline.hpp"
#include "spall/kernels/wendland_c2.hpp"

namespace spall::kernels {

// SPHKERN 0 and 1 are LS-DYNA's codes; 4 is a Spall extension (LS-DYNA's 2 quadratic and
// 3 quartic are not implemented).
enum class KernelKind { cubic_spline = 0, quintic_spline = 1, wendland_c2 = 4 };

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

}  // namespace spall::kernels
