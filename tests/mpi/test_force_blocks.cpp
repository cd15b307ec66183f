// The SPH solid's pair-once force blocks over several ranks (sph::ForceBlocks), run as 1, 2 and 3
// ranks: each block run by one rank, the partial sums handed to the odd blocks' runners after the
// even blocks and to the particles' owners after the odd ones, must leave every particle's sum bit
// for bit as one process takes it, for every way of dealing the particles: cuts inside a block and
// on a block's edge, a rank with fewer particles than half a block (it runs none), an empty rank.
// Each rank holds the sums of its own particles and of those its blocks add to alone, as the SPH
// solid does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/range_array.hpp"
#include "spall/sph/force_blocks.hpp"

namespace spall {
namespace {

constexpr Index particles = 103, length = 8, blocks = (particles + length - 1) / length;  // the last one short
using Sums = RangeArray<Eigen::Vector4d>;

// The term of pair (a, b), b > a: magnitudes over twelve orders, so that the sums' last bits depend
// on the order the terms are taken in.
Eigen::Vector4d term(Index a, Index b) {
  const auto f = [&](double phase) { return std::ldexp(std::sin(0.37 * a + 1.91 * b + phase), (a * b) % 40 - 20); };
  return {f(0), f(1), f(2), 0};
}

// Block `block`'s half rows as the force pass takes them: row a subtracts each term from b, then
// adds its row sum to a (SolidFormulation::compute_pair_forces).
void run_block(const sph::ForceBlocks& blocks, Index block, Sums& sums) {
  for (Index a = blocks.begin(block); a < blocks.end(block); ++a) {
    Eigen::Vector4d row = Eigen::Vector4d::Zero();
    for (Index b = a + 1; b <= std::min(particles - 1, a + length); ++b) {
      row += term(a, b);
      sums[b] -= term(a, b);
    }
    sums[a] += row;
  }
}

// Every particle's sum: the even blocks, then the odd ones, each run by the rank ForceBlocks picks.
Sums pass(const std::vector<Index>& particle_begin) {
  const int rank = parallel::world().rank();
  sph::ForceBlocks force_blocks;
  force_blocks.assign(particles, blocks, length, particle_begin, rank);
  Sums sums;
  sums.assign(particles, Eigen::Vector4d::Zero());
  if (!particle_begin.empty()) {  // dealt: its own particles and those its blocks add to
    Index begin = particle_begin[rank], end = particle_begin[rank + 1];
    if (force_blocks.last_row() > 0) {
      begin = begin < end ? std::min(begin, force_blocks.first_row()) : force_blocks.first_row();
      end = std::max(end, force_blocks.last_touched());
    }
    sums.hold(begin, end);
  }
  for (int parity = 0; parity < 2; ++parity) {
    for (const Index block : force_blocks.run(parity)) run_block(force_blocks, block, sums);
    if (parity == 0)
      force_blocks.after_even(sums);
    else
      force_blocks.after_odd(sums);
  }
  return sums;
}

// The particles dealt at the cuts given (ascending), every rank's sums of its own against one
// process's; returns the particles that differ, over the ranks.
std::int64_t differing(const std::vector<Index>& cuts, const Sums& serial) {
  const parallel::Communicator& ranks = parallel::world();
  std::vector<Index> begin{0};
  begin.insert(begin.end(), cuts.begin(), cuts.end());
  begin.push_back(particles);
  const Sums sums = pass(begin);
  std::int64_t wrong = 0;
  for (Index a = begin[ranks.rank()]; a < begin[ranks.rank() + 1]; ++a) wrong += sums[a] != serial[a];
  ranks.sum({&wrong, 1});
  return wrong;
}

TEST(ForceBlocks, EveryDealSumsEveryParticleAsOneProcess) {
  const Sums serial = pass({});
  // The serial sums are not those of another order (the test could not tell otherwise): the odd
  // blocks first gives other last bits.
  sph::ForceBlocks one;
  one.assign(particles, blocks, length, {}, 0);
  Sums odd_first;
  odd_first.assign(particles, Eigen::Vector4d::Zero());
  for (const int parity : {1, 0})
    for (const Index block : one.run(parity)) run_block(one, block, odd_first);
  Index reordered = 0;
  for (Index a = 0; a < particles; ++a) reordered += odd_first[a] != serial[a];
  ASSERT_GT(reordered, particles / 4);

  const int size = parallel::world().size();
  std::int64_t deals = 0;
  if (size == 1) {
    EXPECT_EQ(differing({}, serial), 0);
    deals = 1;
  } else if (size == 2) {
    for (Index cut = 0; cut <= particles; ++cut, ++deals) EXPECT_EQ(differing({cut}, serial), 0) << "cut " << cut;
  } else {
    for (Index first = 0; first <= particles; first += 3)
      for (Index second = first; second <= particles; second += 5, ++deals)
        EXPECT_EQ(differing({first, second}, serial), 0) << "cuts " << first << ", " << second;
  }
  EXPECT_GT(deals, 0);
}

}  // namespace
}  // namespace spall
