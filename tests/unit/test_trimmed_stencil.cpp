// The trimmed stencil against brute force: its ranges must hold every particle within the radius
// (random clouds, lattices whose particles lie on cell faces, radii that are exact multiples of
// the cell edge, particles moved since they were binned), stay inside the block, and trim a
// lattice cell's block to the count derived by hand.
#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <vector>

#include "spall/neighbors/cell_list.hpp"
#include "spall/neighbors/trimmed_stencil.hpp"

namespace spall::neighbors {
namespace {

std::vector<Vec3> random_cloud(std::size_t n, const Vec3& upper, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<Real> unit(0, 1);
  std::vector<Vec3> x(n);
  for (Vec3& p : x) p = Vec3(unit(random), unit(random), unit(random)).cwiseProduct(upper);
  return x;
}

// side^3 points of spacing 1 from the origin.
std::vector<Vec3> unit_lattice(int side) {
  std::vector<Vec3> x;
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) x.push_back(Vec3(i, j, k));
  return x;
}

// Bins `binned` into cells of edge (radius + 2 moved) / reach (the radius asked plus the point's
// own move); then for every particle, at its position in `now` (within `moved` of where it was
// binned), the trimmed ranges for radius + moved must hold every particle closer than radius in
// `now`, ascending, inside the block.
void expect_superset(const std::vector<Vec3>& binned, const std::vector<Vec3>& now, Real radius,
                     Real moved, int reach) {
  CellList cells;
  cells.build(binned, (radius + 2 * moved) / reach);
  const auto order = cells.order();
  std::vector<Index> position_of(order.size());
  for (std::size_t k = 0; k < order.size(); ++k) position_of[order[k]] = static_cast<Index>(k);
  TrimmedStencil stencil(cells, reach);
  TrimmedStencil::Ranges ranges, block;
  Index checked = 0;
  for (Index c = 0; c < cells.cell_count(); ++c) {
    stencil.prepare(c);
    const int block_count = stencil.block(block);
    for (Index k = cells.cell(c).begin; k < cells.cell(c).end; ++k) {
      const Index a = order[k];
      const int count = stencil.trimmed(now[a] - cells.lower(), radius + moved, ranges);
      EXPECT_EQ(count, block_count);
      std::vector<bool> listed(order.size(), false);
      for (int r = 0; r < count; ++r) {
        // A row's run lies inside the row's block range, after the previous row's.
        EXPECT_LE(block[r].begin, ranges[r].begin);
        EXPECT_LE(ranges[r].begin, ranges[r].end);
        EXPECT_LE(ranges[r].end, block[r].end);
        if (r > 0) {
          EXPECT_LE(block[r - 1].end, block[r].begin);
        }
        for (Index j = ranges[r].begin; j < ranges[r].end; ++j) listed[j] = true;
      }
      for (std::size_t b = 0; b < now.size(); ++b) {
        if ((now[b] - now[a]).squaredNorm() < radius * radius) {
          EXPECT_TRUE(listed[position_of[b]]) << "particle " << a << " misses " << b << " (reach " << reach << ")";
        }
      }
      ++checked;
    }
  }
  EXPECT_EQ(checked, static_cast<Index>(binned.size()));
}

TEST(trimmed_stencil, RandomCloudHoldsEveryNeighbour) {
  const std::vector<Vec3> x = random_cloud(1500, Vec3(3, 2, 1.5), 1);
  for (int reach = 1; reach <= TrimmedStencil::max_reach; ++reach) expect_superset(x, x, 0.3, 0, reach);
  // A radius wider than the box: one cell per axis at reach 1.
  expect_superset(random_cloud(200, Vec3(1, 1, 1), 2), random_cloud(200, Vec3(1, 1, 1), 2), 2.5, 0, 2);
}

TEST(trimmed_stencil, LatticeOnCellFacesWithRadiusAMultipleOfTheEdge) {
  // Spacing 1, radius 2: cell edges 2, 1 and 2/3; at reach 1 and 2 every particle lies on a cell
  // face and the radius is exactly one or two edges, and the shell at distance 2 is exactly on
  // the radius (outside it: the test is strict).
  const std::vector<Vec3> x = unit_lattice(8);
  for (int reach = 1; reach <= TrimmedStencil::max_reach; ++reach) expect_superset(x, x, 2.0, 0, reach);
  // Radius 3 at reach 2: edge 1.5, so every other lattice plane is a cell face.
  expect_superset(x, x, 3.0, 0, 2);
}

TEST(trimmed_stencil, ParticlesMovedSinceBinningAreFoundWithTheRadiusWidened) {
  const Real radius = 0.3, moved = 0.02;
  const std::vector<Vec3> binned = random_cloud(1500, Vec3(3, 2, 1.5), 3);
  std::vector<Vec3> now = binned;
  std::mt19937_64 random(4);
  std::normal_distribution<Real> normal;
  for (Vec3& p : now) p += moved * Vec3(normal(random), normal(random), normal(random)).normalized();
  for (int reach = 1; reach <= TrimmedStencil::max_reach; ++reach) expect_superset(binned, now, radius, moved, reach);
}

TEST(trimmed_stencil, TrimsALatticeCornerToTheCellsItsBallMeets) {
  // Cells of edge 1 on a unit lattice (one particle on the lower corner of each cell), radius 2
  // = two edges, reach 2. For a particle p the distances from p to the slabs of cells along an
  // axis are 1, 0, 0, 1, 2 in cell units (cells -2 .. 2 from p's). A row of cells at slab
  // distances (gy, gz) reaches when gy^2 + gz^2 <= 4, over the cells i whose slab distance
  // gx satisfies gx^2 <= 4 - gy^2 - gz^2:
  //   gy^2 + gz^2 = 0: 4 rows of 5 cells;  = 1: 8 rows of 4;  = 2: 4 rows of 4;
  //   = 4 (the point of such a row's cells nearest p lies on the sphere): 4 rows of 2 cells;
  // 20 + 32 + 16 + 8 = 76 candidates of the 125 in the block, for 26 neighbours strictly inside
  // (6 at 1, 12 at sqrt 2, 8 at sqrt 3).
  const int side = 9;
  const std::vector<Vec3> x = unit_lattice(side);
  CellList cells;
  cells.build(x, 1.0);
  TrimmedStencil stencil(cells, 2);
  TrimmedStencil::Ranges ranges, block;
  const Index centre = (4 * side + 4) * side + 4;  // (4, 4, 4): its block is whole
  for (Index c = 0; c < cells.cell_count(); ++c) {
    const ParticleRange own = cells.cell(c);
    if (cells.order()[own.begin] != centre) continue;
    stencil.prepare(c);
    Index in_block = 0, candidates = 0, neighbours = 0;
    const int block_count = stencil.block(block);
    for (int r = 0; r < block_count; ++r) in_block += block[r].end - block[r].begin;
    const int count = stencil.trimmed(x[centre] - cells.lower(), 2.0, ranges);
    for (int r = 0; r < count; ++r)
      for (Index k = ranges[r].begin; k < ranges[r].end; ++k) {
        ++candidates;
        const Index b = cells.order()[k];
        neighbours += b != centre && (x[b] - x[centre]).squaredNorm() < 4.0;
      }
    EXPECT_EQ(in_block, 125);
    EXPECT_EQ(candidates, 76);
    EXPECT_EQ(neighbours, 26);
    return;
  }
  FAIL() << "no cell holds the centre particle";
}

TEST(trimmed_stencil, ABoxsRunsHoldTheRunsOfEachOfItsPoints) {
  // The SPH fluid screens a cell's particles together, over the runs of their bounding box: in
  // each row, the box's run must hold the run of every particle of the box, and so every particle
  // within the radius of any of them.
  const Real radius = 0.3;
  const std::vector<Vec3> x = random_cloud(1500, Vec3(3, 2, 1.5), 5);
  for (int reach = 1; reach <= TrimmedStencil::max_reach; ++reach) {
    CellList cells;
    cells.build(x, radius / reach);
    TrimmedStencil stencil(cells, reach);
    TrimmedStencil::Ranges box, point, block;
    Index box_candidates = 0, block_candidates = 0;
    for (Index c = 0; c < cells.cell_count(); ++c) {
      stencil.prepare(c);
      const ParticleRange own = cells.cell(c);
      Vec3 lower = x[cells.order()[own.begin]] - cells.lower(), upper = lower;
      for (Index k = own.begin; k < own.end; ++k) {
        lower = lower.cwiseMin(x[cells.order()[k]] - cells.lower());
        upper = upper.cwiseMax(x[cells.order()[k]] - cells.lower());
      }
      const int count = stencil.trimmed(lower, upper, radius, box);
      stencil.block(block);
      for (int r = 0; r < count; ++r) {
        box_candidates += box[r].end - box[r].begin;
        block_candidates += block[r].end - block[r].begin;
      }
      for (Index k = own.begin; k < own.end; ++k) {
        ASSERT_EQ(stencil.trimmed(x[cells.order()[k]] - cells.lower(), radius, point), count);
        for (int r = 0; r < count; ++r) {
          if (point[r].begin == point[r].end) continue;
          EXPECT_LE(box[r].begin, point[r].begin) << "reach " << reach << ", cell " << c << ", row " << r;
          EXPECT_GE(box[r].end, point[r].end) << "reach " << reach << ", cell " << c << ", row " << r;
        }
      }
    }
    // The box still trims: fewer candidates than the cells' whole blocks.
    EXPECT_LT(box_candidates, block_candidates) << "reach " << reach;
  }
}

TEST(trimmed_stencil, SlidingAlongARowGivesTheSameTableAsPreparingAfresh) {
  // prepare() shifts the table when the next cell follows along its row of cells: each cell's
  // trimmed ranges must equal those of a stencil prepared for that cell alone.
  const std::vector<Vec3> x = random_cloud(3000, Vec3(4, 1, 1), 5);
  CellList cells;
  cells.build(x, 0.15);
  TrimmedStencil sliding(cells, 2);
  TrimmedStencil::Ranges slid, fresh_ranges;
  for (Index c = 0; c < cells.cell_count(); ++c) {
    sliding.prepare(c);
    TrimmedStencil fresh(cells, 2);
    fresh.prepare(c);
    for (Index k = cells.cell(c).begin; k < cells.cell(c).end; ++k) {
      const Vec3 offset = x[cells.order()[k]] - cells.lower();
      const int count = sliding.trimmed(offset, 0.3, slid);
      ASSERT_EQ(count, fresh.trimmed(offset, 0.3, fresh_ranges));
      for (int r = 0; r < count; ++r) {
        EXPECT_EQ(slid[r].begin, fresh_ranges[r].begin) << "cell " << c << " row " << r;
        EXPECT_EQ(slid[r].end, fresh_ranges[r].end) << "cell " << c << " row " << r;
      }
    }
  }
}

// The search that starts the stencil's rows: from any hint, the first occupied cell at or after a
// key, as a bisection of the whole list finds it (keys between, on and past the occupied ones).
TEST(trimmed_stencil, CellSearchFromAnyHintFindsTheFirstCellAtOrAfterAKey) {
  CellList cells;
  cells.build(random_cloud(300, Vec3(10, 6, 4), 7), 0.7);  // sparse: many empty cells
  const Index count = cells.cell_count();
  ASSERT_GT(count, 100);
  std::vector<CellKey> keys;
  for (Index c = 0; c < count; ++c) keys.push_back(cells.cell_key(c));
  std::vector<CellKey> asked = {CellKey(0), keys.back() + 1};
  for (CellKey k : keys) asked.insert(asked.end(), {k, k + 1, k > 0 ? k - 1 : k});
  for (CellKey k : asked) {
    const Index expected = static_cast<Index>(std::lower_bound(keys.begin(), keys.end(), k) - keys.begin());
    for (Index hint = 0; hint <= count; hint += 7) EXPECT_EQ(cells.first_cell_near(k, hint), expected);
    EXPECT_EQ(cells.first_cell_near(k, count), expected);
  }
}

TEST(trimmed_stencil, RejectsAReachOutsideOneToThree) {
  CellList cells;
  cells.build(unit_lattice(2), 1.0);
  EXPECT_THROW(TrimmedStencil(cells, 0), std::invalid_argument);
  EXPECT_THROW(TrimmedStencil(cells, 4), std::invalid_argument);
}

}  // namespace
}  // namespace spall::neighbors
