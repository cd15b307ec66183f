// The packs of the neighbour search and of the solid's pair loops (core/simd.hpp): every vector
// implementation the build has must give, lane by lane, what the scalar lanes give (exactly: both
// round every operation once), and the kernels' gradient factor over eight floats must be the
// scalar one at each lane to single-precision round-off.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <span>
#include <vector>

#include "spall/core/simd.hpp"
#include "spall/kernels/kernel.hpp"

using spall::Index;
using spall::Real;
namespace simd = spall::simd;
namespace kernels = spall::kernels;

namespace {

template <typename P>
std::array<Real, P::width> lanes_of(P v) {
  std::array<Real, P::width> out;
  v.store(out.data());
  return out;
}

// Random numbers of both signs over several decades.
template <int W>
std::array<Real, W> random_lanes(std::mt19937_64& rng) {
  std::uniform_real_distribution<Real> mantissa(-1, 1);
  std::uniform_int_distribution<int> exponent(-8, 8);
  std::array<Real, W> v;
  for (Real& x : v) x = std::ldexp(mantissa(rng), exponent(rng));
  return v;
}

template <int W>
std::array<float, W> random_float_lanes(std::mt19937_64& rng) {
  const auto d = random_lanes<W>(rng);
  std::array<float, W> v;
  for (int i = 0; i < W; ++i) v[i] = static_cast<float>(d[i]);
  return v;
}

template <typename P>
std::array<float, P::width> floats_of(P v) {
  std::array<float, P::width> out;
  v.store(out.data());
  return out;
}

// The exactly rounded operations of a float pack P against the scalar lanes S of its width, on
// the lanes a, b, c.
template <typename P, typename S, std::size_t W>
void expect_exact_float_arithmetic(const std::array<float, W>& a, const std::array<float, W>& b,
                                   const std::array<float, W>& c) {
  const P va = P::load(a.data()), vb = P::load(b.data()), vc = P::load(c.data());
  const S sa = S::load(a.data()), sb = S::load(b.data()), sc = S::load(c.data());
  EXPECT_EQ(floats_of(va + vb), floats_of(sa + sb));
  EXPECT_EQ(floats_of(va - vb), floats_of(sa - sb));
  EXPECT_EQ(floats_of(va * vb), floats_of(sa * sb));
  EXPECT_EQ(floats_of(fma(va, vb, vc)), floats_of(fma(sa, sb, sc)));
  EXPECT_EQ(floats_of(select(va < vb, va, vc)), floats_of(select(sa < sb, sa, sc)));
  EXPECT_EQ((va <= vb).lanes(), (sa <= sb).lanes());
}

// The sum of the lanes of a and b, each widened to double. Out of line and out of
// interprocedural analysis: GCC 12 at -O3 -march=x86-64-v4 inlined, added the doubles that the
// floats had been rounded from (the disassembly of the test, session 21), and the exact sum then
// differed from every correct one by the floats' rounding.
[[gnu::noipa]] Real widened_sum(const std::array<float, 8>& a, const std::array<float, 8>& b) {
  Real sum = 0;
  for (int i = 0; i < 8; ++i) sum += Real(a[i]) + Real(b[i]);
  return sum;
}

}  // namespace

// Every vector implementation the build has, each against the scalar lanes of its width.
template <typename P>
class VectorLanes : public ::testing::Test {};
using VectorImplementations = ::testing::Types<simd::lanes::Pack<4>
#if defined(SPALL_SIMD_AVX2)
                                               , simd::avx2::Real4
#endif
#if defined(SPALL_SIMD_AVX512)
                                               , simd::avx512::Real8
#endif
                                               >;
TYPED_TEST_SUITE(VectorLanes, VectorImplementations);

