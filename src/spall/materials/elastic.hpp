#pragma once
// Linear isotropic elasticity (*MAT_ELASTIC, MAT_001) as pure functions of the material constants.
#include <cmath>

#include "spall/core/types.hpp"

namespace spall::materials {

struct ElasticConstants {
  Real density = 0;       // rho_0
  Real young = 0;         // E
  Real poisson = 0;       // nu
  Real bulk_modulus = 0;  // K = E / (3 (1 - 2 nu))
  Real shear_modulus = 0; // G = E / (2 (1 + nu))

  static ElasticConstants from_young_poisson(Real density, Real young, Real poisson) {
    return {density, young, poisson, young / (3 * (1 - 2 * poisson)), young / (2 * (1 + poisson))};
  }

  // Longitudinal (P-wave, uniaxial strain) speed sqrt((K + 4G/3) / rho): the fastest signal,
  // which bounds the explicit time step.
  Real longitudinal_wave_speed(Real rho) const {
    return std::sqrt((bulk_modulus + Real(4) / 3 * shear_modulus) / rho);
  }
  // Bar speed sqrt(E / rho) (uniaxial stress).
  Real bar_wave_speed() const { return std::sqrt(young / density); }
};

// Pressure from the volumetric strain of a hypoelastic solid: p = K (rho / rho_0 - 1),
// compression positive, as LS-DYNA's linear EOS with C1 = K.
inline Real elastic_pressure(const ElasticConstants& c, Real rho) {
  return c.bulk_modulus * (rho / c.density - 1);
}

// W S - S W (= W S + (W S)^T) of a symmetric S and the spin W = skew(L), from L: the
// Jaumann rotation of S, its six independent entries with four products each, mirrored (a third
// of the work of the two matrix products).
inline Mat3 jaumann_rotation(const Mat3& L, const Mat3& S) {
  const Real w01 = Real(0.5) * (L(0, 1) - L(1, 0)), w12 = Real(0.5) * (L(1, 2) - L(2, 1)),
             w02 = Real(0.5) * (L(0, 2) - L(2, 0));
  Mat3 R;
  R(0, 0) = 2 * (w01 * S(1, 0) + w02 * S(2, 0));
  R(1, 1) = 2 * (w12 * S(2, 1) - w01 * S(0, 1));
  R(2, 2) = -2 * (w02 * S(0, 2) + w12 * S(1, 2));
  R(0, 1) = R(1, 0) = w01 * (S(1, 1) - S(0, 0)) + w02 * S(2, 1) + w12 * S(2, 0);
  R(1, 2) = R(2, 1) = w12 * (S(2, 2) - S(1, 1)) - w01 * S(0, 2) - w02 * S(0, 1);
  R(0, 2) = R(2, 0) = w02 * (S(2, 2) - S(0, 0)) + w01 * S(1, 2) - w12 * S(1, 0);
  return R;
}

// Hooke's law in Jaumann rate form for the deviatoric stress S:
//   dS/dt = 2G (D - tr(D)/3 I) + W S - S W,  D = sym(L), W = skew(L), L = grad v.
// (The Jaumann rate S^J = dS/dt - W S + S W is objective; see Gray, Monaghan & Swift 2001.)
inline Mat3 jaumann_deviatoric_stress_rate(Real shear_modulus, const Mat3& S,
                                           const Mat3& velocity_gradient) {
  const Mat3 D = Real(0.5) * (velocity_gradient + velocity_gradient.transpose());
  const Mat3 dev_D = D - (D.trace() / 3) * Mat3::Identity();
  return 2 * shear_modulus * dev_D + jaumann_rotation(velocity_gradient, S);
}

// Von Mises equivalent stress sqrt(3/2 S:S).
inline Real von_mises(const Mat3& S) { return std::sqrt(Real(1.5) * S.cwiseProduct(S).sum()); }

}  // namespace spall::materials
