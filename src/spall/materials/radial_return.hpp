#pragma once
// J2 (von Mises) return mapping shared by the plastic materials (Wilkins 1964; Simo & Hughes,
// Computational Inelasticity, 1998, §3.3). For a trial deviator xi (relative to the back stress)
// with equivalent stress q = sqrt(3/2 xi:xi), a plastic increment dp of effective plastic strain
// moves the stress back along xi / q by 3G dp (and the back stress forward by H_kin dp), so that
//   g(dp) = q - stiffness dp - yield(dp) = 0,   stiffness = 3G + H_kin,
// where yield(dp) is the radius of the yield surface after the increment. g decreases in dp,
// g(0) > 0 when the trial is outside, and g(q / stiffness) = -yield <= 0: the root is bracketed.
#include <cmath>
#include <limits>

#include "spall/core/types.hpp"

namespace spall::materials {

// The yield-surface radius after a plastic increment dp, its derivative d(radius)/d(dp) and, where
// the radius is smooth in dp, its second derivative (0: the return takes Newton's steps there).
struct YieldValue {
  Real stress = 0;
  Real slope = 0;
  Real curvature = 0;
};

// Deviatoric part of a symmetric tensor.
inline Mat3 deviator(const Mat3& a) { return a - (a.trace() / 3) * Mat3::Identity(); }

// The square 2/3 D:D of the effective strain rate of a rate of deformation D.
inline Real effective_strain_rate_squared(const Mat3& d) { return Real(2) / 3 * d.cwiseProduct(d).sum(); }

// Effective strain rate sqrt(2/3 D:D) of a rate of deformation D.
inline Real effective_strain_rate(const Mat3& d) { return std::sqrt(effective_strain_rate_squared(d)); }

// The root dp of g above, by Halley's method where yield(dp) gives a curvature and Newton's
// otherwise, kept inside the bracket. Halley's step converges cubically: from the first guess of
// johnson_cook.cpp an instrumented Taylor bar (10^5 particles, 5 us past impact) took 2.6
// evaluations per return, against 4.2 by Newton's steps. A step from above the root
// that falls below the bracket is taken in ln dp instead, dp exp(step / dp): a rate term
// C ln(dp / dt) (Johnson-Cook) makes g steep at small dp, where steps in dp overshoot below zero
// and bisection would creep down by halves (an instrumented Taylor bar: 3.6 evaluations per
// return before, 2.9 with the first guess of johnson_cook.cpp). Bisection when that step too
// leaves the bracket. It lands on the yield surface to round-off: |g| <= a few ulp of q, or the
// bracket has shrunk to one ulp. `yield(dp)` returns a YieldValue. The first guess is the
// increment of perfect plasticity at the yield stress `guess_yield`, by default yield(0).stress;
// a caller may know a closer one (the elastic check's, or one at the current strain rate).
template <class Yield>
Real plastic_strain_increment(Real q_trial, Real stiffness, const Yield& yield, Real guess_yield = -1) {
  constexpr Real epsilon = std::numeric_limits<Real>::epsilon();
  Real low = 0;
  Real high = q_trial / stiffness;
  Real dp = (q_trial - (guess_yield >= 0 ? guess_yield : yield(Real(0)).stress)) / stiffness;
  if (!(dp > low && dp < high)) dp = Real(0.5) * high;
  for (int iteration = 0; iteration < 200; ++iteration) {
    const YieldValue y = yield(dp);
    const Real g = q_trial - stiffness * dp - y.stress;
    if (g > 0)
      low = dp;
    else
      high = dp;
    if (std::abs(g) <= 4 * epsilon * q_trial || high - low <= 2 * epsilon * high) break;
    // Newton's step g / s with s = -g' = stiffness + slope, or Halley's, 2 g s / (2 s^2 - g g'')
    // with g'' = -curvature, where that is at most twice Newton's. Halley's error is of order
    // step^3 / dp^2, so that a step below 1e-6 dp lands within about 1e-18 dp of the root: it is
    // taken without evaluating g again. One division either way: the loop is a chain of dependent
    // operations.
    const Real s = stiffness + y.slope;
    const Real halley_denominator = 2 * s * s + g * y.curvature;
    const bool halley = y.curvature != 0 && halley_denominator > s * s;
    const Real step = halley ? 2 * g * s / halley_denominator : g / s;
    Real next = dp + step;
    if (halley && std::abs(step) <= Real(1e-6) * dp && next > low && next < high) return next;
    if (!(next > low) && g < 0) next = dp * std::exp(g / (dp * s));  // ln dp step
    if (!(next > low && next < high)) next = Real(0.5) * (low + high);
    dp = next;
  }
  return dp;
}

}  // namespace spall::materials
