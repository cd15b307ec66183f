// SPG bonds (seed 001 §2.2): the failure rule of eq. 14 (IDAM 1) and its permanence: a broken bond
// stays broken through every rebuild of the bond rows, also when the two particles drift out of
// each other's support and come back.
#include <gtest/gtest.h>

#include "spall/spg/bonds.hpp"

using namespace spall;
using namespace spall::spg;

namespace {

// A row of particles 1 apart, all within range of each other (full neighbour list).
neighbors::NeighborList all_pairs(Index n) {
  neighbors::NeighborList list;
  list.offsets.push_back(0);
  for (Index i = 0; i < n; ++i) {
    for (Index j = 0; j < n; ++j)
      if (j != i) list.neighbors.push_back(j);
    list.offsets.push_back(static_cast<Index>(list.neighbors.size()));
  }
  return list;
}

Index find_bond(const BondList& b, Index i, Index j) {
  for (Index k = b.offsets[i]; k < b.offsets[i + 1]; ++k)
    if (b.neighbour[k] == j) return k;
  return -1;
}

const auto keep_all = [](Index, Index) { return true; };

}  // namespace

TEST(SpgBonds, RowsAreMirroredAndRestLengthsAreTheDistances) {
  const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(0, 3, 0)};
  const BondList b = make_bonds(all_pairs(4), x, keep_all, nullptr, {});
  ASSERT_EQ(b.size(), 4);
  for (Index i = 0; i < 4; ++i)
    for (Index k = b.offsets[i]; k < b.offsets[i + 1]; ++k) {
      const Index j = b.neighbour[k];
      EXPECT_EQ(b.neighbour[b.mirror[k]], i);
      EXPECT_GE(b.mirror[k], b.offsets[j]);
      EXPECT_LT(b.mirror[k], b.offsets[j + 1]);
      EXPECT_EQ(b.rest_length[k], (x[i] - x[j]).norm());
      EXPECT_EQ(b.find(i, j), k);
    }
  EXPECT_EQ(b.find(3, 3), -1);
  // `keep` filters pairs symmetrically.
  const BondList near = make_bonds(all_pairs(4), x, [&](Index i, Index j) { return (x[i] - x[j]).norm() < 1.5; },
                                   nullptr, {});
  EXPECT_EQ(near.count(0), 1);
  EXPECT_EQ(near.count(1), 2);
  EXPECT_EQ(near.count(3), 0);
}

// Breaks the bonds of every row that break now (bonds_breaking over every row, as one process
// does), recording them in `broken`: the number broken.
Index judge_bonds(BondList& b, std::span<const Real> quantity, std::span<const Vec3> x, Real critical_value,
                  Real critical_stretch, std::vector<BondPair>& broken) {
  const std::vector<BondPair> breaking =
      bonds_breaking(b, quantity, x, critical_value, critical_stretch, {0, b.size()});
  break_bonds(b, {}, breaking, broken);
  return static_cast<Index>(breaking.size());
}

// Seed 001 eq. 14: Phi_K(x_J) = 0 when (eps_K + eps_J) / 2 > eps_crit AND e_KJ > e_crit.
TEST(SpgBonds, FailureNeedsBothThePlasticStrainAndTheStretch) {
  const std::vector<Vec3> X = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  BondList b = make_bonds(all_pairs(4), X, keep_all, nullptr, {});
  // Stretch the gap between particles 1 and 2 by 30 % and the one between 2 and 3 by 10 %.
  const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2.3, 0, 0), Vec3(3.4, 0, 0)};
  // Averages: (0,1) 0.2; (1,2) 0.45; (2,3) 0.45; (0,2) 0.25; (1,3) 0.45; (0,3) 0.25.
  const std::vector<Real> eps = {0.0, 0.4, 0.5, 0.4};
  std::vector<BondPair> pairs;
  const Index broken = judge_bonds(b, eps, x, /*critical_strain=*/0.3, /*critical_stretch=*/1.2, pairs);
  // (1,2): strain 0.45 > 0.3 and stretch 1.3 > 1.2: breaks. (2,3): stretch (1.1) too small.
  // (1,3): stretch 2.4 / 2 = 1.2, not above. (0,2): strain 0.25 too small.
  EXPECT_EQ(broken, 1);
  EXPECT_EQ(b.broken[find_bond(b, 1, 2)], 1);
  EXPECT_EQ(b.broken[find_bond(b, 2, 1)], 1);
  EXPECT_EQ(b.broken[find_bond(b, 2, 3)], 0);
  EXPECT_EQ(b.broken[find_bond(b, 1, 3)], 0);
  EXPECT_EQ(b.broken[find_bond(b, 0, 2)], 0);
  EXPECT_EQ(b.broken_count(1), 1);
  EXPECT_EQ(b.broken_count(2), 1);
  // Already broken bonds are not counted again.
  EXPECT_EQ(judge_bonds(b, eps, x, 0.3, 1.2, pairs), 0);
  EXPECT_EQ(pairs, (std::vector<BondPair>{{1, 2}}));
}

