// A sort over the ranks into blocks (core/sort_into_blocks.hpp), run as 1, 2 and 3 ranks: items
// keyed by (a pseudo-random number with many ties, a signed ordinal), dealt to the ranks unevenly,
// all on the last rank, none at all, or fewer than the ranks, come back as each rank's block of
// block_begin's size, and the blocks one after the other are the whole sorted on one process, each
// item with its payload: the keys alone decide, not how the items were spread.
#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <random>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/sort_into_blocks.hpp"

namespace spall::parallel {
namespace {

struct Item {
  std::uint64_t cell;
  std::int64_t ordinal;
  double payload;
  std::int64_t tag;
  bool operator==(const Item&) const = default;
};

std::pair<std::uint64_t, std::int64_t> key_of(const Item& item) { return {item.cell, item.ordinal}; }

// The same n items on every rank: cells of 1 024 values (about n / 1 024 items share each, so that
// the ordinal decides among them), ordinals of both signs out of step with the items' order.
std::vector<Item> make_items(Index n) {
  std::mt19937_64 random(20240611);
  std::vector<Item> items(n);
  for (Index i = 0; i < n; ++i)
    items[i] = {random() >> 54, i % 2 ? i : -std::int64_t(i), 0.25 * i - 3.0, 3 * std::int64_t(i) + 1};
  return items;
}

// Sorts this rank's `mine` of `whole` (every rank's items) and checks the blocks against `whole`
// sorted on one process.
void expect_sorted_into_blocks(std::vector<Item> whole, std::vector<Item> mine) {
  const Communicator& ranks = world();
  const std::vector<Item> block = sort_into_blocks(std::move(mine), key_of, ranks);
  const Index n = static_cast<Index>(whole.size());
  const Index first = block_begin(n, ranks.rank(), ranks.size());
  EXPECT_EQ(static_cast<Index>(block.size()), block_begin(n, ranks.rank() + 1, ranks.size()) - first);
  std::sort(whole.begin(), whole.end(), [](const Item& a, const Item& b) { return key_of(a) < key_of(b); });
  const std::vector<Item> blocks = ranks.all(std::span<const Item>(block));
  ASSERT_EQ(blocks.size(), whole.size());
  for (std::size_t k = 0; k < whole.size(); ++k) ASSERT_EQ(blocks[k], whole[k]) << "at place " << k;
}

TEST(SortIntoBlocks, ItemsDealtUnevenlyComeBackInTheBlocksOfTheWholeSorted) {
  const Communicator& ranks = world();
  // Rank r holds the items whose hash, modulo size² + 1, lies in [r², (r + 1)²) (the last rank
  // up to size² too): shares growing up the ranks, 1, 3 and 6 tenths for 3 ranks.
  const std::vector<Item> whole = make_items(100'000);
  const std::uint64_t spans = std::uint64_t(ranks.size()) * ranks.size() + 1;
  const std::uint64_t from = std::uint64_t(ranks.rank()) * ranks.rank();
  const std::uint64_t next = ranks.rank() + 1;
  const std::uint64_t to = next == std::uint64_t(ranks.size()) ? spans : next * next;
  std::vector<Item> mine;
  for (std::size_t i = 0; i < whole.size(); ++i)
    if (const std::uint64_t span = (i * 2654435761u) % 1000003 % spans; span >= from && span < to)
      mine.push_back(whole[i]);
  expect_sorted_into_blocks(whole, mine);
}

TEST(SortIntoBlocks, ItemsAllOnTheLastRank) {
  const Communicator& ranks = world();
  const std::vector<Item> whole = make_items(20'000);
  expect_sorted_into_blocks(whole, ranks.rank() + 1 == ranks.size() ? whole : std::vector<Item>());
}

TEST(SortIntoBlocks, NoItemsLeaveEveryBlockEmpty) { expect_sorted_into_blocks({}, {}); }

TEST(SortIntoBlocks, FewerItemsThanRanks) {
  const Communicator& ranks = world();
  // Two items of one cell on the first rank, the larger ordinal first: on 3 ranks, blocks of 0, 1, 1.
  const std::vector<Item> whole = {{5, 1, 1.5, 10}, {5, -1, -2.5, 20}};
  expect_sorted_into_blocks(whole, ranks.rank() == 0 ? whole : std::vector<Item>());
  const std::vector<Item> block = sort_into_blocks(ranks.rank() == 0 ? whole : std::vector<Item>(), key_of, ranks);
  if (ranks.size() == 3) {
    EXPECT_EQ(block.size(), ranks.rank() == 0 ? 0u : 1u);
    if (ranks.rank() == 1 && block.size() == 1) {
      EXPECT_EQ(block[0], whole[1]);
    }
  }
}

}  // namespace
}  // namespace spall::parallel
