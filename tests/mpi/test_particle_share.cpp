// discretization::ParticleShare, run as 1, 2 and 3 ranks: each rank fills in the particles whose
// node it owns (the nodes dealt out in blocks, as the time loop deals them), and after the share
// every rank holds every particle's value: particles stored in node order (in place), in a
// shuffled order (gathered by rank and put back), on a few nodes only (ranks with no particle).
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/discretization/particle_share.hpp"

namespace spall::discretization {
namespace {

struct Value {
  double x;
  int node;
};

// Shares, on every rank, the values of particles on `node` (of node_count nodes) and checks them.
void check_share(const std::vector<Index>& node, Index node_count) {
  const parallel::Communicator& ranks = parallel::world();
  const Index begin = parallel::block_begin(node_count, ranks.rank(), ranks.size());
  const Index end = parallel::block_begin(node_count, ranks.rank() + 1, ranks.size());
  std::vector<Value> values(node.size(), Value{-1.0, -1});
  for (std::size_t a = 0; a < node.size(); ++a)
    if (node[a] >= begin && node[a] < end) values[a] = Value{0.5 * node[a], static_cast<int>(node[a])};
  const ParticleShare share(node, node_count);
  share(values);
  for (std::size_t a = 0; a < node.size(); ++a) {
    EXPECT_EQ(values[a].x, 0.5 * node[a]) << "particle " << a;
    EXPECT_EQ(values[a].node, node[a]) << "particle " << a;
  }
  std::vector<Value> none;
  share(none);  // an array the options switched off: nothing
  EXPECT_TRUE(none.empty());
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
}

TEST(ParticleShare, RanksWithoutParticles) {
  // Particles on the first tenth of the nodes only: the last ranks own none of them.
  std::vector<Index> node = {7, 3, 0, 9, 5};
  check_share(node, 100);
  check_share({}, 100);
}

}  // namespace
}  // namespace spall::discretization

int main(int argc, char** argv) {
  const spall::parallel::Session session;
  testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}
