#include "spall/materials/johnson_cook.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include "spall/materials/elastic.hpp"
#include "spall/materials/radial_return.hpp"

namespace spall::materials {

namespace {

// ln(rate*) with rate* = max(rate / EPSO, 1).
Real log_rate_ratio(const JohnsonCook& model, Real plastic_strain_rate) {
  const Real ratio = plastic_strain_rate / model.reference_rate;
  return ratio > 1 ? std::log(ratio) : 0;
}

// The Newton steps of the return move dp by small fractions of their first value: there
// x^N and ln x are taken from short series about the last point where pow or log was called, not
// by pow and log again (they were two thirds of the return's cost on the Taylor bar). Within a
// relative distance of 2^-7 the truncation is below 1e-16 relative: |C(N, 7)| u^7 for 0 < N <= 2,
// and u^8 / 8 (the reciprocal 1 / last adds an ulp to u, which the series scales down by u).
constexpr Real series_reach = 0x1p-7;

// ln(1 + u) to u^7, |u| <= series_reach, by Horner's rule.
Real log1p_series(Real u) {
  Real sum = 0;
  for (int k = 7; k >= 1; --k) sum = sum * u + ((k % 2) ? Real(1) : Real(-1)) / k;
  return sum * u;
}

// x^n, by the binomial series (to u^6, u = x / last - 1) about the last point where pow was called
// (the anchor, kept in the point's state from step to step) when x lies within series_reach of it
// (0 < n <= 2; otherwise always pow). The series is always about an exact pow, so that its error
// does not add up over the steps. The Newton loop is a chain of dependent operations, so the
// series' coefficients and 1 / last are ready beforehand.
class PowerNearLast {
 public:
  PowerNearLast(Real n, PowerAnchor anchor) : n_(n), series_(n > 0 && n <= 2) {
    if (series_) {
      static constexpr Real inverse[7] = {0, 1, 1.0 / 2, 1.0 / 3, 1.0 / 4, 1.0 / 5, 1.0 / 6};
      coefficient_[0] = 1;
      for (int k = 1; k <= 6; ++k) coefficient_[k] = coefficient_[k - 1] * (n - (k - 1)) * inverse[k];
    }
    rebase(anchor.base, anchor.power);
  }
  PowerAnchor anchor() const { return {last_, last_power_}; }
  Real operator()(Real x) {
    if (x == last_) return last_power_;  // an elastic step's, or eps_p = 0 and T* = 0
    const Real u = (x - last_) * inverse_last_;
    if (series_ && last_ > 0 && std::abs(u) <= series_reach) {
      Real sum = coefficient_[6];
      for (int k = 5; k >= 0; --k) sum = sum * u + coefficient_[k];
      return last_power_ * sum;
    }
    rebase(x, std::pow(x, n_));
    return last_power_;
  }

 private:
  void rebase(Real x, Real x_power) {
    last_ = x, last_power_ = x_power;
    inverse_last_ = x > 0 ? 1 / x : 0;
  }
  Real n_;
  bool series_;
  Real coefficient_[7] = {};  // C(n, k)
  Real last_ = 0, last_power_ = 0, inverse_last_ = 0;
};

// ln x (x > 0), by the series about the last point where log was called when x lies within
// series_reach of it.
class LogNearLast {
 public:
  Real operator()(Real x) {
    const Real u = (x - last_) * inverse_last_;
    if (last_ > 0 && std::abs(u) <= series_reach) return last_log_ + log1p_series(u);
    last_ = x, last_log_ = std::log(x), inverse_last_ = 1 / x;
    return last_log_;
  }

