#pragma once
// *MAT_PLASTIC_KINEMATIC (003): von Mises plasticity with bilinear hardening, mixed between
// isotropic and kinematic by BETA (LS-DYNA keyword manual; Krieg & Key 1976):
//   yield radius  R = [1 + (rate/SRC)^(1/SRP)] (SIGY + BETA Ep eps_p),
//   back stress   d(alpha) = (1 - BETA) Ep d(eps_p) n,   n = xi / q  (Prager/Ziegler),
//   Ep = E ETAN / (E - ETAN), the plastic hardening modulus.
// BETA = 1 is isotropic hardening, BETA = 0 kinematic. The rate is the effective total strain
// rate sqrt(2/3 D:D) of the step (VP = 0: the yield stress is scaled).
#include "spall/materials/cowper_symonds.hpp"
#include "spall/materials/point_state.hpp"

namespace spall::materials {

struct PlasticKinematic {
  Real yield_stress = 0;       // SIGY
  Real hardening_modulus = 0;  // Ep
  Real beta = 0;               // BETA
  CowperSymonds rate;          // SRC, SRP
  Real failure_strain = 0;     // FS; 0: no failure
};

// Whether the model moves a back stress (BETA < 1 with hardening): its points need one.
inline bool moves_back_stress(const PlasticKinematic& model) {
  return model.beta < 1 && model.hardening_modulus != 0;
}

// Elastic predictor S + 2G dt dev(D), then the return. Returns the plastic work per unit volume
// of the step, S_new : d(eps^p). `back_stress`: the point's alpha, required when
// moves_back_stress(model) (std::logic_error otherwise), else may be null (alpha = 0).
Real update_plastic_kinematic(const PlasticKinematic& model, Real shear_modulus, PointState& state,
                              const Mat3& strain_rate, Real dt, Mat3* back_stress);

}  // namespace spall::materials
