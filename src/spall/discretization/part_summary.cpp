#include "spall/discretization/part_summary.hpp"

#include <algorithm>

namespace spall::discretization {

PartSummary::PartSummary(std::vector<Id> parts) : parts_(std::move(parts)), sums_(parts_.size() * quantity_count) {}

void PartSummary::add(Id part, Quantity quantity, Real x) {
  const auto place = std::lower_bound(parts_.begin(), parts_.end(), part);
  if (place == parts_.end() || *place != part) return;
  sums_[static_cast<std::size_t>(place - parts_.begin()) * quantity_count + quantity] += x;
}

}  // namespace spall::discretization