TEST(SpgBonds, ABrokenBondNeverReforms) {
  std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0)};
  BondList b = make_bonds(all_pairs(3), x, keep_all, nullptr, {});
  std::vector<BondPair> broken;
  x[1] = Vec3(1.5, 0, 0);
  judge_bonds(b, std::vector<Real>{1, 1, 1}, x, 0.5, 1.2, broken);  // (0,1) stretched 1.5: breaks
  ASSERT_EQ(broken, (std::vector<BondPair>{{0, 1}}));
  // The particles move apart: the rebuilt rows no longer hold the pair (an Eulerian kernel
  // update drops it) ...
  const auto within = [&](Index i, Index j) { return (x[i] - x[j]).norm() < 1.2; };
  x = {Vec3(0, 0, 0), Vec3(5, 0, 0), Vec3(5.5, 0, 0)};
  BondList apart = make_bonds(all_pairs(3), x, within, &b, broken);
  EXPECT_EQ(find_bond(apart, 0, 1), -1);
  // ... and when they come back within range, the bond is back in the rows but still broken,
  // while the bond (1,2) that never broke is intact and keeps its first rest length.
  x = {Vec3(0, 0, 0), Vec3(0.9, 0, 0), Vec3(1.1, 0, 0)};
  const BondList back = make_bonds(all_pairs(3), x, within, &apart, broken);
  ASSERT_NE(find_bond(back, 0, 1), -1);
  EXPECT_EQ(back.broken[find_bond(back, 0, 1)], 1);
  EXPECT_EQ(back.broken[find_bond(back, 1, 0)], 1);
  EXPECT_EQ(back.broken[find_bond(back, 1, 2)], 0);
  EXPECT_EQ(back.rest_length[find_bond(back, 1, 2)], 1.0);  // from the configuration it formed in
  // A fresh bond that formed in the rebuild gets the current distance as rest length.
  ASSERT_NE(find_bond(back, 0, 2), -1);
  EXPECT_EQ(back.rest_length[find_bond(back, 0, 2)], 1.1);
}

// Under MPI a rank holds the rows of the particles it reads alone: breaking bonds marks those rows
// and records every pair, also those of rows it does not hold (every rank keeps every broken pair).
TEST(SpgBonds, BreakingMarksTheRowsHeldAndRecordsEveryPair) {
  const std::vector<Vec3> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(2, 0, 0), Vec3(3, 0, 0)};
  BondList b = make_bonds(all_pairs(4), x, keep_all, nullptr, {});
  b.hold(b.entries({1, 3}));  // rows 1 and 2
  EXPECT_EQ(b.neighbour.held_begin(), 3);
  EXPECT_EQ(b.neighbour.held_end(), 9);
  std::vector<BondPair> broken = {{0, 3}};
  const std::vector<std::uint8_t> held = {0, 1, 1, 0};
  break_bonds(b, held, std::vector<BondPair>{{0, 1}, {1, 2}, {2, 3}}, broken);
  EXPECT_EQ(broken, (std::vector<BondPair>{{0, 1}, {0, 3}, {1, 2}, {2, 3}}));
  EXPECT_EQ(b.broken_count(1), 2);  // (1,0) and (1,2)
  EXPECT_EQ(b.broken_count(2), 2);  // (2,1) and (2,3)
  EXPECT_EQ(b.broken[b.find(1, 3)], 0);
}
