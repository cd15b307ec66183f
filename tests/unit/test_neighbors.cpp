// Neighbour search against brute force, against exact lattice counts, on degenerate sets, and for
// independence from the thread count. The suite is `neighbors`, lower case, so that
// `ctest -R neighbor` selects it.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <numeric>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

#include "spall/core/error.hpp"
#include "spall/neighbors/cell_list.hpp"
#include "spall/neighbors/verlet_list.hpp"

namespace spall::neighbors {
namespace {

// Every pair closer than radius, by the same arithmetic as the search, in O(N^2).
NeighborList brute_force(const std::vector<Vec3>& x, Real radius) {
  const auto n = static_cast<Index>(x.size());
  NeighborList list;
  list.offsets.push_back(0);
  for (Index i = 0; i < n; ++i) {
    for (Index j = 0; j < n; ++j) {
      const Real dx = x[i].x() - x[j].x();
      const Real dy = x[i].y() - x[j].y();
      const Real dz = x[i].z() - x[j].z();
      if (i != j && dx * dx + dy * dy + dz * dz < radius * radius) list.neighbors.push_back(j);
    }
    list.offsets.push_back(static_cast<Index>(list.neighbors.size()));
  }
  return list;
}

std::vector<Index> row(const NeighborList& list, Index i) {
  return {list.neighbors.begin() + list.offsets[i], list.neighbors.begin() + list.offsets[i + 1]};
}

// Rows strictly ascending, no self, and j in i's row exactly when i is in j's row.
void expect_sorted_and_symmetric(const NeighborList& list, Index n) {
  ASSERT_EQ(list.offsets.size(), static_cast<std::size_t>(n) + 1);
  EXPECT_EQ(list.offsets.front(), 0);
  EXPECT_EQ(static_cast<std::size_t>(list.offsets.back()), list.neighbors.size());
  for (Index i = 0; i < n; ++i) {
    const std::vector<Index> r = row(list, i);
    EXPECT_TRUE(std::adjacent_find(r.begin(), r.end(), std::greater_equal<>()) == r.end())
        << "row " << i << " is not strictly ascending";
    for (const Index j : r) {
      ASSERT_GE(j, 0);
      ASSERT_LT(j, n);
      EXPECT_NE(j, i);
      const std::vector<Index> back = row(list, j);
      EXPECT_TRUE(std::binary_search(back.begin(), back.end(), i)) << i << " lists " << j;
    }
  }
}

void expect_matches_brute_force(const std::vector<Vec3>& x, Real cutoff, Real skin) {
  VerletList verlet;
  verlet.build(x, cutoff, skin);
  const NeighborList expected = brute_force(x, cutoff + skin);
  expect_sorted_and_symmetric(verlet.list(), static_cast<Index>(x.size()));
  EXPECT_EQ(verlet.list().offsets, expected.offsets);
  EXPECT_EQ(verlet.list().neighbors, expected.neighbors);
}

std::vector<Vec3> random_set(std::size_t n, const Vec3& lower, const Vec3& upper,
                             unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<Real> unit(0, 1);
  std::vector<Vec3> x(n);
  for (Vec3& p : x) {
    for (int d = 0; d < 3; ++d) p[d] = lower[d] + unit(random) * (upper[d] - lower[d]);
  }
  return x;
}

// n reaches drawn uniformly from [lower, upper).
std::vector<Real> random_reach(std::size_t n, Real lower, Real upper, unsigned seed) {
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<Real> uniform(lower, upper);
  std::vector<Real> reach(n);
  for (Real& r : reach) r = uniform(random);
  return reach;
}

// side^3 points of spacing dx from origin, x fastest.
std::vector<Vec3> cubic_lattice(int side, Real dx, const Vec3& origin = Vec3::Zero()) {
  std::vector<Vec3> x;
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) x.push_back(origin + dx * Vec3(i, j, k));
  return x;
}

TEST(neighbors, RandomSetsMatchBruteForce) {
  const Vec3 lower(-1, 0, 2);
  expect_matches_brute_force(random_set(2000, lower, Vec3(3, 4, 6), 1), 0.3, 0.05);
  expect_matches_brute_force(random_set(1500, lower, Vec3(9, 1, 3), 2), 0.2, 0.0);
  // A radius larger than the box: one cell per axis.
  expect_matches_brute_force(random_set(300, lower, Vec3(0, 1, 3), 3), 2.0, 0.5);
  // Sparse: most particles have no neighbour.
  expect_matches_brute_force(random_set(400, lower, Vec3(99, 100, 102), 4), 1.0, 0.1);
}

TEST(neighbors, CubicLatticeInteriorCountsAreExact) {
  // Shells of a cubic lattice of spacing 1: 6 at 1, 12 at sqrt 2, 8 at sqrt 3, 6 at 2. A radius
  // between shells gives 6, 6+12 = 18, 18+8 = 26 neighbours to every particle at least 2 spacings
  // from the faces.
  const int side = 9;
  const std::vector<Vec3> x = cubic_lattice(side, 1.0);
  const struct {
    Real cutoff, skin;
    Index expected;
  } cases[] = {{1.1, 0.1, 6}, {1.5, 0.1, 18}, {1.8, 0.1, 26}, {1.9, 0.0, 26}};
  for (const auto& c : cases) {
    VerletList verlet;
    verlet.build(x, c.cutoff, c.skin);
    const NeighborList& list = verlet.list();
    expect_sorted_and_symmetric(list, static_cast<Index>(x.size()));
    for (int k = 2; k < side - 2; ++k)
      for (int j = 2; j < side - 2; ++j)
        for (int i = 2; i < side - 2; ++i) {
          EXPECT_EQ(list.count((k * side + j) * side + i), c.expected)
              << "radius " << c.cutoff + c.skin << " at " << i << "," << j << "," << k;
        }
    // A corner sees the 1/8 of its shells inside the lattice: 3, 3+3 = 6, 6+1 = 7.
    EXPECT_EQ(list.count(0), c.expected == 6 ? 3 : c.expected == 18 ? 6 : 7);
    EXPECT_EQ(list.neighbors, brute_force(x, c.cutoff + c.skin).neighbors);
  }
}

TEST(neighbors, LatticeOnCellFacesMatchesBruteForce) {
  // The search bins into cells of half the radius: at radius 2 and 3 on a unit lattice the
  // particles lie on cell faces, the radius is a multiple of the cell edge, and whole shells lie
  // exactly on the radius (outside it: the test is strict).
  const std::vector<Vec3> x = cubic_lattice(8, 1.0);
  expect_matches_brute_force(x, 2.0, 0.0);
  expect_matches_brute_force(x, 1.5, 0.5);
  expect_matches_brute_force(x, 3.0, 0.0);
}

TEST(neighbors, AllParticlesInOneCell) {
  const std::vector<Vec3> x = random_set(60, Vec3(5, 5, 5), Vec3(5.1, 5.2, 5.05), 5);
  VerletList verlet;
  verlet.build(x, 1.0, 0.1);
  for (Index i = 0; i < 60; ++i) EXPECT_EQ(verlet.list().count(i), 59);
  expect_matches_brute_force(x, 1.0, 0.1);
}

TEST(neighbors, ParticlesInAPlaneAndOnALine) {
  std::vector<Vec3> plane = random_set(1000, Vec3(0, 0, 3), Vec3(5, 5, 3), 6);
  expect_matches_brute_force(plane, 0.25, 0.05);
  std::vector<Vec3> line = random_set(500, Vec3(0, -2, 1), Vec3(0, 20, 1), 7);
  expect_matches_brute_force(line, 0.1, 0.02);
}

TEST(neighbors, SingleParticleAndNoParticles) {
  VerletList verlet;
  verlet.build(std::vector<Vec3>{Vec3(1, 2, 3)}, 1.0, 0.1);
  EXPECT_EQ(verlet.list().offsets, (std::vector<Index>{0, 0}));
  EXPECT_TRUE(verlet.list().neighbors.empty());

  verlet.build(std::vector<Vec3>{}, 1.0, 0.1);
  EXPECT_EQ(verlet.list().offsets, (std::vector<Index>{0}));
  EXPECT_TRUE(verlet.list().neighbors.empty());
  EXPECT_FALSE(verlet.needs_rebuild(std::vector<Vec3>{}));
  EXPECT_TRUE(spatial_order(std::vector<Vec3>{}, 1.0).empty());
}

TEST(neighbors, FarFromTheOrigin) {
  // Lattice coordinates 1e6 + i are exact, so the list must equal the one at the origin.
  const std::vector<Vec3> near = cubic_lattice(6, 1.0);
  const std::vector<Vec3> far = cubic_lattice(6, 1.0, Vec3(1e6, -1e6, 1e6));
  VerletList at_origin, offset;
  at_origin.build(near, 1.6, 0.1);
  offset.build(far, 1.6, 0.1);
  EXPECT_EQ(offset.list().offsets, at_origin.list().offsets);
  EXPECT_EQ(offset.list().neighbors, at_origin.list().neighbors);
  expect_matches_brute_force(random_set(500, Vec3(1e6, 1e6, 1e6), Vec3(1e6 + 3, 1e6 + 3, 1e6 + 3), 8),
                             0.3, 0.05);
}

TEST(neighbors, HugeBoxWithFewParticles) {
  // Two small clusters 1e9 cutoffs apart: a dense grid over the box would need 1e27 cells.
  std::vector<Vec3> x = random_set(200, Vec3(0, 0, 0), Vec3(2, 2, 2), 9);
  const std::vector<Vec3> far = random_set(200, Vec3(1e9, 1e9, 1e9), Vec3(1e9 + 2, 1e9 + 2, 1e9 + 2), 10);
  x.insert(x.end(), far.begin(), far.end());
  expect_matches_brute_force(x, 0.4, 0.1);

  // A box so wide that even the 63-bit cell key overflows: the cells grow and stay correct.
  const std::vector<Vec3> extreme = {Vec3(0, 0, 0), Vec3(0.5, 0, 0), Vec3(-1e300, 1e300, -1e300),
                                     Vec3(1e300, -1e300, 1e300)};
  expect_matches_brute_force(extreme, 1.0, 0.0);
}

TEST(neighbors, SameListForOneAndTwoThreads) {
  const std::vector<Vec3> x = random_set(6000, Vec3(0, 0, 0), Vec3(4, 3, 2), 11);
  const int threads_before = omp_get_max_threads();
  omp_set_num_threads(1);
  VerletList one;
  one.build(x, 0.2, 0.03);
  const std::vector<Index> order_one = spatial_order(x, 0.23);
  omp_set_num_threads(2);
  VerletList two;
  two.build(x, 0.2, 0.03);
  const std::vector<Index> order_two = spatial_order(x, 0.23);
  omp_set_num_threads(threads_before);
  EXPECT_EQ(one.list().offsets, two.list().offsets);
  EXPECT_EQ(one.list().neighbors, two.list().neighbors);
  EXPECT_EQ(order_one, order_two);
}

// A rank's own rows (VerletList::build with rows): those rows as brute force finds them, every other
// row empty; a range that holds no particle gives an empty list.
TEST(neighbors, RowsOfARangeOnlyMatchBruteForce) {
  const std::vector<Vec3> x = random_set(3000, Vec3(0, 0, 0), Vec3(2, 1.5, 1), 12);
  const Real cutoff = 0.15, skin = 0.02;
  const NeighborList expected = brute_force(x, cutoff + skin);
  const auto n = static_cast<Index>(x.size());
  for (const ParticleRange rows : {ParticleRange{0, 1000}, ParticleRange{1000, 2200}, ParticleRange{2200, n},
                                   ParticleRange{n, n}}) {
    VerletList verlet;
    verlet.build(x, cutoff, skin, rows);
    for (Index i = 0; i < n; ++i) {
      const bool asked = i >= rows.begin && i < rows.end;
      EXPECT_EQ(row(verlet.list(), i), asked ? row(expected, i) : std::vector<Index>{}) << "row " << i;
    }
  }
}

TEST(neighbors, RebuildOnlyAfterAMoveBeyondTheSkin) {
  const Real cutoff = 0.3, skin = 0.06;
  std::vector<Vec3> x = random_set(1500, Vec3(0, 0, 0), Vec3(2, 2, 2), 12);
  VerletList verlet;
  EXPECT_TRUE(verlet.needs_rebuild(x)) << "never built";
  verlet.build(x, cutoff, skin);
  EXPECT_FALSE(verlet.needs_rebuild(x));

  // Every particle moves just under skin / 2 in a random direction: no rebuild, and the old list
  // still holds every pair now closer than the cutoff.
  std::mt19937_64 random(13);
  std::normal_distribution<Real> normal;
  for (Vec3& p : x) p += 0.49 * skin * Vec3(normal(random), normal(random), normal(random)).normalized();
  EXPECT_FALSE(verlet.needs_rebuild(x));
  const NeighborList now = brute_force(x, cutoff);
  for (Index i = 0; i < static_cast<Index>(x.size()); ++i) {
    const std::vector<Index> listed = row(verlet.list(), i);
    for (const Index j : row(now, i)) {
      EXPECT_TRUE(std::binary_search(listed.begin(), listed.end(), j)) << i << " lost " << j;
    }
  }

  // One particle alone moving: its distances to the others change by its own move, so the list
  // holds until it has moved the whole skin.
  std::vector<Vec3> one_moved = x;
  verlet.build(x, cutoff, skin);
  one_moved[700] += Vec3(0, 0.99 * skin, 0);
  EXPECT_FALSE(verlet.needs_rebuild(one_moved));
  one_moved[700] += Vec3(0, 0.02 * skin, 0);
  EXPECT_TRUE(verlet.needs_rebuild(one_moved));
  one_moved[700] = Vec3(std::numeric_limits<Real>::quiet_NaN(), 0, 0);
  EXPECT_TRUE(verlet.needs_rebuild(one_moved));
  EXPECT_THROW(verlet.build(one_moved, cutoff, skin), InstabilityError);
  one_moved.pop_back();
  verlet.build(x, cutoff, skin);
  EXPECT_TRUE(verlet.needs_rebuild(one_moved)) << "particle count changed";
}

TEST(neighbors, PerParticleReachMatchesBruteForce) {
  // Reaches from 0.05 to 0.25: pair (i, j) is listed exactly when closer than r_i + r_j + skin.
  const std::vector<Vec3> x = random_set(2500, Vec3(0, 0, 0), Vec3(3, 2, 2), 14);
  std::vector<Real> reach = random_reach(x.size(), 0.05, 0.25, 15);
  const Real skin = 0.02;
  VerletList verlet;
  verlet.build(x, reach, skin);
  expect_sorted_and_symmetric(verlet.list(), static_cast<Index>(x.size()));
  NeighborList expected;
  expected.offsets.push_back(0);
  for (std::size_t i = 0; i < x.size(); ++i) {
    for (std::size_t j = 0; j < x.size(); ++j) {
      const Real radius = reach[i] + reach[j] + skin;
      if (i != j && (x[i] - x[j]).squaredNorm() < radius * radius) expected.neighbors.push_back(Index(j));
    }
    expected.offsets.push_back(static_cast<Index>(expected.neighbors.size()));
  }
  EXPECT_EQ(verlet.list().offsets, expected.offsets);
  EXPECT_EQ(verlet.list().neighbors, expected.neighbors);
  EXPECT_EQ(verlet.cutoff(), 2 * *std::max_element(reach.begin(), reach.end()));
  // In the search's order, on particles in random order: the same rows up to order.
  VerletList unsorted;
  unsorted.build(x, reach, skin, RowOrder::search);
  ASSERT_EQ(unsorted.list().offsets, expected.offsets);
  bool some_row_unsorted = false;
  for (std::size_t i = 0; i < x.size(); ++i) {
    std::vector<Index> r = row(unsorted.list(), Index(i));
    some_row_unsorted |= !std::is_sorted(r.begin(), r.end());
    std::sort(r.begin(), r.end());
    EXPECT_EQ(r, row(verlet.list(), Index(i))) << "row " << i;
  }
  EXPECT_TRUE(some_row_unsorted) << "random order should leave rows unsorted";
  reach[3] = 0;
  EXPECT_THROW(verlet.build(x, reach, skin), std::invalid_argument);
}

// Under MPI the SPH solid searches the rows it computes (per-particle reach, search order): each
// such row must be the whole build's row, entry for entry (the order sets the bits of the sums);
// search_every_row then makes the whole build's list, and is not counted as a build; search_rows
// narrows a whole build to the range's rows, as a build of them alone would have.
TEST(neighbors, PerReachRowsOfARangeAreTheWholeBuildsRows) {
  const std::vector<Vec3> x = random_set(2500, Vec3(0, 0, 0), Vec3(1.5, 1, 1), 21);
  const std::vector<Real> reach = random_reach(x.size(), 0.04, 0.08, 22);
  const Real skin = 0.01;
  const auto n = static_cast<Index>(x.size());
  VerletList whole;
  whole.build(x, reach, skin, RowOrder::search);
  EXPECT_FALSE(whole.partial());
  for (const ParticleRange rows : {ParticleRange{0, 900}, ParticleRange{900, 1700}, ParticleRange{1700, n},
                                   ParticleRange{n, n}}) {
    VerletList part;
    part.build(x, reach, skin, RowOrder::search, rows);
    EXPECT_EQ(part.partial(), rows.begin > 0 || rows.end < n);
    EXPECT_TRUE(part.searched(rows));
    EXPECT_FALSE(part.searched({rows.begin > 0 ? rows.begin - 1 : rows.end, rows.end + 1}));
    for (Index i = 0; i < n; ++i) {
      const bool asked = i >= rows.begin && i < rows.end;
      EXPECT_EQ(row(part.list(), i), asked ? row(whole.list(), i) : std::vector<Index>{}) << "row " << i;
    }
    VerletList narrowed = whole;
    narrowed.search_rows(reach, rows);
    EXPECT_EQ(narrowed.list().offsets, part.list().offsets);
    EXPECT_EQ(narrowed.list().neighbors, part.list().neighbors);
    EXPECT_EQ(narrowed.builds(), 1);
    part.search_every_row(reach);
    EXPECT_FALSE(part.partial());
    EXPECT_EQ(part.list().offsets, whole.list().offsets);
    EXPECT_EQ(part.list().neighbors, whole.list().neighbors);
    EXPECT_EQ(part.builds(), 1);
  }
}

// Under MPI a rank of the SPH solid bins only the particles within reach of the rows it searches,
// in the grid of every particle's box, the others' positions and reaches unknown to it (here:
// NaN): each row searched is still the whole build's, entry for entry. Kept for the rows alone
// (hold_positions), complete_positions then brings in the others' positions and search_every_row
// makes the whole build's list. A subset that lacks
// a row's particle, is not ascending, or holds a reach above the largest given is refused.
TEST(neighbors, BinnedSubsetGivesTheWholeBuildsRows) {
  // Stored along x, as a bar's nodes are numbered along it: a range of rows is a slab.
  std::vector<Vec3> x = random_set(2500, Vec3(0, 0, 0), Vec3(1.5, 1, 1), 31);
  std::sort(x.begin(), x.end(), [](const Vec3& a, const Vec3& b) { return a.x() < b.x(); });
  const std::vector<Real> reach = random_reach(x.size(), 0.04, 0.08, 32);
  const Real skin = 0.01, largest = *std::max_element(reach.begin(), reach.end());
  const Real radius = 2 * largest + skin;
  const auto n = static_cast<Index>(x.size());
  VerletList whole;
  whole.build(x, reach, skin, RowOrder::search);
  BoundingBox grid;
  for (const Vec3& p : x) grid.include(p);
  const ParticleRange rows{1000, 1400};
  BoundingBox rows_box;
  for (Index i = rows.begin; i < rows.end; ++i) rows_box.include(x[i]);
  const BoundingBox near = rows_box.grown(radius);
  std::vector<Index> binned;
  std::vector<Vec3> known(n, Vec3::Constant(std::numeric_limits<Real>::quiet_NaN()));
  std::vector<Real> known_reach(n, std::numeric_limits<Real>::quiet_NaN());
  for (Index i = 0; i < n; ++i)
    if (near.contains(x[i])) binned.push_back(i), known[i] = x[i], known_reach[i] = reach[i];
  ASSERT_LT(binned.size(), x.size() * 2 / 3);  // a subset worth the name
  const BinnedSubset subset{.particles = binned, .grid = grid, .largest_reach = largest};
  VerletList part;
  part.build(known, known_reach, skin, RowOrder::search, rows, &subset);
  EXPECT_DOUBLE_EQ(part.cutoff(), whole.cutoff());
  Index listed = 0;
  for (Index i = 0; i < n; ++i) {
    const bool asked = i >= rows.begin && i < rows.end;
    EXPECT_EQ(row(part.list(), i), asked ? row(whole.list(), i) : std::vector<Index>{}) << "row " << i;
    if (asked) listed += whole.list().count(i);
  }
  EXPECT_GT(listed, 10 * (rows.end - rows.begin));
  // The rows' particles' own box (not grown by the radius) misses neighbours: the rows differ.
  std::vector<Index> too_few;
  for (const Index i : binned)
    if (rows_box.contains(x[i])) too_few.push_back(i);
  const BinnedSubset short_subset{.particles = too_few, .grid = grid, .largest_reach = largest};
  VerletList short_part;
  short_part.build(known, known_reach, skin, RowOrder::search, rows, &short_subset);
  EXPECT_NE(short_part.list().neighbors.size(), part.list().neighbors.size());

  EXPECT_THROW(part.search_every_row(reach), std::logic_error);
  // A rank keeps its own rows' positions at the build alone (hold_positions); complete_positions
  // brings in the others' around them (here: every position but the rows').
  part.hold_positions(rows);
  EXPECT_EQ(part.positions_at_build().held_begin(), rows.begin);
  EXPECT_EQ(part.positions_at_build().held_end(), rows.end);
  EXPECT_EQ(part.positions_at_build().size(), n);
  part.complete_positions([&](RangeArray<Vec3>& positions) {
    for (Index i = 0; i < n; ++i)
      if (i < rows.begin || i >= rows.end) positions[i] = x[i];
  });
  part.search_every_row(reach);
  EXPECT_EQ(part.list().offsets, whole.list().offsets);
  EXPECT_EQ(part.list().neighbors, whole.list().neighbors);

  // Dealt anew: other rows searched from the positions at the build of the particles near them
  // alone (held and set by hand here, as they come in from their ranks), in the build's grid.
  VerletList dealt;
  dealt.build(known, known_reach, skin, RowOrder::search, rows, &subset);
  const ParticleRange next{1300, 1700};
  BoundingBox next_box;
  for (Index i = next.begin; i < next.end; ++i) next_box.include(x[i]);
  std::vector<Index> next_binned;
  std::vector<Real> next_reach(n, std::numeric_limits<Real>::quiet_NaN());
  for (Index i = 0; i < n; ++i)
    if (next_box.grown(radius).contains(x[i])) next_binned.push_back(i), next_reach[i] = reach[i];
  dealt.hold_positions({next_binned.front(), next_binned.back() + 1});
  for (const Index i : next_binned) dealt.set_position_at_build(i, x[i]);
  dealt.search_binned_rows(next_reach, next, next_binned);
  for (Index i = 0; i < n; ++i) {
    const bool asked = i >= next.begin && i < next.end;
    EXPECT_EQ(row(dealt.list(), i), asked ? row(whole.list(), i) : std::vector<Index>{}) << "dealt row " << i;
  }
  EXPECT_EQ(dealt.builds(), 1);

  std::vector<Index> lacking(binned);
  lacking.erase(std::find(lacking.begin(), lacking.end(), rows.begin + 7));
  const BinnedSubset without_a_row{.particles = lacking, .grid = grid, .largest_reach = largest};
  EXPECT_THROW(part.build(known, known_reach, skin, RowOrder::search, rows, &without_a_row), std::invalid_argument);
  std::vector<Index> unsorted(binned);
  std::swap(unsorted[0], unsorted[1]);
  const BinnedSubset not_ascending{.particles = unsorted, .grid = grid, .largest_reach = largest};
  EXPECT_THROW(part.build(known, known_reach, skin, RowOrder::search, rows, &not_ascending), std::invalid_argument);
  const BinnedSubset small_reach{.particles = binned, .grid = grid, .largest_reach = largest / 2};
  EXPECT_THROW(part.build(known, known_reach, skin, RowOrder::search, rows, &small_reach), std::invalid_argument);
}

TEST(neighbors, RigidTranslationNeedsNoRebuild) {
  // The rebuild test measures displacements from the centre of their bounding box: a common
  // motion of any size keeps every distance, so the list stays valid.
  const Real cutoff = 0.3, skin = 0.06;
  std::vector<Vec3> x = random_set(1500, Vec3(0, 0, 0), Vec3(2, 2, 2), 16);
  VerletList verlet;
  verlet.build(x, cutoff, skin);
  std::vector<Vec3> moved = x;
  for (Vec3& p : moved) p += Vec3(5.0, -3.0, 0.7);
  EXPECT_FALSE(verlet.needs_rebuild(moved));
  // On top of it, particle 10 and its nearest neighbour moving apart by just under the skin in
  // all: still valid (every displacement within skin / 2 of the common one); by just over it, while
  // still within the cutoff of each other: rebuild.
  const std::vector<Index> listed = row(verlet.list(), 10);
  const Index other = *std::min_element(listed.begin(), listed.end(), [&](Index a, Index b) {
    return (x[a] - x[10]).norm() < (x[b] - x[10]).norm();
  });
  ASSERT_LT((x[other] - x[10]).norm() + 1.02 * skin, cutoff);
  moved[10] += Vec3(0.49 * skin, 0, 0);
  moved[other] -= Vec3(0.49 * skin, 0, 0);
  EXPECT_FALSE(verlet.needs_rebuild(moved));
  moved[other] -= Vec3(0.03 * skin, 0, 0);
  EXPECT_TRUE(verlet.needs_rebuild(moved));
}

TEST(neighbors, SpatialOrderIsAStableSortByRowMajorCell) {
  // A lattice given in reverse, cells of 2 spacings: the order must be a permutation, cells
  // ascending row-major (z slowest), and particles within a cell in input order.
  std::vector<Vec3> x = cubic_lattice(7, 1.0);
  std::reverse(x.begin(), x.end());
  const Real cell_size = 2.0;
  const std::vector<Index> order = spatial_order(x, cell_size);
  std::vector<Index> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<Index> identity(x.size());
  std::iota(identity.begin(), identity.end(), 0);
  ASSERT_EQ(sorted, identity);

  auto cell_key = [&](Index i) {
    const Vec3 c = (x[i] / cell_size).array().floor();  // the box starts at the origin
    return (c.z() * 4 + c.y()) * 4 + c.x();              // 7 spacings -> 4 cells an axis
  };
  for (std::size_t k = 1; k < order.size(); ++k) {
    const Real before = cell_key(order[k - 1]), here = cell_key(order[k]);
    EXPECT_LE(before, here);
    if (before == here) {
      EXPECT_LT(order[k - 1], order[k]);
    }
  }
}

// A subset binned in the grid of the whole set's box (under MPI: a rank's particles and those near
// them) has the whole build's cells, each holding the subset's particles in the whole build's
// order (in-cell order by tie); and the whole build made again from its particles' keys
// (build_from_keys, what every rank's keys give) is the same list.
TEST(neighbors, SubsetInTheWholeGridHasTheWholeBuildsCells) {
  std::mt19937 random(21);
  std::uniform_real_distribution<double> u(0, 1);
  const Index n = 600;
  std::vector<Vec3> x(n);
  for (auto& p : x) p = Vec3(2 * u(random), u(random), 0.5 * u(random));
  std::vector<Id> id(n);
  std::iota(id.begin(), id.end(), Id{1});
  std::shuffle(id.begin(), id.end(), random);
  CellList whole;
  whole.build(x, 0.11, id);
  std::vector<CellKey> key(n);
  for (Index c = 0; c < whole.cell_count(); ++c)
    for (Index k = whole.cell(c).begin; k < whole.cell(c).end; ++k) key[whole.order()[k]] = whole.cell_key(c);

  std::vector<Index> subset;
  for (Index i = 0; i < n; ++i)
    if (x[i].x() > 0.7) subset.push_back(i);
  std::vector<Vec3> xs;
  std::vector<Id> ids;
  for (const Index i : subset) xs.push_back(x[i]), ids.push_back(id[i]);
  BoundingBox box;
  for (const auto& p : x) box.include(p);
  CellList part;
  part.build(xs, 0.11, ids, &box);
  EXPECT_EQ(part.lower(), whole.lower());
  EXPECT_EQ(part.cell_size(), whole.cell_size());
  EXPECT_EQ(part.cells_along(), whole.cells_along());
  Index cells_with_subset = 0;
  for (Index c = 0; c < whole.cell_count(); ++c) {
    std::vector<Index> expected;
    for (Index k = whole.cell(c).begin; k < whole.cell(c).end; ++k)
      if (x[whole.order()[k]].x() > 0.7) expected.push_back(whole.order()[k]);
    if (expected.empty()) continue;
    ++cells_with_subset;
    const Index pc = part.first_cell_near(whole.cell_key(c));
    ASSERT_LT(pc, part.cell_count());
    ASSERT_TRUE(part.cell_key(pc) == whole.cell_key(c));
    std::vector<Index> got;
    for (Index k = part.cell(pc).begin; k < part.cell(pc).end; ++k) got.push_back(subset[part.order()[k]]);
    EXPECT_EQ(got, expected) << "cell " << c;
  }
  EXPECT_EQ(cells_with_subset, part.cell_count());

  CellList again;
  again.build_from_keys(key, id, whole.lower(), whole.cell_size(), whole.cells_along());
  EXPECT_TRUE(std::equal(again.order().begin(), again.order().end(), whole.order().begin(), whole.order().end()));
  ASSERT_EQ(again.cell_count(), whole.cell_count());
  for (Index c = 0; c <= whole.cell_count(); ++c) {
    EXPECT_TRUE(again.cell_key(c) == whole.cell_key(c));
    EXPECT_EQ(again.cell_start(c), whole.cell_start(c));
  }
}

TEST(neighbors, RejectsBadArguments) {
  const std::vector<Vec3> x = cubic_lattice(2, 1.0);
  VerletList verlet;
  EXPECT_THROW(verlet.build(x, 0.0, 0.1), std::invalid_argument);
  EXPECT_THROW(verlet.build(x, 1.0, -0.1), std::invalid_argument);
  EXPECT_THROW(spatial_order(x, 0.0), std::invalid_argument);
}

// The resident memory of this process, its peak since the last reset_peak_memory(), in bytes
// (/proc/self/status: VmRSS, VmHWM).
std::size_t status_bytes(const std::string& key) {
  std::ifstream in("/proc/self/status");
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stoull(line.substr(key.size() + 1)) * 1024;
  return 0;
}
bool reset_peak_memory() { return static_cast<bool>(std::ofstream("/proc/self/clear_refs") << "5"); }

// A rebuild frees the old list before it searches, and the copy of the rows it found into the new
// list gives each buffer back once it is copied: the build never holds the list twice (it held the
// old list and the rows found, then the rows found and the new list: 2x the list, 94 + 99 MB of the
// Taylor bar's 408 MB at D0/50). 64^3 lattice particles within 2.7 spacings: 76 neighbours, 80 MB
// of list; the rebuild's scratch (cell-ordered positions, reaches, cells) adds a quarter of the list
// to the resident set, and a build that kept the old list while it searched added 1.17 of it.
TEST(neighbors, ARebuildNeverHoldsTheListTwice) {
  const int side = 64;
  std::vector<Vec3> x;
  x.reserve(static_cast<std::size_t>(side) * side * side);
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) x.emplace_back(i, j, k);
  const std::vector<Real> reach(x.size(), 1.3);
  VerletList verlet;
  verlet.build(x, reach, 0.1, RowOrder::search);
  const double list_bytes = static_cast<double>(verlet.list().neighbors.size() * sizeof(Index));
  ASSERT_GT(list_bytes, 80e6);
  if (!reset_peak_memory()) GTEST_SKIP() << "no /proc/self/clear_refs to reset the peak resident set";
  const double before = static_cast<double>(status_bytes("VmRSS"));
  verlet.build(x, reach, 0.1, RowOrder::search);
  const double peak = static_cast<double>(status_bytes("VmHWM"));
  EXPECT_LT(peak - before, 0.5 * list_bytes) << "resident before " << before << ", peak " << peak << ", list " << list_bytes;
}

}  // namespace
}  // namespace spall::neighbors