 private:
  Real last_ = 0, last_log_ = 0, inverse_last_ = 0;
};

// 1 - T*^M: the thermal softening factor.
Real thermal_factor(const JohnsonCook& model, Real temperature) {
  return 1 - std::pow(homologous_temperature(model, temperature), model.m);
}

}  // namespace

Real homologous_temperature(const JohnsonCook& model, Real temperature) {
  const Real t =
      (temperature - model.room_temperature) / (model.melt_temperature - model.room_temperature);
  return std::clamp(t, Real(0), Real(1));
}

Real johnson_cook_flow_stress(const JohnsonCook& model, Real plastic_strain,
                              Real plastic_strain_rate, Real temperature) {
  const Real rate_factor =
      model.c != 0 ? 1 + model.c * log_rate_ratio(model, plastic_strain_rate) : Real(1);
  return (model.a + model.b * std::pow(plastic_strain, model.n)) * rate_factor *
         thermal_factor(model, temperature);
}

Real johnson_cook_failure_strain(const JohnsonCook& model, Real triaxiality,
                                 Real plastic_strain_rate, Real temperature) {
  const Real rate_factor =
      model.d4 != 0 ? 1 + model.d4 * log_rate_ratio(model, plastic_strain_rate) : Real(1);
  const Real strain = (model.d1 + model.d2 * std::exp(model.d3 * triaxiality)) * rate_factor *
                      (1 + model.d5 * homologous_temperature(model, temperature));
  return std::max(strain, model.min_failure_strain);
}

Real update_johnson_cook(const JohnsonCook& model, Real shear_modulus, PointState& state,
                         const Mat3& strain_rate, Real dt, Real density, Real pressure) {
  const Mat3 rate_deviator = deviator(strain_rate);
  const Mat3 trial = state.deviatoric_stress + 2 * shear_modulus * dt * rate_deviator;
  const Real q = von_mises(trial);
  const Real eps = state.plastic_strain;
  // eps_p^N and T*^M by series about the state's anchors: pow only where they have moved away (two
  // pow calls a point and step were a twentieth of the Taylor bar's step).
  PowerNearLast strain_power_of(model.n, state.strain_power);
  PowerNearLast temperature_power_of(model.m, state.temperature_power);
  const Real thermal = 1 - temperature_power_of(homologous_temperature(model, state.temperature));
  state.temperature_power = temperature_power_of.anchor();
  // The elastic check first: sigma_y at dp = 0 has no rate term (rate* = 1).
  const Real eps_power = strain_power_of(eps);
  const Real yield_at_rest = (model.a + model.b * eps_power) * thermal;
  if (q <= yield_at_rest) {
    state.deviatoric_stress = trial;
    state.strain_power = strain_power_of.anchor();
    return 0;
  }
  LogNearLast log_of;
  const Real inverse_reference_increment = dt > 0 ? 1 / (dt * model.reference_rate) : 0;
  // sigma_y(eps + dp, dp / dt, T) and its derivative in dp.
  const auto yield = [&](Real dp) {
    const Real strain = eps + dp;
    const Real strain_power = strain_power_of(strain);
    const Real hardening = model.a + model.b * strain_power;
    Real hardening_slope = 0, hardening_curvature = 0;
    // d(B eps^N)/d eps = N B eps^N / eps, and the second derivative (N - 1) / eps times that: the
    // same power serves all three.
    if (model.b != 0 && model.n != 0) {
      if (strain > 0) {
        const Real inverse_strain = 1 / strain;
        hardening_slope = model.b * model.n * strain_power * inverse_strain;
        hardening_curvature = hardening_slope * (model.n - 1) * inverse_strain;
      } else {
        hardening_slope = model.n >= 1 ? (model.n == 1 ? model.b : Real(0))
                                       : std::numeric_limits<Real>::infinity();  // N < 1 at eps_p = 0
      }
    }
    Real rate_factor = 1;
    Real rate_slope = 0, rate_curvature = 0;
    bool smooth = strain > 0;
    if (model.c != 0 && dt > 0) {
      const Real ratio = dp * inverse_reference_increment;  // rate* = dp / dt / EPSO
      Real log_ratio = 0;
      if (ratio > 1) log_ratio = log_of(ratio);
      rate_factor = 1 + model.c * log_ratio;
      if (log_ratio > 0) {
        const Real inverse_dp = 1 / dp;
        rate_slope = model.c * inverse_dp, rate_curvature = -rate_slope * inverse_dp;
      }
      smooth = smooth && log_ratio > 0;  // not at or below the kink of max(rate*, 1)
    }
    const Real curvature = smooth ? (hardening_curvature * rate_factor + 2 * hardening_slope * rate_slope +
                                     hardening * rate_curvature) * thermal
                                  : 0;
    return YieldValue{hardening * rate_factor * thermal,
                      (hardening_slope * rate_factor + hardening * rate_slope) * thermal, curvature};
  };
  // First guess of the return: perfect plasticity at the yield stress of the current effective
  // strain rate, which plastic flow mostly carries; the rate term lifts it well above the stress at
  // rest (about 1.2 times for copper at 10^4 /s), and starting there saves Newton steps.
  Real guess_yield = yield_at_rest;
  if (model.c != 0 && dt > 0) {
    const Real rate = effective_strain_rate(rate_deviator);
    const Real at_rate = yield_at_rest * (1 + model.c * log_rate_ratio(model, rate));
    if (at_rate < q) guess_yield = at_rate;
    // The root dp also satisfies yield_at_rest (1 + C ln(dp / (dt EPSO))) <= q - 3G dp <= q
    // (hardening only adds), which bounds it by dp_rate below: near the onset of yield, where the
    // rate term carries the overstress, the guess above overshoots by an order of magnitude.
    if (model.c > 0 && yield_at_rest > 0) {
      const Real dp_rate = model.reference_rate * dt * std::exp((q / yield_at_rest - 1) / model.c);
      guess_yield = std::max(guess_yield, q - 3 * shear_modulus * dp_rate);
    }
  }
  const Real dp = plastic_strain_increment(q, 3 * shear_modulus, yield, guess_yield);
  state.deviatoric_stress = trial * (1 - 3 * shear_modulus * dp / q);
  const Real sigma_eq = von_mises(state.deviatoric_stress);
  const Real work = sigma_eq * dp;
  if (model.damage() && sigma_eq > 0) {
    const Real rate = dt > 0 ? dp / dt : 0;
    const Real failure_strain =
        johnson_cook_failure_strain(model, -pressure / sigma_eq, rate, state.temperature);
    state.damage += failure_strain > 0 ? dp / failure_strain : Real(1);
    if (state.damage >= 1) state.failed = true;
  }
  state.plastic_strain += dp;
  state.temperature += work / (density * model.heat_capacity);
  state.strain_power = strain_power_of.anchor();  // where the return last called pow
  return work;
}

}  // namespace spall::materials
