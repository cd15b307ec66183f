// The Verlet list's rebuild test (VerletList::needs_rebuild, neighbors/relative_motion.cpp): it
// must never keep a list that misses a pair now within reach_i + reach_j (checked against a
// brute-force search), and it must keep the list of a body that deforms as a whole while
// neighbouring particles move together, where a test on the global spread of the displacements
// rebuilds. The suite is `neighbors`, so that `ctest -R neighbor` selects it.
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "spall/neighbors/verlet_list.hpp"

namespace spall::neighbors {
namespace {

// A bar of nx x ny x nz particles of spacing 1 from the origin, x fastest.
std::vector<Vec3> lattice_bar(int nx, int ny, int nz) {
  std::vector<Vec3> x;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) x.emplace_back(i, j, k);
  return x;
}

// Pairs (i, j) now closer than reach_i + reach_j, by brute force, that the list lacks in i's or
// in j's row.
long long missing_pairs(const VerletList& verlet, const std::vector<Vec3>& x, const std::vector<Real>& reach) {
  const NeighborList& list = verlet.list();
  auto lists = [&](std::size_t i, std::size_t j) {
    return std::binary_search(list.neighbors.begin() + list.offsets[i],
                              list.neighbors.begin() + list.offsets[i + 1], Index(j));
  };
  long long missing = 0;
  for (std::size_t i = 0; i < x.size(); ++i)
    for (std::size_t j = i + 1; j < x.size(); ++j) {
      const Real r = reach[i] + reach[j];
      if ((x[i] - x[j]).squaredNorm() < r * r) missing += !lists(i, j) + !lists(j, i);
    }
  return missing;
}

// Largest distance between the displacements of two particles, d = x - before: how far apart
// the body's parts have moved.
Real displacement_spread(const std::vector<Vec3>& x, const std::vector<Vec3>& before) {
  Vec3 lower = x[0] - before[0], upper = lower;
  for (std::size_t i = 0; i < x.size(); ++i) {
    lower = lower.cwiseMin(x[i] - before[i]);
    upper = upper.cwiseMax(x[i] - before[i]);
  }
  return (upper - lower).norm();
}

// The solver's set-up: reach 1.05 h with h = 1.2 spacings, skin 10 % of twice the largest reach
// (src/spall/sph/solid.cpp).
constexpr Real reach_of_bar = 1.05 * 1.2;
constexpr Real skin_of_bar = 0.1 * 2 * reach_of_bar;

// A lattice bar of 200 x 4 x 4 spacings with the solver's list, moved as `move` says: its
// displacements must spread over more than `spread_in_skins` skins, the list must be kept, and
// brute force must find no pair missing from it.
template <typename Move>
void expect_list_kept(Move&& move, Real spread_in_skins) {
  const std::vector<Vec3> x = lattice_bar(200, 4, 4);
  const std::vector<Real> reach(x.size(), reach_of_bar);
  VerletList verlet;
  verlet.build(x, reach, skin_of_bar);
  std::vector<Vec3> moved = x;
  for (Vec3& p : moved) p = move(p);
  ASSERT_GT(displacement_spread(moved, x), spread_in_skins * skin_of_bar);
  EXPECT_FALSE(verlet.needs_rebuild(moved));
  EXPECT_EQ(missing_pairs(verlet, moved, reach), 0);
}

TEST(neighbors, StretchedBarKeepsItsList) {
  // A 4 % uniform stretch of a bar 200 spacings long moves its ends 8 spacings apart (31 skins),
  // but changes the distance of a pair at the cutoff 2.52 by 0.10, 0.4 skin: the list stays
  // complete, and the test must see that.
  expect_list_kept([](const Vec3& p) { return Vec3(1.04 * p.x(), p.y(), p.z()); }, 30);
}

TEST(neighbors, RotatedBarKeepsItsList) {
  // A rigid rotation by 0.02 rad about an oblique axis through the bar's middle, plus a
  // translation: the ends move 3.9 spacings apart (15 skins) while every distance is kept.
  const Mat3 rotation = Eigen::AngleAxis<Real>(0.02, Vec3(0.3, 0.4, 1).normalized()).toRotationMatrix();
  const Vec3 middle(99.5, 1.5, 1.5);
  expect_list_kept([&](const Vec3& p) { return Vec3(middle + rotation * (p - middle) + Vec3(3, -2, 1)); }, 14);
}

TEST(neighbors, CloseParticlesMovingApartByMoreThanTheSkinAskForARebuild) {
  // On top of a 2 % stretch (which alone keeps the list), two neighbouring particles in the
  // middle of the bar move toward each other. Their relative displacement is their own move plus
  // the stretch over one spacing (0.02). By 0.9 skin in all: the list holds; by 1.2 skins: they
  // are still within the cutoff, so the test must ask.
  const std::vector<Vec3> x = lattice_bar(200, 4, 4);
  const std::vector<Real> reach(x.size(), reach_of_bar);
  VerletList verlet;
  verlet.build(x, reach, skin_of_bar);
  std::vector<Vec3> moved = x;
  for (Vec3& p : moved) p.x() *= 1.02;
  ASSERT_FALSE(verlet.needs_rebuild(moved));
  const Index left = 100, right = 101;  // (100, 0, 0) and (101, 0, 0)
  std::vector<Vec3> closer = moved;
  closer[left].x() += 0.45 * skin_of_bar - 0.01;
  closer[right].x() -= 0.45 * skin_of_bar - 0.01;
  EXPECT_FALSE(verlet.needs_rebuild(closer));
  EXPECT_EQ(missing_pairs(verlet, closer, reach), 0);
  closer = moved;
  closer[left].x() += 0.6 * skin_of_bar;
  closer[right].x() -= 0.6 * skin_of_bar;
  EXPECT_TRUE(verlet.needs_rebuild(closer));
  // Sideways instead: the same relative move across the bar.
  closer = moved;
  closer[left].y() += 0.6 * skin_of_bar;
  closer[right].y() -= 0.6 * skin_of_bar;
  EXPECT_TRUE(verlet.needs_rebuild(closer));
  // A pair not listed at the build (3 spacings apart: beyond 2.52 + 0.25) pulled within reach.
  std::vector<Vec3> pulled = moved;
  pulled[100].x() += 0.3;
  pulled[103].x() -= 0.3;
  EXPECT_TRUE(verlet.needs_rebuild(pulled));
}

// A random smooth displacement field: a random affine part plus three random waves.
struct SmoothField {
  Mat3 gradient;
  Vec3 shift;
  std::array<Vec3, 3> wave_vector, amplitude;

