#include "spall/discretization/energy_ledger.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
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
  Real scale = std::max(std::abs(initial_total_), std::abs(external_work()));
  for (const auto& t : terms_)
    if (t.role != Role::reported) scale = std::max(scale, std::abs(t.value));
  // sqrt(eps): the terms are sums over many steps, each rounding at eps times their size; a
  // reference within a few decades of eps * scale is round-off.
  static const Real negligible = std::sqrt(std::numeric_limits<Real>::epsilon());
  if (!(std::abs(reference) > negligible * scale)) return std::numeric_limits<Real>::quiet_NaN();
  return total() / reference;
}

}  // namespace spall::discretization
