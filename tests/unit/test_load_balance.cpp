// solver::balanced_blocks: node blocks cut again where the measured work is even. The work of a
// block is taken as spread evenly over its nodes, so a block whose nodes cost c each is cut at
// the node count that holds the wanted share of the work: the exact cut of that model.
#include <gtest/gtest.h>

#include <algorithm>
#include <vector>

#include "spall/solver/load_balance.hpp"

namespace spall::solver {
namespace {

// Two equal blocks of 100 nodes, the first three times as costly per node (work 3 : 1): the work
// is halved at 2/3 of the first block, node 67 (2.01 : 1.99 in the model's units).
TEST(LoadBalance, CostlyBlockIsCutWhereTheWorkIsHalved) {
  EXPECT_EQ(balanced_blocks(std::vector<Index>{0, 100, 200}, std::vector<double>{3, 1}),
            (std::vector<Index>{0, 67, 200}));
}

// Even work keeps the blocks; no work (or all negative: a clock that went back) keeps them too.
TEST(LoadBalance, EvenOrNoWorkKeepsTheBlocks) {
  const std::vector<Index> blocks{0, 40, 90, 120};
  EXPECT_EQ(balanced_blocks(blocks, std::vector<double>{2, 2, 2}), blocks);
  EXPECT_EQ(balanced_blocks(blocks, std::vector<double>{0, 0, 0}), blocks);
  EXPECT_EQ(balanced_blocks(blocks, std::vector<double>{-1, -1, -1}), blocks);
}

// Four ranks, all the work on the last block's 100 nodes: each rank gets a quarter of that block,
// the first three blocks' nodes (which cost nothing) going to rank 0.
TEST(LoadBalance, WorkInOneBlockIsSharedByEveryRank) {
  EXPECT_EQ(balanced_blocks(std::vector<Index>{0, 10, 20, 30, 130}, std::vector<double>{0, 0, 0, 8}),
            (std::vector<Index>{0, 55, 80, 105, 130}));
}

// An empty block (a rank with no nodes) that did work (what every rank repeats) is passed over:
// the cuts stay in order and cover every node.
TEST(LoadBalance, EmptyBlocksKeepTheCutsInOrder) {
  const std::vector<Index> next = balanced_blocks(std::vector<Index>{0, 0, 50, 100}, std::vector<double>{1, 4, 1});
  ASSERT_EQ(next.size(), 4u);
  EXPECT_EQ(next.front(), 0);
  EXPECT_EQ(next.back(), 100);
  EXPECT_TRUE(std::is_sorted(next.begin(), next.end()));
  // A third of the work (2 of 6): the empty block's 1, then 1 of the second block's 4 over its 50 nodes.
  EXPECT_EQ(next[1], 13);  // 12.5 rounded
}

// The checks: after 10, 20, 40 and 80 steps while those are below the interval, then at its
// multiples; an interval at or below the first check gives its multiples alone, and an interval of
// 0 (or less) none at all. Step 0 is never a check: no work has been measured.
TEST(LoadBalance, FirstChecksComeEarlyThenEveryInterval) {
  const auto checks = [](long long interval, long long last) {
    std::vector<long long> at;
    for (long long step = 0; step <= last; ++step)
      if (LoadBalance{interval, 0.1}.checks_at(step)) at.push_back(step);
    return at;
  };
  EXPECT_EQ(checks(100, 300), (std::vector<long long>{10, 20, 40, 80, 100, 200, 300}));
  EXPECT_EQ(checks(30, 90), (std::vector<long long>{10, 20, 30, 60, 90}));
  EXPECT_EQ(checks(5, 20), (std::vector<long long>{5, 10, 15, 20}));
  EXPECT_EQ(checks(10, 30), (std::vector<long long>{10, 20, 30}));
  EXPECT_TRUE(checks(0, 300).empty());
  EXPECT_TRUE(checks(-7, 300).empty());
}

}  // namespace
}  // namespace spall::solver
