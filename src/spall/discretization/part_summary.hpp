#pragma once
// *DATABASE_MATSUM: the model's energies and momenta part by part (LS-DYNA's matsum). Whoever holds
// a quantity adds it under the part it belongs to: a formulation the internal energy its material
// points hold, its elements' hourglass energy and the mass DT2MS added, the time loop the nodes'
// kinetic energy and momentum and the ledger's work and eroded energies by part. Each sum is exact
// until it is read (ExactSum), so that it depends neither on the order of the terms nor, once
// summed over the ranks, on how the parts are spread over them.
#include <array>
#include <string_view>
#include <utility>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/exact_sum.hpp"
#include "spall/core/types.hpp"

namespace spall::discretization {

class PartSummary {
 public:
  // The eroded energies: what the part's eroded elements took with them, since the start; the
  // added mass: what DT2MS has added to the part's elements (particles).
  enum Quantity : int {
    internal_energy, kinetic_energy, hourglass_energy, x_momentum, y_momentum, z_momentum,
    eroded_internal_energy, eroded_kinetic_energy, added_mass
  };
  static constexpr int quantity_count = 9;
  // matsum.csv's columns, in the order of Quantity.
  static constexpr std::array<std::string_view, quantity_count> names = {
      "internal_energy", "kinetic_energy", "hourglass_energy", "x_momentum", "y_momentum", "z_momentum",
      "eroded_internal_energy", "eroded_kinetic_energy", "added_mass"};

  // The deck's parts, ascending, each once (as Controls::matsum_parts).
  explicit PartSummary(std::vector<Id> parts);

  const std::vector<Id>& parts() const { return parts_; }
  // Adds x to the part's quantity; a part that is not in the list (0, a node no part owns) is
  // left out.
  void add(Id part, Quantity quantity, Real x);
  void add_momentum(Id part, const Vec3& p) {
    for (int d = 0; d < 3; ++d) add(part, Quantity(x_momentum + d), p[d]);
  }
  // Each sum over every rank's terms (collective).
  void sum_over(const parallel::Communicator& ranks) { ranks.sum(sums_); }
  // The sum of the k-th part, rounded once.
  Real value(std::size_t k, Quantity quantity) const { return sums_[k * quantity_count + quantity].value(); }

 private:
  std::vector<Id> parts_;
  std::vector<ExactSum> sums_;
};

}  // namespace spall::discretization
