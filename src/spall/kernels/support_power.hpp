#pragma once
// H^d, the volume scale of a kernel of support H in d dimensions.
#include "spall/core/types.hpp"

namespace spall::kernels {

template <int Dim, typename T = Real>
constexpr T support_power(T support) {
  T p = support;
  for (int d = 1; d < Dim; ++d) p *= support;
  return p;
}

}  // namespace spall::kernels
