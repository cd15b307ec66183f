#pragma once
// Equations of state: the pressure p (compression positive) of a material point from its density
// rho and its specific internal energy e (per unit mass). LS-DYNA writes its EOS with E, the
// internal energy per unit reference volume; here E = rho0 e. mu = rho / rho0 - 1.
#include <array>
#include <variant>

#include "spall/core/types.hpp"

namespace spall::materials {

// p = K mu: the hypoelastic pressure of *MAT_ELASTIC, *MAT_PLASTIC_KINEMATIC,
// *MAT_PIECEWISE_LINEAR_PLASTICITY (and *MAT_JOHNSON_COOK with E), K = E / (3 (1 - 2 nu)).
// The same as LS-DYNA's *EOS_LINEAR_POLYNOMIAL with C1 = K alone.
struct LinearBulk {
  Real bulk_modulus = 0;
};

// *EOS_LINEAR_POLYNOMIAL:
//   p = C0 + C1 mu + C2 mu^2 + C3 mu^3 + (C4 + C5 mu + C6 mu^2) E,
// with the C2 mu^2 and C6 mu^2 terms dropped in tension (mu < 0), as the LS-DYNA manual states
// for this EOS.
struct LinearPolynomial {
  std::array<Real, 7> c{};
};

// *EOS_GRUNEISEN (Mie-Grueneisen on a cubic shock-velocity fit us = C + S1 up + S2 up^2/us + ...):
//   compressed (mu > 0):
//     p = rho0 C^2 mu [1 + (1 - GAMMA0/2) mu - (A/2) mu^2]
//         / [1 - (S1 - 1) mu - S2 mu^2/(mu + 1) - S3 mu^3/(mu + 1)^2]^2 + (GAMMA0 + A mu) E
//   expanded (mu <= 0):  p = rho0 C^2 mu + (GAMMA0 + A mu) E
// (LS-DYNA keyword manual, *EOS_GRUNEISEN.)
struct Gruneisen {
  Real c = 0, s1 = 0, s2 = 0, s3 = 0, gamma0 = 0, a = 0;
};

// *EOS_MURNAGHAN (Tait form for weakly compressible liquids): p = K0 ((rho / rho0)^GAMMA - 1).
struct Murnaghan {
  Real gamma = 0, k0 = 0;
};

using EquationOfState = std::variant<LinearBulk, LinearPolynomial, Gruneisen, Murnaghan>;

// The pressure at one state and its partial derivatives.
struct EosValue {
  Real pressure = 0;
  Real dp_ddensity = 0;  // (dp/drho) at constant specific energy e
  Real dp_denergy = 0;   // (dp/de) at constant density
};

// Throws InstabilityError where the Grueneisen denominator vanishes (a compression beyond the
// range of its shock fit): a state no equation of this form can describe.
EosValue evaluate_eos(const EquationOfState& eos, Real reference_density, Real density,
                      Real specific_energy);

// Isentropic bulk modulus K_s = rho (dp/drho)_s with (de/drho)_s = p / rho^2 (de = -p dv):
//   K_s = rho (dp/drho)_e + (p / rho) (dp/de)_rho.
Real isentropic_bulk_modulus(const EosValue& value, Real density);

}  // namespace spall::materials
