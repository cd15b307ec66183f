#pragma once
// *MAT_JOHNSON_COOK (015) with RATEOP = 0 and VP = 0 (Johnson & Cook 1983, 1985; LS-DYNA
// keyword manual):
//   flow stress    sigma_y = (A + B eps_p^N) (1 + C ln rate*) (1 - T*^M)
//   failure strain eps_f   = [D1 + D2 exp(D3 sigma*)] [1 + D4 ln rate*] [1 + D5 T*], at least EFMIN
//   damage         D = sum d(eps_p) / eps_f; the point fails at D = 1
//   heating        dT = sigma_eq d(eps_p) / (rho CP): all plastic work becomes heat (adiabatic,
//                  as LS-DYNA's MAT_015 without a thermal solver)
// with rate* = max(eps_p-rate / EPSO, 1) so that the logarithms are never negative, the plastic
// strain rate being d(eps_p)/dt of the step; T* = (T - TR) / (TM - TR) kept in [0, 1]; and the
// stress triaxiality sigma* = sigma_m / sigma_eq = -p / sigma_eq (mean stress positive in
// tension, Johnson & Cook 1985), so that D3 < 0 lowers the failure strain in tension.
#include "spall/materials/point_state.hpp"

namespace spall::materials {

struct JohnsonCook {
  Real a = 0, b = 0, n = 0, c = 0, m = 0;
  Real melt_temperature = 0;  // TM
  Real room_temperature = 0;  // TR
  Real reference_rate = 0;    // EPSO
  Real heat_capacity = 0;     // CP (specific heat)
  Real d1 = 0, d2 = 0, d3 = 0, d4 = 0, d5 = 0;
  Real min_failure_strain = 1.0e-6;  // EFMIN
  bool erode_at_failure = true;      // EROD 0: an element whose damage reaches 1 is deleted

  // With D1 = D2 = 0 the failure strain is 0 everywhere: LS-DYNA's "no damage".
  bool damage() const { return d1 != 0 || d2 != 0; }
};

// T* = (T - TR) / (TM - TR), kept in [0, 1].
Real homologous_temperature(const JohnsonCook& model, Real temperature);
Real johnson_cook_flow_stress(const JohnsonCook& model, Real plastic_strain,
                              Real plastic_strain_rate, Real temperature);
Real johnson_cook_failure_strain(const JohnsonCook& model, Real triaxiality,
                                 Real plastic_strain_rate, Real temperature);

// Elastic predictor S + 2G dt dev(D), then the return: the rate term depends on the increment
// itself (rate = dp / dt), so the consistency equation is solved by Newton iteration. The
// temperature of the start of the step is used in the return, then raised by the plastic work.
// `density` is the current density (for the heating), `pressure` the current pressure (for the
// triaxiality). Returns the plastic work per unit volume of the step, sigma_eq dp.
Real update_johnson_cook(const JohnsonCook& model, Real shear_modulus, PointState& state,
                         const Mat3& strain_rate, Real dt, Real density, Real pressure);

}  // namespace spall::materials
