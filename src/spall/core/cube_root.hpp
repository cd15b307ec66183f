#pragma once
// x^(1/3) for the length scales updated at every step (the SPH smoothing length
// h = h0 (rho0 / rho)^(1/3), SPG's spacing l = l0 (V / V0)^(1/3)), in multiplications and fused
// multiply-adds only. glibc's cbrt takes about 125 instructions with three calls (frexp, ldexp,
// scalbn) and is up to 3 ulp off the correctly rounded cube root; this one takes about 35 and is
// within 1 ulp (tests/unit/test_cube_root.cpp).
#include <bit>
#include <cmath>
#include <cstdint>

namespace spall {

inline double cube_root(double x) {
  // Zero, negative, subnormal, huge, infinite or NaN arguments: the library's answer.
  if (!(x >= 0x1p-1000 && x <= 0x1p1000)) return std::cbrt(x);
  // r ~ x^(-1/3) from the bit pattern (the exponent divided by -3; the constant, found by search,
  // keeps the start within 3.5 % of the root), then three Newton steps r <- r + r (1 - x r^3) / 3,
  // which need no division: 3.5e-2 -> 2.3e-3 -> 1.1e-5 -> 2.3e-10 relative error.
  double r = std::bit_cast<double>(0x553ef00000000000ull - std::bit_cast<std::uint64_t>(x) / 3);
  for (int step = 0; step < 3; ++step) {
    const double defect = std::fma(-x * r, r * r, 1.0);  // 1 - x r^3
    r = std::fma(r * defect, 1.0 / 3, r);
  }
  // y = x r^2 ~ x^(1/3), and one Newton step on y^3 = x, y <- y - (y^3 - x) / (3 y^2), with
  // 1 / y^2 ~ r^2 and y^3 - x taken exactly (y^2 and y^3 split into a rounded part and its
  // rounding error by fma), so that the step's own rounding is the only one left.
  const double y = x * r * r;
  const double y2 = y * y, y2_error = std::fma(y, y, -y2);
  const double y3 = y2 * y, y3_error = std::fma(y2, y, -y3);
  const double residual = (y3 - x) + std::fma(y2_error, y, y3_error);
  return std::fma(-residual * (1.0 / 3), r * r, y);
}

}  // namespace spall
