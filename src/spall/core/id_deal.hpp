#pragma once
// Which rank keeps an ID's entries in a join over the ranks by ID (the deck's node IDs and the
// cards that name them, docs/SCALING.md §5 step 4 f2): a mix of the ID's bits, so that the IDs of
// a deck, mostly dense and in runs, spread evenly whatever their stride. And which rank's block
// of the node order holds a place (the set-up in blocks).
#include <algorithm>
#include <cstdint>
#include <span>

#include "spall/core/types.hpp"

namespace spall::parallel {

inline int rank_of_id(Id id, int ranks) {
  std::uint64_t z = static_cast<std::uint64_t>(id) + 0x9e3779b97f4a7c15ull;  // splitmix64's finalizer
  z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9ull;
  z = (z ^ (z >> 27)) * 0x94d049bb133111ebull;
  return static_cast<int>((z ^ (z >> 31)) % static_cast<std::uint64_t>(ranks));
}

// The rank r with blocks[r] <= place < blocks[r + 1] (blocks: every rank's first place, then the
// count, as parallel::block_offsets gives them).
inline int rank_of_place(std::span<const Index> blocks, std::int64_t place) {
  return static_cast<int>(std::upper_bound(blocks.begin(), blocks.end(), place) - blocks.begin()) - 1;
}

}  // namespace spall::parallel
