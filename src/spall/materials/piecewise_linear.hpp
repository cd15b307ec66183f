#pragma once
// *MAT_PIECEWISE_LINEAR_PLASTICITY (024): von Mises plasticity with isotropic hardening along a
// tabulated yield stress sigma_y(eps_p), scaled by Cowper-Symonds (LS-DYNA keyword manual):
//   yield radius R = [1 + (rate/C)^(1/P)] sigma_y(eps_p).
// The table comes from the curve LCSS, the EPS/ES points, or SIGY and ETAN (two points with
// slope Ep = E ETAN / (E - ETAN)). The rate is the effective total strain rate sqrt(2/3 D:D)
// (VP = 0) or that of dev(D) (VP = -1).
#include <utility>
#include <vector>

#include "spall/materials/cowper_symonds.hpp"
#include "spall/materials/point_state.hpp"
#include "spall/materials/radial_return.hpp"

namespace spall::materials {

// Piecewise-linear yield stress versus effective plastic strain, extended beyond its ends with
// the first and last slopes (LS-DYNA extrapolates MAT_024's curve; one point is a constant).
class HardeningCurve {
 public:
  HardeningCurve() = default;
  // Points (eps_p, sigma_y) with strictly increasing eps_p; at least one.
  explicit HardeningCurve(std::vector<std::pair<Real, Real>> points);

  // sigma_y and d(sigma_y)/d(eps_p) at eps_p (the slope of the segment to the right at a point).
  YieldValue at(Real plastic_strain) const;

 private:
  std::vector<std::pair<Real, Real>> points_;
};

struct PiecewiseLinear {
  HardeningCurve curve;
  CowperSymonds rate;            // C, P
  bool deviatoric_rate = false;  // VP = -1
  Real failure_strain = 0;       // FAIL; 0: no failure
};

// Elastic predictor S + 2G dt dev(D), then the return. Returns the plastic work per unit volume
// of the step, sigma_eq dp.
Real update_piecewise_linear(const PiecewiseLinear& model, Real shear_modulus, PointState& state,
                             const Mat3& strain_rate, Real dt);

}  // namespace spall::materials
