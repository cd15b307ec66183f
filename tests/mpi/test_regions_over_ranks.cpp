// Recursive coordinate bisection over the ranks (discretization::Regions::cut with a communicator),
// run as 1, 2 and 3 ranks: each rank brings some of the points, and every rank gets the cuts that
// one process finds with all of them (whose rule test_regions checks against a brute force), bit
// for bit, however the points are shared: dealt at random, all on the last rank, a rank with
// none; random points with random weights, a lattice with weightless points, points of one
// coordinate, no weight anywhere, a point that ran away; 1 to 9 regions, more than the ranks.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/discretization/regions.hpp"

namespace spall::discretization {
namespace {

struct Points {
  std::vector<Vec3> x;
  std::vector<double> w;
};

// The points of rank `rank`: point i goes to holder[i].
Points share_of(const Points& all, const std::vector<int>& holder, int rank) {
  Points mine;
  for (std::size_t i = 0; i < all.x.size(); ++i)
    if (holder[i] == rank) mine.x.push_back(all.x[i]), mine.w.push_back(all.w[i]);
  return mine;
}

void expect_same_cuts_however_shared(const Points& all, const char* what) {
  const parallel::Communicator& ranks = parallel::world();
  std::mt19937 random(17);  // the same draws on every rank
  const int size = ranks.size();
  std::vector<std::vector<int>> holders;
  std::vector<int> holder(all.x.size());
  for (int& h : holder) h = std::uniform_int_distribution<int>(0, size - 1)(random);
  holders.push_back(holder);
  holders.emplace_back(all.x.size(), size - 1);  // all on the last rank
  for (std::size_t i = 0; i < all.x.size(); ++i) holder[i] = size > 1 ? 1 + static_cast<int>(i) % (size - 1) : 0;
  holders.push_back(holder);  // rank 0 with none
  for (const int regions : {1, 2, 3, 4, 7, 9})
    for (std::size_t h = 0; h < holders.size(); ++h) {
      const Points mine = share_of(all, holders[h], ranks.rank());
      const Regions shared = Regions::cut(mine.x, mine.w, regions, ranks);
      const Regions whole = Regions::cut(all.x, all.w, regions);
      EXPECT_TRUE(shared == whole) << what << ", " << regions << " regions, sharing " << h;
      EXPECT_EQ(shared.ranks(), regions);
    }
}

TEST(RegionsOverRanks, RandomPointsAndWeights) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> u(0, 1), weight(0.5, 2);
  Points all;
  for (int i = 0; i < 700; ++i) {
    all.x.emplace_back(3 * u(random), 2 * u(random), u(random));
    all.w.push_back(weight(random));
  }
  expect_same_cuts_however_shared(all, "random points");
}

TEST(RegionsOverRanks, LatticeWithWeightlessPoints) {
  Points all;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 6; ++j)
      for (int k = 0; k < 3; ++k) {
        all.x.emplace_back(0.1 * i, 0.1 * j, -0.1 * k);
        all.w.push_back((i + j) % 4 == 0 ? 0.0 : 1.0);
      }
  expect_same_cuts_however_shared(all, "lattice");
}

TEST(RegionsOverRanks, DegeneratePoints) {
  Points stacked{std::vector<Vec3>(9, Vec3(1, 2, 3)), std::vector<double>(9, 1.0)};
  expect_same_cuts_however_shared(stacked, "one coordinate");
  Points weightless{{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0), Vec3(-0.0, 1, 0)},
                    std::vector<double>(5, 0.0)};
  expect_same_cuts_however_shared(weightless, "no weight");
  std::mt19937 random(8);
  std::uniform_real_distribution<double> u(-1, 1);
  Points ran_away;
  for (int i = 0; i < 40; ++i) ran_away.x.emplace_back(u(random), u(random), u(random)), ran_away.w.push_back(1);
  ran_away.x[6] = Vec3(std::numeric_limits<Real>::quiet_NaN(), 0, 0);
  expect_same_cuts_however_shared(ran_away, "a point that ran away");
  expect_same_cuts_however_shared(Points{}, "no points");
}

}  // namespace
}  // namespace spall::discretization