// The double packs carry the neighbour search's distance test (neighbors/verlet_list.cpp) and the
// one-point hexahedra (fem/solid_elements.cpp): arithmetic, the fused multiply-add, the comparison,
// abs, max, min, sqrt and the left-pack of indices.
TYPED_TEST(VectorLanes, EveryOperationMatchesTheScalarLanesExactly) {
  using P = TypeParam;
  constexpr int W = P::width;
  using S = simd::lanes::Pack<W>;
  std::mt19937_64 rng(7);
  for (int trial = 0; trial < 200; ++trial) {
    const auto a = random_lanes<W>(rng), b = random_lanes<W>(rng), c = random_lanes<W>(rng);
    const P va = P::load(a.data()), vb = P::load(b.data()), vc = P::load(c.data());
    const S sa = S::load(a.data()), sb = S::load(b.data()), sc = S::load(c.data());
    EXPECT_EQ(lanes_of(va + vb), lanes_of(sa + sb));
    EXPECT_EQ(lanes_of(va - vb), lanes_of(sa - sb));
    EXPECT_EQ(lanes_of(va * vb), lanes_of(sa * sb));
    EXPECT_EQ(lanes_of(va / vb), lanes_of(sa / sb));
    EXPECT_EQ(lanes_of(abs(va)), lanes_of(abs(sa)));
    EXPECT_EQ(lanes_of(fma(va, vb, vc)), lanes_of(fma(sa, sb, sc)));
    EXPECT_EQ((va < vb).lanes(), (sa < sb).lanes());
    EXPECT_EQ(lanes_of(P(a[0])), lanes_of(S(a[0])));
    // The neighbour stencil's row reach (neighbors/trimmed_stencil.hpp).
    EXPECT_EQ(lanes_of(max(va, vb)), lanes_of(max(sa, sb)));
    EXPECT_EQ(lanes_of(min(va, vb)), lanes_of(min(sa, sb)));
    EXPECT_EQ(lanes_of(sqrt(max(va, P(0)))), lanes_of(sqrt(max(sa, S(0)))));
    EXPECT_EQ(lanes_of(floor(va * P(100))), lanes_of(floor(sa * S(100))));
    EXPECT_EQ(lanes_of(select(va < vb, va, vc)), lanes_of(select(sa < sb, sa, sc)));
  }
  // A NaN lane: max and min take their second operand, as the x86 instructions do.
  std::array<Real, W> nan;
  nan.fill(std::nan(""));
  EXPECT_EQ(lanes_of(min(max(P::load(nan.data()), P(0)), P(3))), lanes_of(S(0)));
  EXPECT_EQ(lanes_of(min(max(S::load(nan.data()), S(0)), S(3))), lanes_of(S(0)));
  const Real table[7] = {0.5, 1.5, 2.5, 3.5, 4.5, 5.5, 6.5};
  Index rows[W];
  for (int i = 0; i < W; ++i) rows[i] = (3 * i + 1) % 7;
  EXPECT_EQ(lanes_of(P::template gather<1>(table, rows)), lanes_of(S::template gather<1>(table, rows)));
  for (int i = 0; i < W; ++i) EXPECT_EQ(lanes_of(P::template gather<1>(table, rows))[i], table[rows[i]]);
}

