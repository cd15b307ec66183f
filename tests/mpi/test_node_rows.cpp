// A node store with rows of its own (dealt by region, docs/SCALING.md §3, or a window of the node
// order in blocks, §5 step 5), run as 1, 2 and 3 ranks: a rank keeps some rows in an order of its
// own, takes rows that come in from other ranks, finds every row by the node's place in the deck
// (also those added since the last keep), and writes its own rows into a checkpoint on rank 0 (in
// pieces, core/pieces.hpp) that reads back as the whole store, in the deck's order, with each
// node's state, as one process holds it, and into each rank's block of the nodes (a restart under
// MPI) as that block of it; a node that no rank keeps fails the read, on every rank alike.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
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

// A store of every node with the deck's IDs and nothing else, as a restart's set-up builds it
// before the checkpoint is read into it.
NodeStore deck_ids(const NodeStore& whole) {
  NodeStore nodes;
  nodes.resize(whole.size());
  nodes.id = whole.id;
  return nodes;
}

// A rank's block of the nodes of `whole` with the deck's IDs and nothing else, as the set-up in
// blocks builds it before a checkpoint is read into it, dealt by whole's regions as the time loop
// deals it.
NodeStore deck_block(const NodeStore& whole) {
  const parallel::Communicator& ranks = parallel::world();
  const Index first = parallel::block_begin(whole.size(), ranks.rank(), ranks.size());
  const Index end = parallel::block_begin(whole.size(), ranks.rank() + 1, ranks.size());
  NodeStore nodes;
  nodes.resize(end - first);
  for (Index row = 0; row < nodes.size(); ++row) nodes.id[row] = whole.id[first + row];
  nodes.hold_block(first, whole.size());
  nodes.deal(whole.regions, ranks.rank());
  return nodes;
}

// What rank 0's archive holds, on every rank (the others' kept nothing).
std::string written_on_first_rank(const Archive& written) {
  const std::string& mine = written.bytes();
  const std::vector<char> file = parallel::world().all(std::span<const char>(mine.data(), mine.size()));
  return {file.begin(), file.end()};
}

void expect_same_state(const NodeStore& a, Index i, const NodeStore& b, Index j) {
  EXPECT_EQ(a.id[i], b.id[j]);
  EXPECT_EQ(a.part[i], b.part[j]);
  EXPECT_EQ(a.x0[i], b.x0[j]);
  EXPECT_EQ(a.x[i], b.x[j]);
  EXPECT_EQ(a.v[i], b.v[j]);
  EXPECT_EQ(a.mass[i], b.mass[j]);
  EXPECT_EQ(a.fixed[i], b.fixed[j]);
  EXPECT_EQ(a.active[i], b.active[j]);
  EXPECT_EQ(a.body[i], b.body[j]);
}

void expect_same_node(const NodeStore& a, Index i, const NodeStore& b, Index j) {
  expect_same_state(a, i, b, j);
  EXPECT_EQ(a.owner[i], b.owner[j]);
}

TEST(NodeRows, KeptAddedFoundAndCheckpointedWhole) {
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
  // A checkpoint: every rank's own rows, with their forces, go to rank 0's archive in turn, and no
  // rank's rows change; read back into a store of every node (the deck's IDs, nothing else), they
  // are the whole store's rows.
  for (const Index i : nodes.owned) {
    const Index deck = nodes.deck_index(i);
    nodes.f[i] = Vec3(deck, -deck, 2 * deck);
  }
  const NodeStore before = nodes;
  Archive written = ranks.rank() == 0 ? Archive::for_writing() : Archive::discarding();
  nodes.checkpoint(written);
  ASSERT_EQ(nodes.size(), before.size());
  for (Index row = 0; row < nodes.size(); ++row) {
    expect_same_node(nodes, row, before, row);
    EXPECT_EQ(nodes.deck_index(row), before.deck_index(row));
  }
  const std::string file = written_on_first_rank(written);
  NodeStore read = deck_ids(reference);
  Archive archive = Archive::for_reading(file, "checkpoint");
  read.checkpoint(archive);
  EXPECT_TRUE(archive.at_end());
  read.owner = reference.owner;  // a rank's share is the run's, not the checkpoint's
  for (Index i = 0; i < reference.size(); ++i) {
    expect_same_node(read, i, reference, i);
    EXPECT_EQ(read.f[i], Vec3(i, -i, 2 * i)) << "node " << i;
  }
  // Read back into each rank's block of the nodes, as the set-up in blocks builds it and the time
  // loop deals it (a restart under MPI): the block's rows alone, the others' read past.
  NodeStore block = deck_block(reference);
  Archive again = Archive::for_reading(file, "checkpoint");
  block.checkpoint(again);
  EXPECT_TRUE(again.at_end());
  for (Index row = 0; row < block.size(); ++row) {
    const Index i = block.deck_index(row);
    block.owner[row] = reference.owner[i];
    expect_same_node(block, row, reference, i);
    EXPECT_EQ(block.f[row], Vec3(i, -i, 2 * i)) << "node " << i;
  }
}

TEST(NodeRows, ANodeNoRankKeepsIsMissingFromTheCheckpoint) {
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
  Archive written = ranks.rank() == 0 ? Archive::for_writing() : Archive::discarding();
  nodes.checkpoint(written);
  const std::string file = written_on_first_rank(written);
  NodeStore read = deck_ids(whole_store());
  Archive archive = Archive::for_reading(file, "checkpoint");
  EXPECT_THROW(read.checkpoint(archive), InputError);
  // Every rank alike when each reads its block, whichever holds the node.
  NodeStore block = deck_block(whole_store());
  Archive again = Archive::for_reading(file, "checkpoint");
  EXPECT_THROW(block.checkpoint(again), InputError);
}

