// The per-particle array that holds one range of particles (core/range_array.hpp): a
// particle keeps its value while the range still holds it, whatever the range becomes; the ranks'
// exchanges tell an array switched off (empty) from one that holds no particle.
#include <gtest/gtest.h>

#include "spall/core/range_array.hpp"

namespace spall {
namespace {

RangeArray<double> numbered(Index n) {
  RangeArray<double> a;
  a.resize(n);
  for (Index p = 0; p < n; ++p) a[p] = 10.0 * p;
  return a;
}

TEST(RangeArray, AParticleKeepsItsValueWhileHeld) {
  RangeArray<double> a = numbered(100);
  a.hold(40, 60);  // a rank's own block
  for (Index p = 40; p < 60; ++p) EXPECT_EQ(a[p], 10.0 * p);
  a.hold(30, 50);  // dealt anew: 40..49 stay, 30..39 arrive
  for (Index p = 40; p < 50; ++p) EXPECT_EQ(a[p], 10.0 * p);
  for (Index p = 30; p < 40; ++p) EXPECT_EQ(a[p], 0.0);
  a.hold(55, 70);  // no overlap
  for (Index p = 55; p < 70; ++p) EXPECT_EQ(a[p], 0.0);
  EXPECT_EQ(a.held_begin(), 55);
  EXPECT_EQ(a.held_end(), 70);
  EXPECT_EQ(a.capacity_bytes(), 15 * sizeof(double));
}

TEST(RangeArray, ParticlesNewlyHeldStartAsGiven) {
  RangeArray<double> a = numbered(100);
  a.hold(40, 60);
  a.hold(30, 50, -1.0);  // dealt anew: 40..49 stay, 30..39 start at the set-up's value
  for (Index p = 30; p < 40; ++p) EXPECT_EQ(a[p], -1.0);
  for (Index p = 40; p < 50; ++p) EXPECT_EQ(a[p], 10.0 * p);
  RangeArray<double> off;
  off.hold(0, 10, 5.0);  // an array switched off stays off
  EXPECT_TRUE(off.empty());
}

TEST(RangeArray, NoParticlesIsNotOff) {
  RangeArray<double> a = numbered(8);
  a.hold(8, 8);  // a rank without particles
  EXPECT_FALSE(a.empty());
  a.hold(3, 1);  // an empty range, however given
  EXPECT_FALSE(a.empty());
  a.clear();
  EXPECT_TRUE(a.empty());
  a.hold(0, 8);  // an array switched off stays off
  EXPECT_TRUE(a.empty());
  EXPECT_EQ(a.capacity_bytes(), 0u);
}

TEST(RangeArray, AssignHoldsEveryParticle) {
  RangeArray<int> a;
  EXPECT_TRUE(a.empty());
  a.assign(5, 7);
  a.hold(2, 5);
  a.assign(4, 3);  // the set-up's state again: from particle 0
  for (Index p = 0; p < 4; ++p) EXPECT_EQ(a[p], 3);
}

}  // namespace
}  // namespace spall