TYPED_TEST(VectorLanes, CompressOfIndicesKeepsTheSelectedLanesInOrder) {
  using P = TypeParam;
  constexpr int W = P::width;
  Index indices[W];
  for (int i = 0; i < W; ++i) indices[i] = 20 + i;
  for (int mask = 0; mask < (1 << W); ++mask) {
    Index packed_index[W];
    for (int i = 0; i < W; ++i) packed_index[i] = -1;
    P::compress_indices(indices, mask, packed_index);
    int k = 0;
    for (int lane = 0; lane < W; ++lane) {
      if (!(mask & (1 << lane))) continue;
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

// The solid's pair loops take the factor over eight floats (simd::Float8): the scalar double one
// at each lane to single-precision round-off (amplified by the quintic's cancellation near r = 0).
TYPED_TEST(KernelLanes, GradientFactorOfEightFloatPairsIsTheScalarOneToFloatRoundOff) {
  using K = TypeParam;
  using P = simd::Float8;
  const Real H = 0.37;
  const Real scale = std::abs(K::gradient_factor(H / 2, 2 / H, 1 / H));
  for (int i = 1; i + 8 <= 200; i += 8) {
    float r[8];
    for (int lane = 0; lane < 8; ++lane) r[lane] = static_cast<float>(H * (i + lane) / 200.0);
    const P vr = P::load(r);
    std::array<float, 8> pack;
    K::gradient_factor(vr, P(1) / vr, P(static_cast<float>(1 / H))).store(pack.data());
    for (int lane = 0; lane < 8; ++lane) {
      const Real one = K::gradient_factor(Real(r[lane]), 1 / Real(r[lane]), 1 / H);
      // Below q = 1/4 the quintic's factor is a difference of terms growing as 1/r, and float
      // keeps fewer of its digits there; a lattice's nearest neighbour sits at q of about 0.4.
      const Real tolerance = (r[lane] / H < 0.25 ? 5e-4 : 1e-5) * scale;
      EXPECT_NEAR(pack[lane], one, tolerance) << "q = " << r[lane] / H;
    }
  }
}

// The single-precision pack of the solid's pair loops (simd::Float8: AVX2 where the build has it,
// else the scalar lanes) against the scalar lanes of floats: every operation exactly (the
// reciprocals to a few ulp), the lane sums in the same order, the double accumulator of widened
// lanes, and the transposed row loads, compressions and index comparisons on eight lanes.
TEST(FloatLanes, EveryOperationMatchesTheScalarLanesExactly) {
  using P = simd::Float8;
  using S = simd::lanes::Pack<8, float>;
  std::mt19937_64 rng(13);
  for (int trial = 0; trial < 200; ++trial) {
    const auto a = random_float_lanes<8>(rng), b = random_float_lanes<8>(rng), c = random_float_lanes<8>(rng);
    expect_exact_float_arithmetic<P, S>(a, b, c);
    const P va = P::load(a.data()), vb = P::load(b.data());
    const S sa = S::load(a.data()), sb = S::load(b.data());
    // The reciprocals: estimates refined by a Newton step in the vector pack, within 4 ulp of
    // the division and square root.
    const auto within_4_ulp = [](std::array<float, 8> estimate, std::array<float, 8> exact) {
      for (int i = 0; i < 8; ++i) EXPECT_NEAR(estimate[i], exact[i], 4 * 0x1p-23f * std::abs(exact[i]));
    };
    within_4_ulp(floats_of(reciprocal(abs(va))), floats_of(reciprocal(abs(sa))));
    within_4_ulp(floats_of(reciprocal_sqrt(abs(va))), floats_of(reciprocal_sqrt(abs(sa))));
    EXPECT_EQ(va.sum(), sa.sum());
    simd::WideSum8 wide;
    simd::lanes::WideSum<8> wide_lanes;
    wide.add(va), wide.add(vb), wide_lanes.add(sa), wide_lanes.add(sb);
    EXPECT_EQ(wide.sum(), wide_lanes.sum());
    // In double: summed in float the 16 terms (up to 2^8) would be off by up to about 1e-4.
    EXPECT_NEAR(wide.sum(), widened_sum(a, b), 1e-12);
  }
  P packs[8];
  for (int i = 0; i < 8; ++i) {
    std::array<float, 8> v;
    for (int j = 0; j < 8; ++j) v[j] = static_cast<float>(std::ldexp(1.0 + 0.1 * j, i - j));
    packs[i] = P::load(v.data());
  }
  Real sums[8];
  simd::sum_lanes(packs, sums);
  for (int i = 0; i < 8; ++i) EXPECT_EQ(sums[i], packs[i].sum()) << "pack " << i;
}

TEST(FloatLanes, TransposedLoadsGathersCompressionAndComparisonsPickTheRightElements) {
  using P = simd::Float8;
  // A 12-wide table (the stride of the stress records) whose element (row, column) is 100 row + column.
  std::vector<float> table(12 * 12);
  for (int row = 0; row < 12; ++row)
    for (int column = 0; column < 12; ++column) table[12 * row + column] = float(100 * row + column);
  const Index rows[8] = {7, 0, 11, 3, 5, 10, 1, 8};
  P eight[8], four[4], two[2];
  simd::load_rows<12>(table.data(), rows, 0, eight);
  simd::load_rows<12>(table.data(), rows, 8, four);
  simd::load_rows<12>(table.data(), rows, 10, two);  // as the viscosity's (c, rho) rows
  // The gather of the solid's non-uniform masses (stride 1) and a strided one.
  const auto column_one = floats_of(P::gather<12>(table.data(), rows, 1));
  const auto by_index = floats_of(P::gather<1>(table.data(), rows));
  for (int i = 0; i < 8; ++i) {
    for (int j = 0; j < 8; ++j) EXPECT_EQ(floats_of(eight[j])[i], 100 * rows[i] + j);
    for (int j = 0; j < 4; ++j) EXPECT_EQ(floats_of(four[j])[i], 100 * rows[i] + 8 + j);
    for (int j = 0; j < 2; ++j) EXPECT_EQ(floats_of(two[j])[i], 100 * rows[i] + 10 + j);
    EXPECT_EQ(column_one[i], 100 * rows[i] + 1);
    EXPECT_EQ(by_index[i], table[rows[i]]);
  }
  Index indices[8];
  for (int i = 0; i < 8; ++i) indices[i] = 20 + i;
  for (int mask = 0; mask < 256; ++mask) {
    Index packed[8];
    P::compress_indices(indices, mask, packed);
    int k = 0;
    for (int lane = 0; lane < 8; ++lane) {
      if (!(mask & (1 << lane))) continue;
      EXPECT_EQ(packed[k++], indices[lane]) << "mask " << mask;
    }
  }
  for (Index a : {-1, 0, 3, 7, 8, 11, 12}) {
    int expected = 0;
    for (int i = 0; i < 8; ++i) expected |= int(rows[i] > a) << i;
    EXPECT_EQ(P::indices_above(rows, a), expected) << "a " << a;
  }
  // The last, partial pack of a row, padded: only the row's entries are taken.
  for (int count = 0; count < 8; ++count) {
    Index padded[8];
    P::padded_indices(rows, count, -1, padded);
    for (int i = 0; i < 8; ++i) EXPECT_EQ(padded[i], i < count ? rows[i] : -1) << "count " << count << " lane " << i;
  }
}

// The fluid's pack (simd::FloatPack: sixteen floats with AVX-512, eight with AVX2, else the
// scalar lanes) against the scalar lanes of its width: what the fluid's pair loops
// (sph/fluid_pairs.hpp) take of it.
TEST(FloatPackLanes, WhatTheFluidsPairLoopsTakeMatchesTheScalarLanes) {
  using P = simd::FloatPack;
  constexpr int W = P::width;
  using S = simd::lanes::Pack<W, float>;
  std::mt19937_64 rng(17);
  for (int trial = 0; trial < 200; ++trial) {
    const auto a = random_float_lanes<W>(rng), b = random_float_lanes<W>(rng), c = random_float_lanes<W>(rng);
    expect_exact_float_arithmetic<P, S>(a, b, c);
    const P va = P::load(a.data()), vb = P::load(b.data());
    const S sa = S::load(a.data()), sb = S::load(b.data());
    EXPECT_EQ(floats_of(-va), floats_of(-sa));
    EXPECT_EQ(floats_of(min(va, vb)), floats_of(min(sa, sb)));
    EXPECT_EQ(floats_of(max(va, vb)), floats_of(max(sa, sb)));
    EXPECT_EQ((va < vb).lanes(), (sa < sb).lanes());
    for (int i = 0; i < W; ++i) {
      const float estimate[2] = {floats_of(reciprocal(abs(va)))[i], floats_of(reciprocal_sqrt(abs(va)))[i]};
      const float exact[2] = {1 / std::abs(a[i]), 1 / std::sqrt(std::abs(a[i]))};
      for (int k = 0; k < 2; ++k) EXPECT_NEAR(estimate[k], exact[k], 4 * 0x1p-23f * exact[k]);
    }
    EXPECT_EQ(va.sum(), sa.sum());
    simd::WideFloatSum wide;
    simd::lanes::WideSum<W> wide_lanes;
    wide.add(va), wide.add(vb), wide_lanes.add(sa), wide_lanes.add(sb);
    EXPECT_EQ(wide.sum(), wide_lanes.sum());
  }
  // Records of eight floats, element (row, column) = 100 row + column: transposed loads by index
  // and of consecutive rows, the gather of masses, the left-pack of consecutive indices.
  struct alignas(32) Row {  // as sph::FluidRecord
    float v[8];
  };
  std::vector<Row> table(64);
  for (int row = 0; row < 64; ++row)
    for (int column = 0; column < 8; ++column) table[row].v[column] = float(100 * row + column);
  const float* records = table[0].v;
  Index rows[W];
  for (int i = 0; i < W; ++i) rows[i] = (37 * i + 5) % 64;
  P fields[8], positions[3];
  load_rows<8>(records, rows, 0, fields);
  load_consecutive_rows<8>(table[8].v, positions);
  const auto masses = floats_of(P::template gather<1>(records, rows));
  for (int i = 0; i < W; ++i) {
    for (int j = 0; j < 8; ++j) EXPECT_EQ(floats_of(fields[j])[i], 100 * rows[i] + j);
    for (int j = 0; j < 3; ++j) EXPECT_EQ(floats_of(positions[j])[i], 100 * (8 + i) + j);
    EXPECT_EQ(masses[i], records[rows[i]]);
  }
  for (int lanes : {0, 1, 5, 0x30, W == 16 ? 0xA5F0 : 0xF0, (1 << W) - 1}) {
    Index packed[W];
    P::compress_consecutive(40, lanes, packed);
    int k = 0;
    for (int lane = 0; lane < W; ++lane) {
      if (lanes & (1 << lane)) {
        EXPECT_EQ(packed[k++], 40 + lane) << "lanes " << lanes;
      }
    }
  }
}

namespace {

__attribute__((noinline)) double weigh(std::span<const double> w) {
  double sum = 0;
  for (std::size_t i = 0; i < w.size(); ++i) sum += w[i] * static_cast<double>(i + 1);
  return sum;
}

}  // namespace

// The build's flags compile constant vectors as written: Debian 12's GCC 12.2 with AVX-512 stores
// {1, 1, 1, 0} as four ones after a broadcast of 1.0 in the same function unless moves wider than
// 128 bits are off (CMakeLists.txt checks the compiler and sets the flags; this is the same code
// built with them, so that a build that lost the flags fails here).
TEST(Compiler, ConstantVectorsAfterABroadcastKeepTheirZeros) {
  EXPECT_EQ(weigh(std::vector<double>(4, 1.0)), 10.0);
  EXPECT_EQ(weigh(std::vector<double>{1, 1, 1, 0}), 6.0);
  EXPECT_EQ(weigh(std::vector<double>(4, 2.0)), 20.0);
  EXPECT_EQ(weigh(std::vector<double>{2, 2, 0, 0}), 6.0);
  EXPECT_EQ(weigh(std::vector<double>(8, 1.0)), 36.0);
  EXPECT_EQ(weigh(std::vector<double>{1, 1, 1, 1, 1, 1, 1, 0}), 28.0);
}
