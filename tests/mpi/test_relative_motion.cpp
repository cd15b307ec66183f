// neighbors::close_pairs_moved_together over several ranks (the SPH solid's list rebuild test when
// each rank holds current only its own particles' positions), run as 1, 2 and 3 ranks: each rank
// passes its block of the particles and stale positions (NaN) for the rest, and every rank must
// give the answer one process gives over all of them. Particles stored in lattice order (each
// rank's block a slab: neighbouring ranks' cells meet in a layer) and shuffled (every rank's
// cells spread over the whole grid).
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <limits>
#include <random>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/neighbors/relative_motion.hpp"

namespace spall::neighbors {
namespace {

constexpr Real distance = 1.5;  // close pairs: the lattice's nearest and diagonal neighbours
constexpr Real limit = 0.2;     // the skin

struct Motion {
  std::vector<Vec3> before, now;
};

// A 6 x 6 x 18 lattice of spacing 1, z slowest, displaced by d(p) from its place p; `shuffled`
// stores the particles in a random order instead.
using Displacement = std::function<Vec3(const Vec3&)>;

Motion lattice(const Displacement& displacement, bool shuffled) {
  Motion m;
  for (int z = 0; z < 18; ++z)
    for (int y = 0; y < 6; ++y)
      for (int x = 0; x < 6; ++x) m.before.emplace_back(x, y, z);
  if (shuffled) std::shuffle(m.before.begin(), m.before.end(), std::mt19937(7));
  for (const Vec3& p : m.before) m.now.push_back(p + displacement(p));
  return m;
}

// The answer of every rank, each given its own block's positions only, and checked to agree.
bool distributed_answer(const Motion& m) {
  const parallel::Communicator& ranks = parallel::world();
  const auto blocks = parallel::block_offsets(static_cast<Index>(m.now.size()), ranks.size());
  const ParticleRange own{blocks[ranks.rank()], blocks[ranks.rank() + 1]};
  std::vector<Vec3> x(m.now.size(), Vec3::Constant(std::numeric_limits<Real>::quiet_NaN()));
  std::copy(m.now.begin() + own.begin, m.now.begin() + own.end, x.begin() + own.begin);
  const bool answer = close_pairs_moved_together(x, m.before, distance, limit, own, ranks);
  double lowest = answer ? 1 : 0, highest = answer ? -1 : 0;  // the answers' minimum and -maximum
  ranks.minimum({&lowest, 1}), ranks.minimum({&highest, 1});
  EXPECT_EQ(lowest, -highest) << "the ranks disagree";
  return answer;
}

void expect_answer(const Displacement& displacement, bool expected) {
  for (bool shuffled : {false, true}) {
    const Motion m = lattice(displacement, shuffled);
    // What one process answers, by the triangle-inequality argument of relative_motion.cpp.
    EXPECT_EQ(close_pairs_moved_together(m.now, m.before, distance, limit), expected) << "shuffled " << shuffled;
    EXPECT_EQ(distributed_answer(m), expected) << "shuffled " << shuffled;
  }
}

TEST(RelativeMotionOverRanks, ARigidTranslationPasses) {
  expect_answer([](const Vec3&) { return Vec3(3, -2, 5); }, true);
}

// Neighbours move 0.05 apart along z, the ends 0.85: the global test fails, the cells' passes.
TEST(RelativeMotionOverRanks, AStretchWhoseNeighboursMoveTogetherPasses) {
  expect_answer([](const Vec3& p) { return Vec3(0, 0, 0.05 * p.z()); }, true);
}

// The same stretch, and the two layers where rank 0's slab meets rank 1's (in lattice order; the
// middle for one rank) moved 0.15 sideways in opposite directions: 0.3 apart from their neighbours
// across.
TEST(RelativeMotionOverRanks, NeighboursMovingApartAcrossARankBoundaryFail) {
  const int ranks = parallel::world().size();
  const Real above = ranks == 1 ? 9 : static_cast<Real>(parallel::block_offsets(648, ranks)[1] / 36);
  expect_answer(
      [&](const Vec3& p) {
        const Real side = p.z() == above - 1 ? 0.15 : p.z() == above ? -0.15 : 0;
        return Vec3(side, 0, 0.05 * p.z());
      },
      false);
}

// One pair near an end moves 0.25 apart (the far corner of the last slab).
TEST(RelativeMotionOverRanks, OnePairMovingApartFails) {
  expect_answer([](const Vec3& p) { return p == Vec3(5, 5, 17) ? Vec3(0.25, 0, 0) : Vec3(0, 0, 0); }, false);
}

TEST(RelativeMotionOverRanks, ANonFinitePositionFails) {
  expect_answer(
      [](const Vec3& p) {
        return p == Vec3(0, 0, 0) ? Vec3::Constant(std::numeric_limits<Real>::infinity()) : Vec3(0.01, 0, 0);
      },
      false);
}

}  // namespace
}  // namespace spall::neighbors
