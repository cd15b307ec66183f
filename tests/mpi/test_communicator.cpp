// The communicator's collectives (core/communicator.hpp), run as 1, 2 and 3 ranks: a global
// minimum and exact sums give on every rank the answer one process computes from all the data,
// bit for bit, however the data are split among the ranks; share() gives every rank every block
// (a rank with none included); exchange() and deliver() give each rank what every other sent it. Every rank draws the same random
// numbers, keeps its share, and checks the collective against the whole.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <random>
#include <vector>

#include "spall/core/bounding_box.hpp"
#include "spall/core/communicator.hpp"

namespace spall::parallel {
namespace {

TEST(Communicator, HasTheRanksTheLauncherStarted) {
  const Communicator& ranks = world();
  EXPECT_EQ(ranks.size(), built_with_mpi() ? launched_ranks() : 1);
  EXPECT_GE(ranks.rank(), 0);
  EXPECT_LT(ranks.rank(), ranks.size());
}

TEST(Communicator, MinimumOfEveryRanksValues) {
  const Communicator& ranks = world();
  std::mt19937_64 random(35);
  std::normal_distribution<double> normal(0.0, 1.0);
  constexpr int n = 7;
  // Rank r holds row r of a table with a row per rank; the minimum is each column's.
  std::vector<std::vector<double>> table(ranks.size(), std::vector<double>(n));
  for (auto& row : table)
    for (double& x : row) x = normal(random);
  table[0][3] = -std::numeric_limits<double>::infinity();
  std::vector<double> mine = table[ranks.rank()];
  ranks.minimum(mine);
  for (int j = 0; j < n; ++j) {
    double expected = table[0][j];
    for (const auto& row : table) expected = std::min(expected, row[j]);
    EXPECT_EQ(mine[j], expected) << "column " << j;
  }
}

TEST(Communicator, ExactSumsDoNotDependOnHowTheTermsAreSplit) {
  const Communicator& ranks = world();
  std::mt19937_64 random(1729);
  std::lognormal_distribution<double> size(0.0, 6.0);
  std::vector<double> terms(50000);
  for (double& x : terms) x = (random() & 1 ? 1.0 : -1.0) * size(random);
  ExactSum whole[2];
  for (double x : terms) {
    whole[0] += x;
    whole[1] += x * x;
  }
  // Terms dealt to the ranks at random (the same draw on every rank), in a shuffled order.
  std::shuffle(terms.begin(), terms.end(), random);
  std::vector<ExactSum> mine(2);
  for (double x : terms)
    if (static_cast<int>(random() % ranks.size()) == ranks.rank()) {
      mine[0] += x;
      mine[1] += x * x;
    }
  ranks.sum(mine);
  EXPECT_EQ(mine[0].value(), whole[0].value());
  EXPECT_EQ(mine[1].value(), whole[1].value());
}

TEST(Communicator, NonFiniteTermsOnOneRankReachEveryRank) {
  const Communicator& ranks = world();
  std::vector<ExactSum> sums(2);
  sums[0] += 1.0;
  if (ranks.rank() == ranks.size() - 1) {
    sums[0] += std::numeric_limits<double>::quiet_NaN();
    sums[1] += -std::numeric_limits<double>::infinity();
  }
  sums[1] += 2.0;
  ranks.sum(sums);
  EXPECT_TRUE(std::isnan(sums[0].value()));
  EXPECT_EQ(sums[1].value(), -std::numeric_limits<double>::infinity());
}

TEST(Communicator, IntegerSums) {
  const Communicator& ranks = world();
  std::vector<std::int64_t> counts = {ranks.rank() + 1, std::int64_t(1) << 40};
  ranks.sum(counts);
  EXPECT_EQ(counts[0], std::int64_t(ranks.size()) * (ranks.size() + 1) / 2);
  EXPECT_EQ(counts[1], ranks.size() * (std::int64_t(1) << 40));
}

TEST(Communicator, ShareGivesEveryRankEveryBlock) {
  const Communicator& ranks = world();
  struct Item {
    double value;
    float extra;
    int rank;
  };
  // 10 items a rank less one: blocks of unequal sizes, and none for a rank when there are more
  // ranks than items.
  for (const Index count : {Index(10 * ranks.size() - 1), Index(ranks.size() - 1)}) {
    const std::vector<Index> offsets = block_offsets(count, ranks.size());
    ASSERT_EQ(offsets.front(), 0);
    ASSERT_EQ(offsets.back(), count);
    std::vector<Item> items(count, Item{-1.0, -1.0f, -1});
    for (Index i = offsets[ranks.rank()]; i < offsets[ranks.rank() + 1]; ++i)
      items[i] = Item{0.5 * i, 0.25f * i, ranks.rank()};
    const std::int64_t received_before = ranks.received_bytes();
    ranks.share(std::span(items), offsets);
    // What came in: every other rank's block, and nothing on one process.
    const Index others = count - (offsets[ranks.rank() + 1] - offsets[ranks.rank()]);
    EXPECT_EQ(ranks.received_bytes() - received_before, ranks.size() == 1 ? 0 : std::int64_t(others) * sizeof(Item));
    for (int r = 0; r < ranks.size(); ++r)
      for (Index i = offsets[r]; i < offsets[r + 1]; ++i) {
        EXPECT_EQ(items[i].value, 0.5 * i);
        EXPECT_EQ(items[i].extra, 0.25f * i);
        EXPECT_EQ(items[i].rank, r);
      }
  }
}

// Rank s sends rank r (s + 1) * (r + 1) - 1 items, none to itself: lists of unequal lengths, an
// empty one on 1 rank, each item naming its sender, receiver and place.
TEST(Communicator, ExchangeDeliversEachRanksItemsForAnother) {
  const Communicator& ranks = world();
  struct Item {
    int from, to, k;
  };
  const int me = ranks.rank(), size = ranks.size();
  const auto count = [](int from, int to) { return from == to ? 0 : (from + 1) * (to + 1) - 1; };
  std::vector<Index> send_offsets(size + 1, 0), receive_offsets(size + 1, 0);
  for (int r = 0; r < size; ++r) {
    send_offsets[r + 1] = send_offsets[r] + count(me, r);
    receive_offsets[r + 1] = receive_offsets[r] + count(r, me);
  }
  std::vector<Item> send(send_offsets.back()), receive(receive_offsets.back(), Item{-1, -1, -1});
  for (int r = 0; r < size; ++r)
    for (int k = 0; k < count(me, r); ++k) send[send_offsets[r] + k] = Item{me, r, k};
  const std::int64_t received_before = ranks.received_bytes();
  ranks.exchange(std::span<const Item>(send), send_offsets, std::span(receive), receive_offsets);
  EXPECT_EQ(ranks.received_bytes() - received_before, std::int64_t(receive_offsets.back()) * sizeof(Item));
  for (int r = 0; r < size; ++r)
    for (int k = 0; k < count(r, me); ++k) {
      const Item& item = receive[receive_offsets[r] + k];
      EXPECT_EQ(item.from, r);
      EXPECT_EQ(item.to, me);
      EXPECT_EQ(item.k, k);
    }
}

// all(): rank r offers r items (none on rank 0), each naming its rank and place; every rank gets
// every rank's, in rank order.
TEST(Communicator, AllGivesEveryRanksListInRankOrder) {
  const Communicator& ranks = world();
  struct Item {
    int rank, k;
  };
  std::vector<Item> mine;
  for (int k = 0; k < ranks.rank(); ++k) mine.push_back({ranks.rank(), k});
  const std::vector<Item> all = ranks.all(std::span<const Item>(mine));
  ASSERT_EQ(all.size(), std::size_t(ranks.size() * (ranks.size() - 1) / 2));
  std::size_t at = 0;
  for (int r = 0; r < ranks.size(); ++r)
    for (int k = 0; k < r; ++k, ++at) {
      EXPECT_EQ(all[at].rank, r);
      EXPECT_EQ(all[at].k, k);
    }
}

// offsets_in(): rank s sends rank r (s + 1) * (r + 1) items; each rank learns where each sender's
// land (on one process, its own to itself).
TEST(Communicator, OffsetsInCountWhatEachRankSends) {
  const Communicator& ranks = world();
  const int me = ranks.rank(), size = ranks.size();
  std::vector<Index> out(size + 1, 0);
  for (int r = 0; r < size; ++r) out[r + 1] = out[r] + (me + 1) * (r + 1);
  const std::vector<Index> in = ranks.offsets_in(out);
  ASSERT_EQ(in.size(), std::size_t(size + 1));
  EXPECT_EQ(in[0], 0);
  for (int r = 0; r < size; ++r) EXPECT_EQ(in[r + 1] - in[r], (r + 1) * (me + 1)) << "from rank " << r;
}

// deliver(): rank `me` sends rank r the list (me, r, 0), (me, r, 1), ... of me + 2 r items (none
// from rank 0 to itself); each rank gets every sender's list, in rank order.
TEST(Communicator, DeliverGivesEachRankItsListsInSenderOrder) {
  const Communicator& ranks = world();
  const int size = ranks.size(), me = ranks.rank();
  struct Item {
    std::int64_t from, to, k;
  };
  std::vector<std::vector<Item>> out(size);
  for (int r = 0; r < size; ++r)
    for (int k = 0; k < me + 2 * r; ++k) out[r].push_back({me, r, k});
  const std::vector<Item> in = ranks.deliver(out);
  std::size_t next = 0;
  for (int from = 0; from < size; ++from)
    for (int k = 0; k < from + 2 * me; ++k, ++next) {
      ASSERT_LT(next, in.size());
      EXPECT_EQ(in[next].from, from);
      EXPECT_EQ(in[next].to, me);
      EXPECT_EQ(in[next].k, k);
    }
  EXPECT_EQ(next, in.size());
}

// over_ranks(): each rank's box of its points (rank 1, when there is one, has none) merged into the
// box of every point, exactly; a non-finite point on one rank leaves every rank's box not finite.
TEST(Communicator, BoxOverRanksIsTheBoxOfEveryPoint) {
  const Communicator& ranks = world();
  std::mt19937_64 random(36);
  std::normal_distribution<double> normal(0.0, 1.0);
  BoundingBox whole, mine;
  for (int k = 0; k < 30; ++k) {
    const Vec3 p(normal(random), 1e3 * normal(random), -5 + normal(random));
    const int r = k % ranks.size() == 1 ? 0 : k % ranks.size();
    whole.include(p);
    if (r == ranks.rank()) mine.include(p);
  }
  const BoundingBox merged = over_ranks(mine, ranks);
  EXPECT_EQ(merged.lower, whole.lower);
  EXPECT_EQ(merged.upper, whole.upper);
  EXPECT_TRUE(merged.finite);
  if (ranks.rank() == ranks.size() - 1) mine.include(Vec3(0, std::numeric_limits<double>::quiet_NaN(), 0));
  EXPECT_FALSE(over_ranks(mine, ranks).finite);
}

}  // namespace
}  // namespace spall::parallel
