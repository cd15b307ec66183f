// A node store with rows of its own (dealt by region, docs/SCALING.md §3), run as 1, 2 and
// 3 ranks: a rank keeps some rows in an order of its own, takes rows that come in from other ranks,
// finds every row by the node's place in the deck (also those added since the last keep), and
// rank 0 gathers every rank's own rows into the whole store, in the deck's order, with each node's
// state and rank, as one process holds it; a node that no rank keeps stops the gather.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/discretization/node_store.hpp"

namespace spall::discretization {
namespace {

// The same store on every rank: 90 nodes at random, every ninth without mass (a node no particle
// uses, which only its rank keeps), dealt by region among the ranks.
NodeStore whole_store() {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(0, 1);
  NodeStore nodes;
  nodes.resize(90);
  for (Index i = 0; i < nodes.size(); ++i) {
    nodes.id[i] = 1000 + 7 * i;
    nodes.part[i] = 1 + i % 3;
    nodes.x0[i] = Vec3(u(random), u(random), u(random));
    nodes.x[i] = nodes.x0[i] + 0.01 * Vec3(u(random), u(random), u(random));
    nodes.v[i] = Vec3(u(random), -u(random), u(random));
    nodes.mass[i] = i % 9 == 0 ? 0 : 1 + u(random);
    nodes.fixed[i] = static_cast<std::uint8_t>(i % 8);
    nodes.active[i] = i % 11 != 0;
    nodes.body[i] = i % 13 == 0 ? 2 : NodeStore::no_body;
  }
  const parallel::Communicator& ranks = parallel::world();
  const std::vector<double> weight(nodes.size(), 1.0);
  nodes.deal(Regions::cut(nodes.x, weight, ranks.size()), ranks.rank());
  return nodes;
}

void expect_same_node(const NodeStore& a, Index i, const NodeStore& b, Index j) {
  EXPECT_EQ(a.id[i], b.id[j]);
  EXPECT_EQ(a.part[i], b.part[j]);
  EXPECT_EQ(a.x0[i], b.x0[j]);
  EXPECT_EQ(a.x[i], b.x[j]);
  EXPECT_EQ(a.v[i], b.v[j]);
  EXPECT_EQ(a.mass[i], b.mass[j]);
  EXPECT_EQ(a.fixed[i], b.fixed[j]);
  EXPECT_EQ(a.active[i], b.active[j]);
  EXPECT_EQ(a.body[i], b.body[j]);
  EXPECT_EQ(a.owner[i], b.owner[j]);
}

TEST(NodeRows, KeptAddedFoundAndGatheredWhole) {
  const parallel::Communicator& ranks = parallel::world();
  const NodeStore reference = whole_store();
  NodeStore nodes = whole_store();
  // This rank's own nodes and every fifth other, last first (an order of its own).
  std::vector<Index> kept;
  for (Index i = nodes.size() - 1; i >= 0; --i)
    if (nodes.owns(i) || i % 5 == 0) kept.push_back(i);
  const long long partition = nodes.partition;
  nodes.keep(kept);
  EXPECT_EQ(nodes.partition, partition + 1);
  ASSERT_EQ(nodes.size(), static_cast<Index>(kept.size()));
  for (Index i = 0; i < reference.size(); ++i) {
    const auto at = std::find(kept.begin(), kept.end(), i);
    const Index row = at == kept.end() ? -1 : static_cast<Index>(at - kept.begin());
    ASSERT_EQ(nodes.row_of(i), row) << "node " << i;
    if (row >= 0) {
      EXPECT_EQ(nodes.deck_index(row), i);
      expect_same_node(nodes, row, reference, i);
    }
  }
  EXPECT_EQ(static_cast<Index>(nodes.owned.size()), reference.owned_count());
  // Rows that come in (every seventh node this rank lacks), found as the sorted ones are.
  for (Index i = 0; i < reference.size(); ++i) {
    if (nodes.row_of(i) >= 0 || i % 7 != 0) continue;
    const Index row = nodes.add(reference.row(i), reference.owner[i]);
    EXPECT_EQ(nodes.row_of(i), row);
    expect_same_node(nodes, row, reference, i);
  }
  for (const Index i : kept) EXPECT_EQ(nodes.deck_index(nodes.row_of(i)), i);
  // Rank 0 gathers every rank's own rows; the others keep theirs.
  const Index held = nodes.size();
  nodes.gather_on_first_rank();
  if (ranks.rank() == 0) {
    ASSERT_EQ(nodes.size(), reference.size());
    EXPECT_TRUE(nodes.global.empty());
    for (Index i = 0; i < reference.size(); ++i) {
      EXPECT_EQ(nodes.row_of(i), i);
      expect_same_node(nodes, i, reference, i);
    }
    EXPECT_EQ(nodes.owned, reference.owned);
  } else {
    EXPECT_EQ(nodes.size(), held);
  }
}

TEST(NodeRows, ANodeNoRankKeepsStopsTheGather) {
  const parallel::Communicator& ranks = parallel::world();
  NodeStore nodes = whole_store();
  // The last rank drops its own node of the lowest place in the deck.
  std::vector<Index> kept;
  for (Index i = 0; i < nodes.size(); ++i)
    if (nodes.owns(i)) kept.push_back(i);
  if (ranks.rank() == ranks.size() - 1) {
    ASSERT_FALSE(kept.empty());
    kept.erase(kept.begin());
  }
  nodes.keep(kept);
  if (ranks.rank() == 0)
    EXPECT_THROW(nodes.gather_on_first_rank(), std::logic_error);
  else
    EXPECT_NO_THROW(nodes.gather_on_first_rank());
}

}  // namespace
}  // namespace spall::discretization
