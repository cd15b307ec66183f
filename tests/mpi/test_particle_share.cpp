// discretization::ParticleShare, run as 1, 2 and 3 ranks: each rank fills in the particles whose
// node it owns (the nodes dealt out in blocks, as the time loop deals them), and after the share
// every rank holds every particle's value: particles stored in node order (in place), in a
// shuffled order, the same or each rank's own (gathered by rank and node and put back), with the
// nodes dealt by region, on a few nodes only (ranks with no particle),
// stored anew in another order (planned again), several values a particle, rows of different
// lengths (shared whole, or completed from the rows each rank made for its own particles); and
// discretization::ReachShare, which brings in only the particles a rank reads (a value each, or rows).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <stdexcept>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/discretization/particle_share.hpp"
#include "spall/discretization/reach_share.hpp"

namespace spall::discretization {
namespace {

struct Value {
  double x;
  int node;
};

// A store of node_count nodes dealt out to the ranks as the time loop deals them.
NodeStore dealt_nodes(Index node_count) {
  const parallel::Communicator& ranks = parallel::world();
  NodeStore nodes;
  nodes.resize(node_count);
  nodes.deal(parallel::block_offsets(node_count, ranks.size()), ranks.rank());
  return nodes;
}

// Fills in, on every rank, the values of its own particles on `node` and shares them.
void fill_and_share(ParticleShare& share, const std::vector<Index>& node, std::vector<Value>& values) {
  values.assign(node.size(), Value{-1.0, -1});
  for (std::size_t a = 0; a < node.size(); ++a)
    if (share.owns(node[a])) values[a] = Value{0.5 * node[a], static_cast<int>(node[a])};
  std::vector<Value> none;
  share(node, values, none);  // none: an array the options switched off, left empty
  EXPECT_TRUE(none.empty());
}

void expect_every_value(const std::vector<Index>& node, const std::vector<Value>& values) {
  for (std::size_t a = 0; a < node.size(); ++a) {
    EXPECT_EQ(values[a].x, 0.5 * node[a]) << "particle " << a;
    EXPECT_EQ(values[a].node, node[a]) << "particle " << a;
  }
}

// Shares, on every rank, the values of particles on `node` (of node_count nodes) and checks them.
void check_share(const std::vector<Index>& node, Index node_count) {
  ParticleShare share;
  share.bind(dealt_nodes(node_count));
  std::vector<Value> values;
  fill_and_share(share, node, values);
  expect_every_value(node, values);
}

TEST(ParticleShare, ParticlesInNodeOrderWithNodesOfNoParticle) {
  std::vector<Index> node(100);
  for (Index a = 0; a < 100; ++a) node[a] = 3 * a + 1;  // every third node
  check_share(node, 301);
}

TEST(ParticleShare, ParticlesInAnyOrder) {
  std::vector<Index> node(257);
  std::iota(node.begin(), node.end(), Index(0));
  std::shuffle(node.begin(), node.end(), std::mt19937(35));  // the same on every rank
  check_share(node, 300);
  // Each rank's order its own (the fluid's cells near a rank's region): by node they agree.
  std::shuffle(node.begin(), node.end(), std::mt19937(36 + parallel::world().rank()));
  check_share(node, 300);
}

// Nodes dealt by region (RCB over random positions, so a rank's nodes are no block), the particles
// stored in an order of each rank's own.
TEST(ParticleShare, NodesDealtByRegion) {
  const parallel::Communicator& ranks = parallel::world();
  const Index n = 211;
  NodeStore nodes;
  nodes.resize(n);
  std::mt19937 random(41);
  std::uniform_real_distribution<double> u(0, 1);
  for (auto& p : nodes.x) p = Vec3(u(random), u(random), u(random));
  nodes.deal(Regions::cut(nodes.x, std::vector<double>(n, 1.0), ranks.size()), ranks.rank());
  std::vector<Index> node(n);
  std::iota(node.begin(), node.end(), Index(0));
  std::shuffle(node.begin(), node.end(), std::mt19937(43 + ranks.rank()));
  ParticleShare share;
  share.bind(nodes);
  std::vector<Value> values;
  fill_and_share(share, node, values);
  expect_every_value(node, values);
}

TEST(ParticleShare, RanksWithoutParticles) {
  // Particles on the first tenth of the nodes only: the last ranks own none of them.
  std::vector<Index> node = {7, 3, 0, 9, 5};
  check_share(node, 100);
  check_share({}, 100);
}

TEST(ParticleShare, PlannedAgainWhenTheParticlesAreStoredInAnotherOrder) {
  std::vector<Index> node(90);
  std::iota(node.begin(), node.end(), Index(0));
  ParticleShare share;
  share.bind(dealt_nodes(90));
  std::vector<Value> values;
  fill_and_share(share, node, values);  // in node order: in place
  expect_every_value(node, values);
  std::reverse(node.begin(), node.end());
  share.reorder();
  fill_and_share(share, node, values);  // reversed: gathered by rank and put back
  expect_every_value(node, values);
}

TEST(ParticleShare, PlannedAgainWhenTheNodesAreDealtAnew) {
  std::vector<Index> node(80);
  std::iota(node.begin(), node.end(), Index(0));
  NodeStore nodes = dealt_nodes(80);
  ParticleShare share;
  share.bind(nodes);
  std::vector<Value> values;
  fill_and_share(share, node, values);
  expect_every_value(node, values);
  // The time loop's rebalancing: rank 0 gets the first 5 nodes, the last rank the rest but 5.
  const int ranks = parallel::world().size();
  std::vector<Index> begins(ranks + 1, 75);
  begins[0] = 0;
  if (ranks > 1) begins[1] = 5;
  begins[ranks] = 80;
  nodes.deal(begins, parallel::world().rank());
  share.bind(nodes);
  EXPECT_EQ(share.owns(4), parallel::world().rank() == 0);
  fill_and_share(share, node, values);
  expect_every_value(node, values);
}

TEST(ParticleShare, SeveralValuesAParticle) {
  // Three values a particle (an element's points), the particles in a shuffled order.
  std::vector<Index> node(61);
  std::iota(node.begin(), node.end(), Index(0));
  std::shuffle(node.begin(), node.end(), std::mt19937(36));
  ParticleShare share;
  share.bind(dealt_nodes(61));
  std::vector<double> values(3 * node.size(), -1.0);
  for (std::size_t a = 0; a < node.size(); ++a)
    if (share.owns(node[a]))
      for (int k = 0; k < 3; ++k) values[3 * a + k] = 10.0 * node[a] + k;
  share(node, values);
  for (std::size_t a = 0; a < node.size(); ++a)
    for (int k = 0; k < 3; ++k) EXPECT_EQ(values[3 * a + k], 10.0 * node[a] + k) << "particle " << a;
  std::vector<double> ragged(node.size() + 1);  // not a whole number of values a particle
  if (parallel::world().size() > 1) {
    EXPECT_THROW(share(node, ragged), std::logic_error);
  }
}

// Rows of different lengths (SPG bonds): particle a has a % 4 entries, entry e of it worth
// 100 a + e.
std::vector<Index> row_offsets_of(Index n) {
  std::vector<Index> offsets(n + 1, 0);
  for (Index a = 0; a < n; ++a) offsets[a + 1] = offsets[a] + a % 4;
  return offsets;
}

// ReachShare: each rank reads a few particles of the others' (those within `reach` of its own, in
// a storage order of each rank's own, and one far away), writes -1 into every particle it does not
// own, and after the share holds the true values of exactly the particles it reads; the rest stay
// -1. Also with the node store's rows in an order of each rank's own (dealt by region): the
// particles are asked for by their nodes' places in the deck.
TEST(ReachShare, BringsInWhatEachRankReadsAndNothingElse) {
  const Index n = 203;
  for (const bool own_rows : {false, true}) {
    NodeStore nodes = dealt_nodes(n);
    if (own_rows) {  // dealt by region along x instead, in rows of each rank's own order
      for (Index i = 0; i < n; ++i) nodes.x[i] = Vec3(i, 0, 0);
      const parallel::Communicator& ranks = parallel::world();
      nodes.deal(Regions::cut(nodes.x, std::vector<double>(n, 1.0), ranks.size()), ranks.rank());
      std::vector<Index> rows(n);
      std::iota(rows.begin(), rows.end(), Index(0));
      std::shuffle(rows.begin(), rows.end(), std::mt19937(11 + parallel::world().rank()));
      nodes.keep(rows);
    }
    std::vector<Index> node(n);
    std::iota(node.begin(), node.end(), Index(0));
    std::shuffle(node.begin(), node.end(), std::mt19937(37 + parallel::world().rank()));  // each rank's own order
    const auto deck = [&](Index a) { return nodes.deck_index(node[a]); };
    ParticleShare share;
    share.bind(nodes);
    std::vector<std::uint8_t> reads(n, 0);
    for (Index a = 0; a < n; ++a)
      for (Index reach = -3; reach <= 3; ++reach)
        if (share.owns(nodes.row_of(std::clamp(deck(a) + reach, Index(0), n - 1)))) reads[a] = 1;
    for (Index a = 0; a < n; ++a)
      if (deck(a) == 0) reads[a] = 1;  // every rank reads node 0
    ReachShare reach;
    EXPECT_FALSE(reach.planned());
    reach.plan(reads, node, share, nodes);
    EXPECT_TRUE(reach.planned());
    std::vector<Value> values(n, Value{-1.0, -1});
    std::vector<double> doubled(n, -1.0), none;
    for (Index a = 0; a < n; ++a)
      if (share.owns(node[a])) values[a] = Value{0.5 * deck(a), static_cast<int>(deck(a))}, doubled[a] = 2.0 * deck(a);
    reach(values, none, doubled);
    EXPECT_TRUE(none.empty());
    Index read_of_others = 0;
    for (Index a = 0; a < n; ++a) {
      const bool known = share.owns(node[a]) || reads[a];
      read_of_others += reads[a] && !share.owns(node[a]);
      EXPECT_EQ(values[a].x, known ? 0.5 * deck(a) : -1.0) << "particle " << a << ", own rows " << own_rows;
      EXPECT_EQ(values[a].node, known ? deck(a) : -1) << "particle " << a << ", own rows " << own_rows;
      EXPECT_EQ(doubled[a], known ? 2.0 * deck(a) : -1.0) << "particle " << a << ", own rows " << own_rows;
    }
    EXPECT_EQ(reach.received(), read_of_others);
    // What the ranks receive, they send: the totals agree.
    std::int64_t counts[2] = {reach.sent(), reach.received()};
    parallel::world().sum(counts);
    EXPECT_EQ(counts[0], counts[1]);
  }
}

// ReachShare::rows: rows of different lengths (particle a has a % 4 entries, some none) of two
// arrays of different types; each rank holds the true rows of its own particles and of those it
// reads (the particles within 2 of its own in the node order), every other entry stays -1.
TEST(ReachShare, BringsInTheRowsEachRankReads) {
  const Index n = 70;
  std::vector<Index> node(n);
  for (Index a = 0; a < n; ++a) node[a] = 2 * a;  // in node order, every other node
  const NodeStore nodes = dealt_nodes(2 * n);
  ParticleShare share;
  share.bind(nodes);
  std::vector<std::uint8_t> reads(n, 0);
  for (Index a = 0; a < n; ++a)
    for (Index b = std::max<Index>(a - 2, 0); b <= std::min<Index>(a + 2, n - 1); ++b)
      if (share.owns(node[b])) reads[a] = 1;
  ReachShare reach;
  reach.plan(reads, node, share, nodes);
  const std::vector<Index> offsets = row_offsets_of(n);
  std::vector<double> entries(offsets.back(), -1.0), none;
  std::vector<Vec3> vectors(offsets.back(), Vec3::Constant(-1.0));
  for (Index a = 0; a < n; ++a)
    if (share.owns(node[a]))
      for (Index k = offsets[a]; k < offsets[a + 1]; ++k) {
        entries[k] = 100.0 * a + (k - offsets[a]);
        vectors[k] = Vec3(a, k, -a);
      }
  reach.rows(offsets, entries, none, vectors);
  EXPECT_TRUE(none.empty());
  for (Index a = 0; a < n; ++a) {
    const bool known = share.owns(node[a]) || reads[a];
    for (Index k = offsets[a]; k < offsets[a + 1]; ++k) {
      EXPECT_EQ(entries[k], known ? 100.0 * a + (k - offsets[a]) : -1.0) << "particle " << a;
      EXPECT_EQ(vectors[k], known ? Vec3(a, k, -a) : Vec3::Constant(-1.0)) << "particle " << a;
    }
  }
}

TEST(ParticleShare, EveryParticleOwnedUntilBound) {
  const ParticleShare share;
  EXPECT_TRUE(share.owns(0));
  EXPECT_TRUE(share.owns(1'000'000));
}

}  // namespace
}  // namespace spall::discretization
