#include "spall/materials/eos.hpp"

#include <fmt/format.h>

#include <cmath>

#include "spall/core/error.hpp"

namespace spall::materials {

namespace {

EosValue linear_bulk(const LinearBulk& eos, Real rho0, Real density) {
  return {eos.bulk_modulus * (density / rho0 - 1), eos.bulk_modulus / rho0, 0};
}

EosValue linear_polynomial(const LinearPolynomial& eos, Real rho0, Real density, Real e) {
  const auto& c = eos.c;
  const Real mu = density / rho0 - 1;
  const Real energy = rho0 * e;  // per unit reference volume
  // LS-DYNA drops the mu^2 terms in tension.
  const Real c2 = mu < 0 ? 0 : c[2];
  const Real c6 = mu < 0 ? 0 : c[6];
  const Real p =
      c[0] + mu * (c[1] + mu * (c2 + mu * c[3])) + (c[4] + mu * (c[5] + mu * c6)) * energy;
  const Real dp_dmu = c[1] + mu * (2 * c2 + 3 * mu * c[3]) + (c[5] + 2 * mu * c6) * energy;
  return {p, dp_dmu / rho0, (c[4] + mu * (c[5] + mu * c6)) * rho0};
}

EosValue gruneisen(const Gruneisen& eos, Real rho0, Real density, Real e) {
  const Real mu = density / rho0 - 1;
  const Real energy = rho0 * e;
  const Real rho0_c2 = rho0 * eos.c * eos.c;
  const Real energy_factor = eos.gamma0 + eos.a * mu;
  Real cold = rho0_c2 * mu;
  Real dcold_dmu = rho0_c2;
  if (mu > 0) {
    const Real numerator = rho0_c2 * mu * (1 + (1 - eos.gamma0 / 2) * mu - eos.a / 2 * mu * mu);
    const Real dnumerator = rho0_c2 * (1 + (2 - eos.gamma0) * mu - Real(1.5) * eos.a * mu * mu);
    const Real m1 = mu + 1;
    const Real denominator =
        1 - (eos.s1 - 1) * mu - eos.s2 * mu * mu / m1 - eos.s3 * mu * mu * mu / (m1 * m1);
    const Real ddenominator = -(eos.s1 - 1) - eos.s2 * mu * (mu + 2) / (m1 * m1) -
                              eos.s3 * mu * mu * (mu + 3) / (m1 * m1 * m1);
    if (!(denominator > 0))
      throw InstabilityError(fmt::format(
          "*EOS_GRUNEISEN: compression mu = {:g} is beyond the range of the shock fit (its "
          "denominator 1 - (S1 - 1) mu - ... reaches 0)",
          mu));
    cold = numerator / (denominator * denominator);
    dcold_dmu = dnumerator / (denominator * denominator) -
                2 * numerator * ddenominator / (denominator * denominator * denominator);
  }
  return {cold + energy_factor * energy, (dcold_dmu + eos.a * energy) / rho0, energy_factor * rho0};
}

// x^n by repeated squaring where n is a whole number from 1 to 16 (Tait's 7 for water: pow was
// 2 % of the dam break's step), within a few ulp of pow; pow otherwise.
Real whole_power(Real x, Real n) {
  if (!(n >= 1 && n <= 16 && n == std::floor(n))) return std::pow(x, n);
  Real result = 1;
  for (auto k = static_cast<unsigned>(n); k != 0; k >>= 1, x *= x)
    if (k & 1u) result *= x;
  return result;
}

EosValue murnaghan(const Murnaghan& eos, Real rho0, Real density) {
  const Real ratio = density / rho0;
  const Real power = whole_power(ratio, eos.gamma);
  return {eos.k0 * (power - 1), eos.k0 * eos.gamma * power / density, 0};
}

}  // namespace

EosValue evaluate_eos(const EquationOfState& eos, Real reference_density, Real density,
                      Real specific_energy) {
  struct Visitor {
    Real rho0, rho, e;
    EosValue operator()(const LinearBulk& m) const { return linear_bulk(m, rho0, rho); }
    EosValue operator()(const LinearPolynomial& m) const {
      return linear_polynomial(m, rho0, rho, e);
    }
    EosValue operator()(const Gruneisen& m) const { return gruneisen(m, rho0, rho, e); }
    EosValue operator()(const Murnaghan& m) const { return murnaghan(m, rho0, rho); }
  };
  return std::visit(Visitor{reference_density, density, specific_energy}, eos);
}

Real isentropic_bulk_modulus(const EosValue& value, Real density) {
  return density * value.dp_ddensity + value.pressure / density * value.dp_denergy;
}

}  // namespace spall::materials
