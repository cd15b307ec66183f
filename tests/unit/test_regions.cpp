// Recursive coordinate bisection (discretization::Regions; Berger & Bokhari 1987): each cut is
// across the longest side of its points' box, where the weight below it comes nearest the share
// of the ranks below it, never splitting points of one coordinate. Checked against that
// specification directly: a brute-force search of every cut a split could have taken, counts a
// rank within one point a level of its share, whole lattice planes, weights, and the nodes'
// ranks following their positions (NodeStore::migrate).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "spall/discretization/node_store.hpp"
#include "spall/discretization/regions.hpp"

namespace spall::discretization {
namespace {

std::vector<Vec3> random_points(int n, const Vec3& size, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> u(0, 1);
  std::vector<Vec3> x(n);
  for (auto& p : x) p = Vec3(u(random), u(random), u(random)).cwiseProduct(size);
  return x;
}

std::vector<int> counts(const Regions& regions, const std::vector<Vec3>& x, int ranks) {
  std::vector<int> count(ranks, 0);
  for (const auto& p : x) {
    const int r = regions.rank_of(p);
    EXPECT_GE(r, 0);
    EXPECT_LT(r, ranks);
    if (r >= 0 && r < ranks) ++count[r];
  }
  return count;
}

// Distinct coordinates: every rank holds n / ranks points to within one point a level of the tree
// (each cut is off its share by at most half a point, and a side's share rounds once more below).
TEST(Regions, RandomPointsShareEvenly) {
  const int n = 1001;
  const auto x = random_points(n, Vec3(3, 2, 1), 7);
  const std::vector<double> w(n, 1.0);
  for (int ranks : {1, 2, 3, 4, 5, 7, 8, 16, 33}) {
    const Regions regions = Regions::cut(x, w, ranks);
    EXPECT_EQ(regions.ranks(), ranks);
    const auto count = counts(regions, x, ranks);
    const double levels = std::ceil(std::log2(ranks));
    for (int r = 0; r < ranks; ++r)
      EXPECT_LE(std::abs(count[r] - double(n) / ranks), levels) << ranks << " ranks, rank " << r;
  }
}

// Two ranks: the cut is across x (the longest side) and no other cut along x puts a weight nearer
// half below it (brute force over every plane between two points).
TEST(Regions, TwoRanksTakeTheBestCutAlongTheLongestSide) {
  const int n = 400;
  auto x = random_points(n, Vec3(1, 4, 2), 11);
  std::vector<double> w(n);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(0.5, 2);
  for (double& wi : w) wi = u(random);
  const Regions regions = Regions::cut(x, w, 2);
  double low = 0, total = 0;
  Real highest_low = -std::numeric_limits<Real>::infinity(), lowest_high = std::numeric_limits<Real>::infinity();
  for (int i = 0; i < n; ++i) {
    total += w[i];
    if (regions.rank_of(x[i]) == 0) {
      low += w[i];
      highest_low = std::max(highest_low, x[i][1]);
    } else {
      lowest_high = std::min(lowest_high, x[i][1]);
    }
  }
  EXPECT_LT(highest_low, lowest_high) << "the two sides overlap along y";
  double best = std::numeric_limits<double>::infinity();
  for (int k = 0; k < n; ++k) {
    double below = 0;
    for (int i = 0; i < n; ++i)
      if (x[i][1] <= x[k][1]) below += w[i];
    best = std::min(best, std::abs(below - total / 2));
  }
  EXPECT_DOUBLE_EQ(std::abs(low - total / 2), best);
}

// A lattice of 10 x 4 x 4 points on 2 and 3 ranks: whole planes x = const to each rank, the one
// cut along x nearest the share (2 ranks: 5 planes each; 3 ranks: 3 planes below, 48 points, being
// nearer 160 / 3 than 4 planes, 64).
TEST(Regions, LatticePlanesStayWhole) {
  std::vector<Vec3> x;
  for (int i = 0; i < 10; ++i)
    for (int j = 0; j < 4; ++j)
      for (int k = 0; k < 4; ++k) x.emplace_back(0.1 * i, 0.1 * j, 0.1 * k);
  const std::vector<double> w(x.size(), 1.0);
  for (int ranks : {2, 3}) {
    const Regions regions = Regions::cut(x, w, ranks);
    for (int i = 0; i < 10; ++i) {
      const int r = regions.rank_of(Vec3(0.1 * i, 0, 0));
      for (int j = 0; j < 4; ++j)
        for (int k = 0; k < 4; ++k) EXPECT_EQ(regions.rank_of(Vec3(0.1 * i, 0.1 * j, 0.1 * k)), r);
    }
    const auto count = counts(regions, x, ranks);
    if (ranks == 2) {
      EXPECT_EQ(count, (std::vector<int>{80, 80}));
    } else {
      EXPECT_EQ(count[0], 48);
    }
  }
}

// Two cuts as near their share: the lower is taken (three points of weight 1 on 2 ranks: 1 and 2
// below are both half a point off 1.5). A weightless point is a coordinate like any other: the
// cut after x = 1 (1 below, the share) is taken, not the one after the weightless x = 2, as near.
TEST(Regions, TiesTakeTheLowerCut) {
  const std::vector<Vec3> row{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  const Regions ties = Regions::cut(row, std::vector<double>(3, 1.0), 2);
  EXPECT_EQ(counts(ties, row, 2), (std::vector<int>{1, 2}));
  EXPECT_EQ(ties.box(0).upper[0], 0.5);
  const std::vector<Vec3> four{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  const Regions weightless = Regions::cut(four, std::vector<double>{0, 1, 0, 1}, 2);
  EXPECT_EQ(weightless.box(0).upper[0], 1.5);
}

// Weights: points of weight 0 count for nothing, heavier ones for more.
TEST(Regions, WeightsNotCounts) {
  const int n = 1000;
  const auto x = random_points(n, Vec3(2, 1, 1), 5);
  std::vector<double> w(n);
  for (int i = 0; i < n; ++i) w[i] = x[i][0] < 0.5 ? 3.0 : x[i][0] < 1.5 ? 1.0 : 0.0;
  for (int ranks : {2, 4}) {
    const Regions regions = Regions::cut(x, w, ranks);
    std::vector<double> weight(ranks, 0);
    double total = 0;
    for (int i = 0; i < n; ++i) weight[regions.rank_of(x[i])] += w[i], total += w[i];
    for (int r = 0; r < ranks; ++r) EXPECT_LE(std::abs(weight[r] - total / ranks), 3.0 * 2) << ranks << " " << r;
  }
}

// Each region's box holds the points of its rank, and a point of space lies in its rank's box (on
// a face, in both boxes that share it).
TEST(Regions, BoxesHoldTheirRanksPoints) {
  const auto x = random_points(600, Vec3(3, 2, 1), 13);
  const int ranks = 7;
  const Regions regions = Regions::cut(x, std::vector<double>(x.size(), 1.0), ranks);
  const auto inside = [](const BoundingBox& b, const Vec3& p) {
    return (p.array() >= b.lower.array()).all() && (p.array() <= b.upper.array()).all();
  };
  for (const auto& p : x) EXPECT_TRUE(inside(regions.box(regions.rank_of(p)), p));
  const auto far = random_points(2000, Vec3(9, 6, 3), 17);
  for (const Vec3& q : far) {
    const Vec3 p = q - Vec3(3, 2, 1);  // points beyond every side too
    int boxes = 0;
    for (int r = 0; r < ranks; ++r) boxes += inside(regions.box(r), p);
    EXPECT_TRUE(inside(regions.box(regions.rank_of(p)), p));
    EXPECT_EQ(boxes, 1) << "a point off every face lies in one box";
  }
}

// near(): the ranks whose region's box grown by the reach holds a point, as a test of every box
// finds them, in rank order; points on the cuts, on their grown faces, beyond every side.
TEST(Regions, NearFindsEveryGrownBoxThatHoldsThePoint) {
  const auto x = random_points(300, Vec3(3, 2, 1), 21);
  for (const int ranks : {1, 2, 5, 8}) {
    const Regions regions = Regions::cut(x, std::vector<double>(x.size(), 1.0), ranks);
    const Real reach = 0.25;
    auto probes = random_points(3000, Vec3(4, 3, 2), 23);
    for (Vec3& p : probes) p -= Vec3(0.5, 0.5, 0.5);
    for (int r = 0; r < ranks; ++r) {  // on the faces and on the grown faces
      const BoundingBox box = regions.box(r);
      for (int d = 0; d < 3; ++d)
        for (const Real c : {box.lower[d], box.upper[d], box.lower[d] - reach, box.upper[d] + reach})
          if (std::isfinite(c)) probes.push_back(Vec3(1.5, 1, 0.5)), probes.back()[d] = c;
    }
    for (const Vec3& p : probes) {
      std::vector<int> found, expected;
      regions.near(p, reach, [&](int r) { found.push_back(r); });
      for (int r = 0; r < ranks; ++r)
        if (regions.box(r).grown(reach).contains(p)) expected.push_back(r);
      EXPECT_EQ(found, expected) << ranks << " ranks, point " << p.transpose();
    }
  }
}

// BoundingBox::meets, by which a rank picks the ranks its particles may go to (near_particles):
// boxes that touch at a face or a corner meet, boxes apart by any gap do not, an empty box meets
// none, and two boxes that both contain a point meet.
TEST(Regions, BoxesMeetWhereTheyShareAPoint) {
  BoundingBox unit;
  unit.include(Vec3(0, 0, 0)), unit.include(Vec3(1, 1, 1));
  BoundingBox face = unit, corner = unit, apart = unit;
  face.lower[0] = 1, face.upper[0] = 2;
  corner.lower = Vec3(1, 1, 1), corner.upper = Vec3(2, 2, 2);
  apart.lower[1] = std::nextafter(Real(1), Real(2)), apart.upper[1] = 2;
  EXPECT_TRUE(unit.meets(face) && face.meets(unit));
  EXPECT_TRUE(unit.meets(corner) && corner.meets(unit));
  EXPECT_FALSE(unit.meets(apart) || apart.meets(unit));
  EXPECT_FALSE(unit.meets(BoundingBox{}) || BoundingBox{}.meets(unit));
  const auto corners = random_points(400, Vec3(2, 2, 2), 31), probes = random_points(200, Vec3(2, 2, 2), 37);
  for (std::size_t k = 0; k + 3 < corners.size(); k += 4) {
    BoundingBox a, b;
    a.include(corners[k]), a.include(corners[k + 1]), b.include(corners[k + 2]), b.include(corners[k + 3]);
    for (const Vec3& p : probes) {
      if (a.contains(p) && b.contains(p)) {
        EXPECT_TRUE(a.meets(b) && b.meets(a)) << p.transpose();
      }
    }
    // Apart along some axis exactly when they do not meet.
    bool apart_along_an_axis = false;
    for (int d = 0; d < 3; ++d) apart_along_an_axis |= a.upper[d] < b.lower[d] || b.upper[d] < a.lower[d];
    EXPECT_EQ(a.meets(b), !apart_along_an_axis);
  }
}

// Regions in order along the longest side: a rod along z on 4 ranks.
TEST(Regions, RodCutAcrossItsLength) {
  const auto x = random_points(500, Vec3(0.1, 0.2, 5), 9);
  const Regions regions = Regions::cut(x, std::vector<double>(x.size(), 1.0), 4);
  int last = 0;
  for (double z = -1; z <= 6; z += 0.01) {
    const int r = regions.rank_of(Vec3(0.05, 0.1, z));
    EXPECT_GE(r, last);
    last = r;
  }
  EXPECT_EQ(last, 3);
}

// No points, every point in one place, no point with weight, a point that ran away (NaN): every
// point of space still has a rank.
TEST(Regions, DegenerateInputsStillCoverSpace) {
  const std::vector<Vec3> none;
  const Regions empty = Regions::cut(none, {}, 3);
  EXPECT_GE(empty.rank_of(Vec3(1, 2, 3)), 0);
  EXPECT_LT(empty.rank_of(Vec3(1, 2, 3)), 3);
  const std::vector<Vec3> same(6, Vec3(1, 1, 1));
  const Regions stacked = Regions::cut(same, std::vector<double>(6, 1.0), 2);
  EXPECT_EQ(counts(stacked, same, 2), (std::vector<int>{0, 6})) << "points of one coordinate split";
  const std::vector<Vec3> row{Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  const Regions weightless = Regions::cut(row, std::vector<double>(4, 0.0), 2);
  EXPECT_EQ(counts(weightless, row, 2), (std::vector<int>{2, 2})) << "no weight: each point counts as one";
  std::vector<Vec3> with_nan = random_points(20, Vec3(1, 1, 1), 1);
  with_nan[4] = Vec3(std::numeric_limits<Real>::quiet_NaN(), 0, 0);
  const Regions regions = Regions::cut(with_nan, std::vector<double>(20, 1.0), 5);
  const auto count = counts(regions, with_nan, 5);
  EXPECT_EQ(count[0] + count[1] + count[2] + count[3] + count[4], 20);
}

// NodeStore dealt by region: each node is its region's rank's, and the ranks and the partition stay
// when the regions are cut anew (the nodes move into them at the formulation's next rebuild,
// keep); dealt in blocks again, the blocks (each node's rank from the blocks' first nodes).
TEST(Regions, NodesDealtByRegionKeepTheirRanksWhenCutAnew) {
  NodeStore nodes;
  nodes.resize(4);
  nodes.x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  nodes.deal(Regions::cut(nodes.x, std::vector<double>(4, 1.0), 2), 0);
  EXPECT_TRUE(nodes.by_region());
  EXPECT_EQ(nodes.owner, (std::vector<std::int32_t>{0, 0, 1, 1}));
  EXPECT_EQ(nodes.owned_count(), 2);
  EXPECT_EQ(nodes.owned_node(1), 1);
  EXPECT_TRUE(nodes.owns(1));
  EXPECT_FALSE(nodes.owns(2));
  nodes.deal(Regions::cut(nodes.x, std::vector<double>(4, 1.0), 1), 0);  // every node this rank's
  const long long before_recut = nodes.partition;
  nodes.recut(Regions::cut(nodes.x, std::vector<double>{1, 1, 1, 0}, 2));
  EXPECT_EQ(nodes.owner, (std::vector<std::int32_t>{0, 0, 0, 0}));
  EXPECT_EQ(nodes.partition, before_recut);
  EXPECT_EQ(nodes.regions.rank_of(nodes.x[1]), 1);
  nodes.deal(std::vector<Index>{0, 3, 4}, 1);  // blocks again
  EXPECT_FALSE(nodes.by_region());
  EXPECT_TRUE(nodes.owner.empty());  // in blocks the ranks' first nodes tell, O(P) not O(N)
  for (Index i = 0; i < 4; ++i) {
    EXPECT_EQ(nodes.rank_of(i), i < 3 ? 0 : 1);
    EXPECT_EQ(nodes.owns(i), i == 3);
  }
  EXPECT_EQ(nodes.owned_count(), 1);
  EXPECT_EQ(nodes.owned_node(0), 3);
}

}  // namespace
}  // namespace spall::discretization
