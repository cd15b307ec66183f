#include "spall/discretization/part_summary.hpp"

#include "spall/discretization/part_slot.hpp"

namespace spall::discretization {

PartSummary::PartSummary(std::vector<Id> parts) : parts_(std::move(parts)), sums_(parts_.size() * quantity_count) {}

void PartSummary::add(Id part, Quantity quantity, Real x) {
  const int k = part_slot(parts_, part);
  if (k >= 0) sums_[static_cast<std::size_t>(k) * quantity_count + quantity] += x;
}

}  // namespace spall::discretization