// A window of the node order (dealt in blocks, docs/SCALING.md §5 step 5): the rows a rank held
// keep their state and force, those it lacked come whole from the ranks that compute them (never
// from a stale copy), a row is its place less the window's first, a new deal first holds the hull
// of the window and the new block (a rank left without nodes among them), and a checkpoint of
// every rank's own rows reads back as the whole store.
TEST(NodeRows, AWindowOfTheNodeOrderHeldDealtAndCheckpointed) {
  const parallel::Communicator& ranks = parallel::world();
  const NodeStore reference = whole_store();
  NodeStore nodes = reference;
  nodes.deal(parallel::block_offsets(nodes.size(), ranks.size()), ranks.rank());
  const Index own_first = nodes.rank_begin[ranks.rank()], own_end = nodes.rank_begin[ranks.rank() + 1];
  // The others' rows go stale here, and this rank's own take forces.
  for (Index i = 0; i < nodes.size(); ++i) {
    if (nodes.owns(i))
      nodes.f[i] = Vec3(i, 1, -i);
    else
      nodes.v[i] = Vec3::Constant(-1 - ranks.rank());
  }
  const auto expect_window = [&](Index first, Index end) {
    ASSERT_TRUE(nodes.windowed());
    ASSERT_EQ(nodes.window_first(), first);
    ASSERT_EQ(nodes.size(), end - first);
    for (Index place = 0; place < reference.size(); ++place)
      ASSERT_EQ(nodes.row_of(place), place >= first && place < end ? place - first : -1) << "node " << place;
    for (Index row = 0; row < nodes.size(); ++row) {
      const Index i = first + row;
      EXPECT_EQ(nodes.deck_index(row), i);
      EXPECT_EQ(nodes.rank_of(row), std::upper_bound(nodes.rank_begin.begin(), nodes.rank_begin.end(), i) -
                                        nodes.rank_begin.begin() - 1);
    }
  };
  long long layout = nodes.layout;
  nodes.hold_window(own_first, own_end);
  expect_window(own_first, own_end);
  EXPECT_GT(nodes.layout, layout);
  EXPECT_EQ(nodes.owned_begin, 0);
  EXPECT_EQ(nodes.owned_end, own_end - own_first);
  for (Index row = 0; row < nodes.size(); ++row) {
    expect_same_state(nodes, row, reference, own_first + row);
    EXPECT_EQ(nodes.f[row], Vec3(own_first + row, 1, -(own_first + row)));
  }
  // Grown by 7 each way: the rows dropped above come back from their ranks, current, force zero.
  const Index first = std::max<Index>(own_first - 7, 0), end = std::min<Index>(own_end + 7, reference.size());
  nodes.hold_window(first, end);
  expect_window(first, end);
  for (Index row = 0; row < nodes.size(); ++row) {
    const Index i = first + row;
    expect_same_state(nodes, row, reference, i);
    EXPECT_EQ(nodes.f[row], nodes.owns(row) ? Vec3(i, 1, -i) : Vec3::Zero()) << "node " << i;
  }
  // Dealt anew with rank 0 left without nodes: each rank's new block among its rows, found by
  // subtraction; the others' rows as they were.
  std::vector<Index> begins(ranks.size() + 1, 0);
  for (int r = 1; r < ranks.size(); ++r) begins[r + 1] = parallel::block_begin(reference.size(), r, ranks.size() - 1);
  begins[ranks.size()] = reference.size();
  layout = nodes.layout;
  const long long partition = nodes.partition;
  nodes.deal(begins, ranks.rank());
  EXPECT_EQ(nodes.partition, partition + 1);
  EXPECT_GT(nodes.layout, layout);
  const Index new_first = begins[ranks.rank()], new_end = begins[ranks.rank() + 1];
  const bool own_nodes = new_first < new_end;
  expect_window(own_nodes ? std::min(first, new_first) : first, own_nodes ? std::max(end, new_end) : end);
  EXPECT_EQ(nodes.owned_count(), new_end - new_first);
  for (Index k = 0; k < nodes.owned_count(); ++k) {
    const Index row = nodes.owned_node(k);
    EXPECT_EQ(nodes.deck_index(row), new_first + k);
    EXPECT_TRUE(nodes.owns(row));
    expect_same_state(nodes, row, reference, new_first + k);
  }
  // A checkpoint: each rank's own rows in pieces, read back into every node as one process holds it.
  for (Index k = 0; k < nodes.owned_count(); ++k) {
    const Index i = nodes.deck_index(nodes.owned_node(k));
    nodes.f[nodes.owned_node(k)] = Vec3(i, -i, 2 * i);
  }
  Archive written = ranks.rank() == 0 ? Archive::for_writing() : Archive::discarding();
  nodes.checkpoint(written);
  const std::string file = written_on_first_rank(written);
  NodeStore read = deck_ids(reference);
  Archive archive = Archive::for_reading(file, "checkpoint");
  read.checkpoint(archive);
  EXPECT_TRUE(archive.at_end());
  for (Index i = 0; i < reference.size(); ++i) {
    expect_same_state(read, i, reference, i);
    EXPECT_EQ(read.f[i], Vec3(i, -i, 2 * i)) << "node " << i;
  }
}

}  // namespace
}  // namespace spall::discretization
