// The energy ratio of the ledger: total / (initial total + external work), and NaN for a model at
// rest, where that reference is zero or at the round-off level of the terms (docs/OUTPUT.md).
#include <gtest/gtest.h>

#include <cmath>

#include "spall/discretization/energy_ledger.hpp"

namespace spall::discretization {
namespace {

using Role = EnergyLedger::Role;

TEST(energy_ledger, RatioOfAConservingRun) {
  EnergyLedger ledger;
  ledger.set(EnergyLedger::kinetic_energy, Role::kinetic, 2.0);
  ledger.set_initial_total();
  ledger.set(EnergyLedger::kinetic_energy, Role::kinetic, 0.5);
  ledger.add(EnergyLedger::internal_energy, Role::stored, 1.5);
  ledger.add(EnergyLedger::external_work_name, Role::external, 1.0);
  ledger.add(EnergyLedger::kinetic_energy, Role::kinetic, 1.0);
  EXPECT_DOUBLE_EQ(ledger.ratio(), 3.0 / 3.0);
}

TEST(energy_ledger, RatioOfAModelAtRestIsNotANumber) {
  EnergyLedger nothing;
  nothing.set_initial_total();
  EXPECT_TRUE(std::isnan(nothing.ratio()));
  // Round-off energies of a model at rest: a reference of 1e-31 beside terms of 1e-16 gave 6.7e14.
  EnergyLedger at_rest;
  at_rest.set(EnergyLedger::kinetic_energy, Role::kinetic, 1e-31);
  at_rest.set_initial_total();
  at_rest.add(EnergyLedger::internal_energy, Role::stored, 6.7e-17);
  EXPECT_TRUE(std::isnan(at_rest.ratio()));
  // The threshold is sqrt(eps) = 1.5e-8 of the largest term: a reference of 1e-7 beside a term of 1
  // is a number (a run that made energy), one of 1e-9 is not.
  for (const double reference : {1e-7, 1e-9}) {
    EnergyLedger ledger;
    ledger.set(EnergyLedger::kinetic_energy, Role::kinetic, reference);
    ledger.set_initial_total();
    ledger.add(EnergyLedger::internal_energy, Role::stored, 1.0);
    if (reference > 1e-8)
      EXPECT_NEAR(ledger.ratio(), (1.0 + reference) / reference, 1.0);
    else
      EXPECT_TRUE(std::isnan(ledger.ratio()));
  }
}

}  // namespace
}  // namespace spall::discretization
