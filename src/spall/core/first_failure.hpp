#pragma once
// Checks that each rank makes of its own share of a deck (its cards, its block of the nodes) stop
// every rank alike: of the failures the ranks found, the first in the deck's order is thrown on
// every rank, word for word as the rank that found it has it, whatever the number of ranks
// (docs/SCALING.md §5 step 4 f2).
#include <cstdint>
#include <optional>

#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"

namespace spall::parallel {

// `position` orders the failures (a card's ordinal, and what failed there where a card can fail in
// more than one way: up to a few times the count of cards, hence 64 bits), -1 when this rank found
// none; `error` is this rank's failure at it. Throws the failure of the lowest position over the
// ranks on every rank; returns when none failed. Collective.
void throw_first_failure(std::int64_t position, const std::optional<InputError>& error, const Communicator& ranks);

}  // namespace spall::parallel
