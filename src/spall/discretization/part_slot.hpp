#pragma once
// The place of a part in a list of the deck's part IDs (ascending, each once), as the per-part sums
// of *DATABASE_MATSUM keep them (EnergyLedger's work, PartSummary's quantities).
#include <algorithm>
#include <span>

#include "spall/core/types.hpp"

namespace spall::discretization {

// The index of `part` in `parts`, -1 when it is not there (0, a node no part owns).
inline int part_slot(std::span<const Id> parts, Id part) {
  const auto at = std::lower_bound(parts.begin(), parts.end(), part);
  return at == parts.end() || *at != part ? -1 : static_cast<int>(at - parts.begin());
}

}  // namespace spall::discretization
