#pragma once
// The global energy balance as an open ledger (DESIGN, phase 8): whoever produces a term registers
// it by name (the time loop: kinetic energy and external work; SPH and SPG: internal energy and
// artificial viscosity; FEM later: hourglass; contact: sliding), and glstat's columns are the
// ledger's terms. Each term has a role in the balance
//   total = kinetic + stored + dissipated,   ratio = total / (total at t = 0 + external work),
// which is 1 for a run that conserves energy (LS-DYNA's glstat "energy ratio"). The kinetic and
// internal energy of eroded elements leave with them and are dissipated terms of their own.
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/part_slot.hpp"

namespace spall::discretization {

class EnergyLedger {
 public:
  // reported: a quantity glstat shows beside the energies that is not part of the balance (the
  // mass eroded elements took away, the mass DT2MS added).
  enum class Role { kinetic, stored, dissipated, external, reported };

  struct Term {
    std::string name;  // the glstat column, e.g. "internal_energy"
    Role role;
    Real value = 0;
    void checkpoint(Archive& a) { a(name, role, value); }
  };

  // Adds `amount` to the term `name`, registering it on first use. Terms are listed by role
  // (kinetic, stored, dissipated, external), then in the order they were registered. A name
  // registered under another role throws std::logic_error.
  void add(std::string_view name, Role role, Real amount);
  // Sets the term (a state, like the kinetic energy, rather than an accumulated work).
  void set(std::string_view name, Role role, Real value);

  const std::vector<Term>& terms() const { return terms_; }
  // The term's value, 0 when nobody registered it.
  Real value(std::string_view name) const;

  // The standard terms by name.
  Real kinetic() const { return value(kinetic_energy); }
  Real internal() const { return value(internal_energy); }
  Real artificial_viscosity() const { return value(artificial_viscosity_energy); }
  Real external_work() const { return value(external_work_name); }

  Real total() const;
  // Fixes the reference of the ratio: the total at t = 0.
  void set_initial_total() { initial_total_ = total(); }
  Real initial_total() const { return initial_total_; }
  // total / (initial total + external work): 1 for a perfectly conserving run. NaN for a model at
  // rest, where the reference is zero or no larger than the round-off of the terms it is made of:
  // |reference| <= sqrt(eps) * (the largest |term|, initial total and external work included).
  // Below that, the quotient measures round-off, not energy (6.7e14 for a model at rest).
  Real ratio() const;

  static constexpr std::string_view kinetic_energy = "kinetic_energy";
  static constexpr std::string_view internal_energy = "internal_energy";
  static constexpr std::string_view artificial_viscosity_energy = "artificial_viscosity_energy";
  static constexpr std::string_view external_work_name = "external_work";
  static constexpr std::string_view hourglass_energy = "hourglass_energy";
  static constexpr std::string_view eroded_kinetic_energy = "eroded_kinetic_energy";
  static constexpr std::string_view eroded_internal_energy = "eroded_internal_energy";
  static constexpr std::string_view eroded_mass = "eroded_mass";
  static constexpr std::string_view added_mass = "added_mass";

  // *DATABASE_MATSUM: internal_energy booked part by part, by the formulations whose material
  // points hold no energy that follows their forces' work (the SPH solid: its e integrates the
  // corrected velocity gradient, whose power the pair forces do not deliver; SPG: its e leaves out
  // the stabilization's springs; FEM: its points' e, each a mass m / points, drifts from the work
  // as elements distort). Off until keep_part_work
  // names the parts (ascending, each once); then add_part_work(k, amount) adds to the k-th, and
  // add_part_eroded(k, internal, kinetic) what its eroded elements took with them.
  struct PartEnergies {
    Real work = 0;
    Real eroded_internal = 0, eroded_kinetic = 0;
    void checkpoint(Archive& a) { a(work, eroded_internal, eroded_kinetic); }
  };
  void keep_part_work(std::vector<Id> parts) {
    part_ids_ = std::move(parts);
    part_energies_.assign(part_ids_.size(), {});
  }
  const std::vector<Id>& part_ids() const { return part_ids_; }
  // The place of `part` in part_ids(), -1 when it is not there.
  int part_slot(Id part) const { return discretization::part_slot(part_ids_, part); }
  void add_part_work(std::size_t k, Real amount) { part_energies_[k].work += amount; }
  void add_part_eroded(std::size_t k, Real internal, Real kinetic) {
    part_energies_[k].eroded_internal += internal;
    part_energies_[k].eroded_kinetic += kinetic;
  }
  const PartEnergies& part_energies(std::size_t k) const { return part_energies_[k]; }

  // The terms and the total at t = 0 (a restart continues the same balance).
  void checkpoint(Archive& a) { a(terms_, initial_total_, part_ids_, part_energies_); }

 private:
  Term& term(std::string_view name, Role role);

  std::vector<Term> terms_;
  Real initial_total_ = 0;
  std::vector<Id> part_ids_;
  std::vector<PartEnergies> part_energies_;
};

// The power of a formulation's internal forces at the nodes' velocities: the rate of stored
// (strain) energy and the rate of energy dissipated by its artificial viscosity.
struct InternalPower {
  Real stored = 0;
  Real dissipated = 0;
};

// Books dt times the power as internal_energy and artificial_viscosity_energy.
inline void book_internal_power(EnergyLedger& ledger, const InternalPower& power, Real dt) {
  ledger.add(EnergyLedger::internal_energy, EnergyLedger::Role::stored, dt * power.stored);
  ledger.add(EnergyLedger::artificial_viscosity_energy, EnergyLedger::Role::dissipated, dt * power.dissipated);
}

}  // namespace spall::discretization
