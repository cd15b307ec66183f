#pragma once
// Checks that each rank makes of its own share of a deck (its cards, its block of the nodes) stop
// every rank alike: of the failures the ranks found, the first in the deck's order is thrown on
// every rank, word for word as the rank that found it has it, whatever the number of ranks
// (docs/SCALING.md §5 step 4 f2).
#include <optional>

#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"

namespace spall::parallel {

// `position` orders the failures (a card's ordinal, and what failed there where a card can fail in
// more than one way), -1 when this rank found none; `error` is this rank's failure at it. Throws
// the failure of the lowest position over the ranks on every rank; returns when none failed.
// Collective.
void throw_first_failure(Index position, const std::optional<InputError>& error, const Communicator& ranks);

// The same for one check run card by card: check(k) for k = 0, 1, ... count - 1 in this rank's
// order, which is the deck's among its own cards; the first that throws is this rank's failure at
// position_of(k).
template <typename Check, typename PositionOf>
void check_each_card(Index count, Check&& check, PositionOf&& position_of, const Communicator& ranks) {
  std::optional<InputError> error;
  Index position = -1;
  for (Index k = 0; k < count && !error; ++k) {
    try {
      check(k);
    } catch (const InputError& e) {
      error = e;
      position = position_of(k);
    }
  }
  throw_first_failure(position, error, ranks);
}

}  // namespace spall::parallel
