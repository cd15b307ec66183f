// The four-lane type of the SPH pair loops (core/simd.hpp): the vector implementation must give,
// lane by lane, what the scalar lanes give (exactly: both round every operation once), and the
// kernels' gradient factor over four lanes must be the scalar one at each lane.
#include <gtest/gtest.h>

#include <array>
#include <random>

#include "spall/core/simd.hpp"
#include "spall/kernels/kernel.hpp"

using spall::Index;
using spall::Real;
namespace simd = spall::simd;
namespace kernels = spall::kernels;

namespace {

std::array<Real, 4> lanes_of(simd::Real4 v) {
  std::array<Real, 4> out;
  v.store(out.data());
  return out;
}

std::array<Real, 4> lanes_of(simd::lanes::Real4 v) {
  std::array<Real, 4> out;
  v.store(out.data());
  return out;
}

// Random numbers of both signs over several decades.
std::array<Real, 4> random_lanes(std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-8, 8);
  std::array<Real, 4> v;
  for (Real& x : v) x = std::ldexp(mantissa(rng), exponent(rng));
  return v;
}

}  // namespace

TEST(Simd, EveryOperationMatchesTheScalarLanesExactly) {
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const auto a = random_lanes(rng), b = random_lanes(rng), c = random_lanes(rng);
    const simd::Real4 va = simd::Real4::load(a.data()), vb = simd::Real4::load(b.data()),
                      vc = simd::Real4::load(c.data());
    const auto sa = simd::lanes::Real4::load(a.data()), sb = simd::lanes::Real4::load(b.data()),
               sc = simd::lanes::Real4::load(c.data());
    EXPECT_EQ(lanes_of(va + vb), lanes_of(sa + sb));
    EXPECT_EQ(lanes_of(va - vb), lanes_of(sa - sb));
    EXPECT_EQ(lanes_of(va * vb), lanes_of(sa * sb));
    EXPECT_EQ(lanes_of(va / vb), lanes_of(sa / sb));
    EXPECT_EQ(lanes_of(-va), lanes_of(-sa));
    EXPECT_EQ(lanes_of(fma(va, vb, vc)), lanes_of(fma(sa, sb, sc)));
    EXPECT_EQ(lanes_of(sqrt(abs(va))), lanes_of(sqrt(abs(sa))));
    EXPECT_EQ(lanes_of(max(va, vb)), lanes_of(max(sa, sb)));
    EXPECT_EQ((va < vb).lanes(), (sa < sb).lanes());
    EXPECT_EQ((va <= vb).lanes(), (sa <= sb).lanes());
    EXPECT_EQ((va > vb).lanes(), (sa > sb).lanes());
    EXPECT_EQ(lanes_of(select(va < vb, va, vc)), lanes_of(select(sa < sb, sa, sc)));
    EXPECT_EQ(va.sum(), (a[0] + a[1]) + (a[2] + a[3]));
    EXPECT_EQ(sa.sum(), va.sum());
  }
}

TEST(Simd, GatherCompressAndTransposedLoadsPickTheRightElements) {
  // A 9-wide table (the stride of a 3x3 matrix) whose element (row, column) is 100 row + column.
  std::vector<Real> table(9 * 12 + 4);
  for (int row = 0; row < 12; ++row)
    for (int column = 0; column < 9; ++column) table[9 * row + column] = 100 * row + column;
  const Index rows[4] = {7, 0, 11, 3};
  for (int column = 0; column < 9; ++column) {
    const auto g = lanes_of(simd::Real4::gather<9>(table.data(), rows, column));
    for (int i = 0; i < 4; ++i) EXPECT_EQ(g[i], 100 * rows[i] + column);
  }
  for (int offset : {0, 4}) {
    simd::Real4 block[4];
    simd::load_transposed<9>(table.data(), rows, offset, block);
    for (int j = 0; j < 4; ++j) {
      const auto g = lanes_of(block[j]);
      for (int i = 0; i < 4; ++i) EXPECT_EQ(g[i], 100 * rows[i] + offset + j);
    }
  }
  simd::Real4 x, y, z;
  simd::load_vectors(table.data(), rows, x, y, z);  // the table read as 3-vectors
  const auto xs = lanes_of(x), ys = lanes_of(y), zs = lanes_of(z);
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(xs[i], table[3 * rows[i]]);
    EXPECT_EQ(ys[i], table[3 * rows[i] + 1]);
    EXPECT_EQ(zs[i], table[3 * rows[i] + 2]);
  }
  const Real values[4] = {10, 11, 12, 13};
  const Index indices[4] = {20, 21, 22, 23};
  for (int mask = 0; mask < 16; ++mask) {
    Real packed[4] = {-1, -1, -1, -1};
    Index packed_index[4] = {-1, -1, -1, -1};
    simd::Real4::load(values).compress_store(packed, mask);
    simd::compress_store(indices, mask, packed_index);
    int k = 0;
    for (int lane = 0; lane < 4; ++lane) {
      if (!(mask & (1 << lane))) continue;
      EXPECT_EQ(packed[k], values[lane]) << "mask " << mask;
      EXPECT_EQ(packed_index[k], indices[lane]) << "mask " << mask;
      ++k;
    }
  }
}

template <typename K>
class KernelLanes : public ::testing::Test {};
using AllKernels3 = ::testing::Types<kernels::CubicSpline<2>, kernels::CubicSpline<3>, kernels::QuinticSpline<3>,
                                     kernels::WendlandC2<3>>;
TYPED_TEST_SUITE(KernelLanes, AllKernels3);

TYPED_TEST(KernelLanes, GradientFactorOfFourPairsIsTheScalarOneAtEachLane) {
  using K = TypeParam;
  const Real H = 0.37;
  // Near q = 1 the factor cancels to zero: errors are measured against its size mid-support.
  const Real scale = std::abs(K::gradient_factor(H / 2, 2 / H, 1 / H));
  for (int i = 1; i < 200; i += 4) {
    Real r[4];
    for (int lane = 0; lane < 4; ++lane) r[lane] = H * (i + lane) / 200.0;
    simd::Real4 vr = simd::Real4::load(r);
    const auto four = lanes_of(K::gradient_factor(vr, simd::Real4(1) / vr, simd::Real4(1 / H)));
    for (int lane = 0; lane < 4; ++lane) {
      const Real one = K::gradient_factor(r[lane], 1 / r[lane], 1 / H);
      // The scalar form may be contracted into fused multiply-adds by the compiler: a few ulps.
      EXPECT_NEAR(four[lane], one, 1e-13 * scale) << "q = " << r[lane] / H;
    }
  }
}