  SmoothField(std::mt19937_64& random, Real strain, Real wave_amplitude) {
    std::normal_distribution<Real> normal;
    for (int r = 0; r < 3; ++r)
      for (int c = 0; c < 3; ++c) gradient(r, c) = strain * normal(random);
    shift = 5 * Vec3(normal(random), normal(random), normal(random));
    for (int w = 0; w < 3; ++w) {
      // Wavelengths of 4 to 20 spacings: smooth on the scale of a few neighbours.
      const Real wavelength = std::uniform_real_distribution<Real>(4, 20)(random);
      wave_vector[w] = 2 * M_PI / wavelength * Vec3(normal(random), normal(random), normal(random)).normalized();
      amplitude[w] = wave_amplitude * Vec3(normal(random), normal(random), normal(random));
    }
  }
  Vec3 operator()(const Vec3& p) const {
    Vec3 d = gradient * p + shift;
    for (int w = 0; w < 3; ++w) d += std::sin(wave_vector[w].dot(p)) * amplitude[w];
    return d;
  }
};

TEST(neighbors, RandomSmoothMotionsNeverLoseAPair) {
  // 1 500 particles at random in a 48 x 4 x 4 box, per-particle reach 0.6 to 1.5 spacings, skin
  // 0.3. Each trial moves them by a random smooth field of random size: whenever the test keeps
  // the list, the brute-force search must find no pair missing, and one and two threads must give
  // the same answer. The sizes are drawn so that both answers occur often.
  std::mt19937_64 random(21);
  std::uniform_real_distribution<Real> unit(0, 1);
  std::vector<Vec3> x(1500);
  std::vector<Real> reach(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) {
    x[i] = Vec3(48 * unit(random), 4 * unit(random), 4 * unit(random));
    reach[i] = 0.6 + 0.9 * unit(random);
  }
  const Real skin = 0.3;
  VerletList verlet;
  verlet.build(x, reach, skin);
  const int threads_before = omp_get_max_threads();
  int kept = 0, rebuilt = 0, kept_while_spread = 0;
  for (int trial = 0; trial < 100; ++trial) {
    const Real strain = 0.015 * unit(random), wave_amplitude = 0.06 * unit(random);
    const SmoothField field(random, strain, wave_amplitude);
    std::vector<Vec3> moved = x;
    for (Vec3& p : moved) p += field(p);
    omp_set_num_threads(1);
    const bool one = verlet.needs_rebuild(moved);
    omp_set_num_threads(2);
    const bool two = verlet.needs_rebuild(moved);
    EXPECT_EQ(one, two) << "trial " << trial;
    if (one) {
      ++rebuilt;
      continue;
    }
    ++kept;
    if (displacement_spread(moved, x) > 2 * skin) ++kept_while_spread;
    EXPECT_EQ(missing_pairs(verlet, moved, reach), 0) << "trial " << trial;
  }
  omp_set_num_threads(threads_before);
  EXPECT_GE(kept, 10);
  EXPECT_GE(rebuilt, 10);
  // Kept lists whose displacements spread over more than 2 skins, which the global test alone
  // (every displacement within skin / 2 of one vector: a spread of at most sqrt(3) skins) would
  // have rebuilt: the local test did the work.
  EXPECT_GE(kept_while_spread, 5);
}

TEST(neighbors, FarFlungClustersKeepTheGuarantee) {
  // Two clusters 10^9 apart moving rigidly in opposite directions by many skins: a dense grid over
  // their box would need 10^27 cells. The test must answer without building it, and an answer of
  // "keep" must still leave no pair missing.
  std::vector<Vec3> x = lattice_bar(6, 6, 6);
  const std::size_t half = x.size();
  for (std::size_t i = 0; i < half; ++i) x.push_back(x[i] + Vec3(1e9, 1e9, 1e9));
  const std::vector<Real> reach(x.size(), reach_of_bar);
  VerletList verlet;
  verlet.build(x, reach, skin_of_bar);
  std::vector<Vec3> moved = x;
  for (std::size_t i = 0; i < x.size(); ++i) moved[i] += (i < half ? 1 : -1) * Vec3(2, 0, 0);
  if (!verlet.needs_rebuild(moved)) {
    EXPECT_EQ(missing_pairs(verlet, moved, reach), 0);
  }
  moved[3] += Vec3(0, 0.6, 0);  // now apart from its neighbours by more than the skin
  EXPECT_TRUE(verlet.needs_rebuild(moved));
}

}  // namespace
}  // namespace spall::neighbors
