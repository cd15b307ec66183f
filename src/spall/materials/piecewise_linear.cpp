#include "spall/materials/piecewise_linear.hpp"

#include <algorithm>

#include "spall/materials/elastic.hpp"

namespace spall::materials {

HardeningCurve::HardeningCurve(std::vector<std::pair<Real, Real>> points)
    : points_(std::move(points)) {}

YieldValue HardeningCurve::at(Real plastic_strain) const {
  if (points_.size() == 1) return {points_.front().second, 0};
  // The segment [k, k+1] holding eps_p; the first or last one beyond the ends.
  auto upper = std::upper_bound(points_.begin(), points_.end(), plastic_strain,
                                [](Real x, const auto& point) { return x < point.first; });
  upper = std::clamp(upper, points_.begin() + 1, points_.end() - 1);
  const auto& [x0, y0] = *(upper - 1);
  const auto& [x1, y1] = *upper;
  const Real slope = (y1 - y0) / (x1 - x0);
  return {y0 + slope * (plastic_strain - x0), slope};
}

Real update_piecewise_linear(const PiecewiseLinear& model, Real shear_modulus, PointState& state,
                             const Mat3& strain_rate, Real dt) {
  const Mat3 trial = state.deviatoric_stress + 2 * shear_modulus * dt * deviator(strain_rate);
  const Real q = von_mises(trial);
  const Real rate_factor =
      model.rate.active()
          ? model.rate.factor(effective_strain_rate(model.deviatoric_rate ? deviator(strain_rate) : strain_rate))
          : Real(1);
  const auto yield = [&](Real dp) {
    const YieldValue y = model.curve.at(state.plastic_strain + dp);
    // A softening curve extrapolated below zero has lost all strength there.
    if (y.stress <= 0) return YieldValue{0, 0};
    return YieldValue{rate_factor * y.stress, rate_factor * y.slope};
  };
  if (q <= yield(0).stress) {
    state.deviatoric_stress = trial;
    return 0;
  }
  const Real dp = plastic_strain_increment(q, 3 * shear_modulus, yield);
  state.deviatoric_stress = trial * (1 - 3 * shear_modulus * dp / q);
  state.plastic_strain += dp;
  if (model.failure_strain > 0 && state.plastic_strain >= model.failure_strain) state.failed = true;
  return von_mises(state.deviatoric_stress) * dp;
}

}  // namespace spall::materials
