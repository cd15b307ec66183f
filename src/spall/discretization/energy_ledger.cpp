#include "spall/discretization/energy_ledger.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <stdexcept>

namespace spall::discretization {

EnergyLedger::Term& EnergyLedger::term(std::string_view name, Role role) {
  for (auto& t : terms_) {
    if (t.name != name) continue;
    if (t.role != role) throw std::logic_error(fmt::format("energy term '{}' registered under two roles", name));
    return t;
  }
  // After the last term of the same or an earlier role: columns grouped by role, stable in time.
  const auto after = std::find_if(terms_.begin(), terms_.end(), [role](const Term& t) { return t.role > role; });
  return *terms_.insert(after, Term{std::string(name), role, 0});
}

void EnergyLedger::add(std::string_view name, Role role, Real amount) { term(name, role).value += amount; }

void EnergyLedger::set(std::string_view name, Role role, Real value) { term(name, role).value = value; }

Real EnergyLedger::value(std::string_view name) const {
  for (const auto& t : terms_)
    if (t.name == name) return t.value;
  return 0;
}

Real EnergyLedger::total() const {
  Real sum = 0;
  for (const auto& t : terms_)
    if (t.role != Role::external && t.role != Role::reported) sum += t.value;
  return sum;
}

Real EnergyLedger::ratio() const {
  const Real reference = initial_total_ + external_work();
  return reference != 0 ? total() / reference : 1;
}

}  // namespace spall::discretization
