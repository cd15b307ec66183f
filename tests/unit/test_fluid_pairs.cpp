// The SPH fluid's pair physics (sph/fluid_pairs.hpp) is written once, on a number type: the pair
// pass runs it on the build's widest float pack (simd::FloatPack), and here it runs on the scalar
// lanes of the same width too. Both must give the sums of the equations in sph/fluid.hpp,
// evaluated here in double pair by pair (continuity and pressure of Monaghan 1994, the
// artificial viscosity of Monaghan 1992 with the mean of the inverse densities, Morris, Fox & Zhu
// 1997's laminar term), to single-precision round-off, for every kernel SPHKERN offers; the
// screen must find the same neighbours on both; and the pack's term of (a, b) must be exactly
// minus that of (b, a), which is what conserves momentum to round-off.
// GCC 12 reports the self-initialised placeholder of its AVX-512 intrinsics (_mm512_undefined_ps in
// avx512fintrin.h) as "used uninitialized" once this test inlines the sixteen-lane pair loop at -O3;
// the pair pass itself (sph/fluid.cpp) inlines the same code without the report.
#pragma GCC diagnostic ignored "-Wuninitialized"
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <random>
#include <vector>

#include "spall/kernels/kernel.hpp"
#include "spall/sph/fluid_pairs.hpp"

using namespace spall;
using namespace spall::sph::fluid_pairs;

namespace {

using Pack = simd::FloatPack;
using WidePack = simd::WideFloatSum;
constexpr int W = Pack::width;
using Scalar = simd::lanes::Pack<W, float>;
using WideScalar = simd::lanes::WideSum<W>;
using Ranges = std::array<neighbors::ParticleRange, 1>;

constexpr Real H = 0.026;  // support 2h, h = 1.3 x 0.01 m
constexpr int n = 60;

// n particles of water scattered around the middle of a box of 2H, moving and slightly
// compressed at random, with unequal masses; the records padded as the formulation pads them.
struct Cloud {
  std::vector<sph::FluidRecord> record;
  std::vector<float> mass;
  std::vector<std::uint8_t> moving;
  PairConstants constants;
  PairInputs inputs() const { return {record.data(), mass.data(), 0.0f, moving.data()}; }
};

Cloud cloud() {
  Cloud c;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<Real> unit(-1, 1);
  c.record.assign(n + W + 1, sph::FluidRecord{});
  c.mass.assign(n + W + 1, 0);
  c.moving.assign(n / 8 + 8, 0);
  for (int a = 0; a < n; ++a) {
    sph::FluidRecord& r = c.record[a];
    r.x = static_cast<float>(H * (1 + 0.8 * unit(rng)));
    r.y = static_cast<float>(H * (1 + 0.8 * unit(rng)));
    r.z = static_cast<float>(H * (1 + 0.8 * unit(rng)));
    r.vx = static_cast<float>(unit(rng)), r.vy = static_cast<float>(unit(rng)), r.vz = static_cast<float>(unit(rng));
    const Real rho = 1000 * (1 + 0.01 * unit(rng));
    const Real p = 2.2e5 * (rho / 1000 - 1) + 1e3;
    r.inverse_density = static_cast<float>(1 / rho);
    r.pressure_term = static_cast<float>(p / (rho * rho));
    c.mass[a] = static_cast<float>(1e-3 * (1 + 0.2 * unit(rng)));
    if (a % 3 != 0) c.moving[a / 8] |= static_cast<std::uint8_t>(1u << (a % 8));  // every third a wall
  }
  const Real h = H / 2, c0 = 15, alpha = 0.1, beta = 1.5, eta = 0.1, mu = 0.3;
  c.constants = {float(H * H), float(1 / H), float(h), float(eta * eta * h * h), float(alpha * c0), float(beta),
                 float(2 * mu)};
  return c;
}

struct Reference {
  Real rate = 0, f[3] = {}, fv[3] = {}, scale_rate = 0, scale_f = 0;
};

// The equations of sph/fluid.hpp for particle a over the list, in double.
template <typename Kernel>
Reference reference(const Cloud& cl, Index a, const std::vector<Index>& list) {
  const auto& k = cl.constants;
  const sph::FluidRecord& p = cl.record[a];
  Reference out;
  for (Index b : list) {
    const sph::FluidRecord& q = cl.record[b];
    const Real x[3] = {Real(p.x) - q.x, Real(p.y) - q.y, Real(p.z) - q.z};
    const Real v[3] = {Real(p.vx) - q.vx, Real(p.vy) - q.vy, Real(p.vz) - q.vz};
    const Real r2 = x[0] * x[0] + x[1] * x[1] + x[2] * x[2], r = std::sqrt(r2);
    const Real F = Kernel::gradient_factor(r, 1 / r, 1 / H);
    const Real vr = v[0] * x[0] + v[1] * x[1] + v[2] * x[2];
    const Real ma = cl.mass[a], mb = cl.mass[b];
    out.rate += mb * F * vr;
    out.scale_rate += std::abs(mb * F * vr);
    const Real r2e = r2 + Real(k.eta2);
    const Real mu = Real(k.h) * vr / r2e;
    const Real Pi = vr < 0 ? (-Real(k.alpha_c) * mu + Real(k.beta) * mu * mu) *
                                 (0.5 * (Real(p.inverse_density) + Real(q.inverse_density)))
                           : 0;
    const Real pressure = -ma * mb * (Real(p.pressure_term) + Real(q.pressure_term)) * F;
    const Real laminar = ma * mb * Real(k.two_mu) * Real(p.inverse_density) * Real(q.inverse_density) * F * r2 / r2e;
    for (int d = 0; d < 3; ++d) {
      const Real viscous = -ma * mb * Pi * F * x[d] + laminar * v[d];
      out.fv[d] += viscous;
      out.f[d] += pressure * x[d] + viscous;
      out.scale_f += std::abs(pressure * x[d]) + std::abs(viscous);
    }
  }
  return out;
}

// Particle a's list as the pair pass hands it over: padded with a to a multiple of W.
std::vector<Index> padded(std::vector<Index> list, Index a) {
  while (list.size() % W != 0) list.push_back(a);
  return list;
}

template <typename P>
std::vector<std::vector<Index>> screened(const Cloud& cl) {
  const Ranges all{{{0, n}}};
  std::vector<Index> found(n * (n + 2 * W)), count(n), cluster(n);
  for (Index a = 0; a < n; ++a) cluster[a] = a;
  const Index stride = n + 2 * W;
  screen_cluster<P>(cl.inputs(), cl.constants.support_squared, cluster.data(), n, all, 1, found.data(), stride,
                    count.data());
  std::vector<std::vector<Index>> lists(n);
  for (Index a = 0; a < n; ++a) lists[a].assign(found.begin() + a * stride, found.begin() + a * stride + count[a]);
  return lists;
}

template <typename K>
class FluidPairs : public ::testing::Test {};
using Kernels = ::testing::Types<kernels::CubicSpline<3>, kernels::QuinticSpline<3>, kernels::WendlandC2<3>,
                                 kernels::CubicSpline<2>>;
TYPED_TEST_SUITE(FluidPairs, Kernels);

TYPED_TEST(FluidPairs, PackAndScalarLanesGiveTheEquationsSumsToFloatRoundOff) {
  using Kernel = TypeParam;
  const Cloud cl = cloud();
  const auto lists = screened<Pack>(cl);
  ASSERT_EQ(lists, screened<Scalar>(cl));  // the same fused distance test on both
  Index pairs = 0;
  for (Index a = 0; a < n; ++a) {
    pairs += static_cast<Index>(lists[a].size());
    const auto list = padded(lists[a], a);
    const Index count = static_cast<Index>(list.size());
    const PairSums pack = interact<Kernel, Pack, WidePack, false>(cl.inputs(), cl.constants, a, list.data(), count);
    const PairSums lanes = interact<Kernel, Scalar, WideScalar, false>(cl.inputs(), cl.constants, a, list.data(), count);
    const Reference exact = reference<Kernel>(cl, a, lists[a]);
    // Each term is a few float roundings off; 1e-5 of the sum of their sizes covers them.
    const Real tol_rate = 1e-5 * exact.scale_rate + 1e-30, tol_f = 1e-5 * exact.scale_f + 1e-30;
    for (const PairSums* s : {&pack, &lanes}) {
      EXPECT_NEAR(s->rate, exact.rate, tol_rate) << "particle " << a;
      EXPECT_NEAR(s->fx, exact.f[0], tol_f) << "particle " << a;
      EXPECT_NEAR(s->fy, exact.f[1], tol_f) << "particle " << a;
      EXPECT_NEAR(s->fz, exact.f[2], tol_f) << "particle " << a;
      EXPECT_NEAR(s->fvx, exact.fv[0], tol_f) << "particle " << a;
      EXPECT_NEAR(s->fvy, exact.fv[1], tol_f) << "particle " << a;
      EXPECT_NEAR(s->fvz, exact.fv[2], tol_f) << "particle " << a;
    }
  }
  EXPECT_GT(pairs, 10 * n);  // the cloud is dense enough to test sums, not single terms
}

TYPED_TEST(FluidPairs, TheTermOfABIsExactlyMinusTheTermOfBA) {
  using Kernel = TypeParam;
  const Cloud cl = cloud();
  const auto lists = screened<Pack>(cl);
  for (Index a = 0; a < n; ++a)
    for (Index b : lists[a]) {
      const auto ab = padded({b}, a), ba = padded({a}, b);
      const PairSums s_ab = interact<Kernel, Pack, WidePack, false>(cl.inputs(), cl.constants, a, ab.data(), W);
      const PairSums s_ba = interact<Kernel, Pack, WidePack, false>(cl.inputs(), cl.constants, b, ba.data(), W);
      ASSERT_EQ(s_ab.fx, -s_ba.fx) << a << " " << b;
      ASSERT_EQ(s_ab.fy, -s_ba.fy) << a << " " << b;
      ASSERT_EQ(s_ab.fz, -s_ba.fz) << a << " " << b;
    }
}

// The walls' continuity rates (walls in the lanes, moving neighbours broadcast), on the pack of
// eight and on the scalar lanes, against the continuity sum in double over the moving particles
// within H.
TYPED_TEST(FluidPairs, WallRatesAreTheContinuitySumOverMovingNeighbours) {
  using Kernel = TypeParam;
  const Cloud cl = cloud();
  std::vector<Index> walls;
  for (Index a = 0; a < n; ++a)
    if (!(moving_lanes(cl.moving.data(), a) & 1u)) walls.push_back(a);
  const Ranges all{{{0, n}}};
  for (std::size_t w = 0; w < walls.size(); w += 8) {
    const int count = static_cast<int>(std::min<std::size_t>(8, walls.size() - w));
    Real pack[8], lanes[8];
    wall_rates<Kernel, simd::Float8>(cl.inputs(), cl.constants, walls.data() + w, count, all, 1, pack);
    wall_rates<Kernel, simd::lanes::Pack<8, float>>(cl.inputs(), cl.constants, walls.data() + w, count, all, 1, lanes);
    for (int k = 0; k < count; ++k) {
      const Index a = walls[w + k];
      std::vector<Index> moving_neighbours;
      for (Index b = 0; b < n; ++b) {
        const auto& p = cl.record[a];
        const auto& q = cl.record[b];
        const Real r2 = Real(p.x - q.x) * (p.x - q.x) + Real(p.y - q.y) * (p.y - q.y) + Real(p.z - q.z) * (p.z - q.z);
        if ((moving_lanes(cl.moving.data(), b) & 1u) && r2 < H * H) moving_neighbours.push_back(b);
      }
      const Reference exact = reference<Kernel>(cl, a, moving_neighbours);
      EXPECT_NEAR(pack[k], exact.rate, 1e-5 * exact.scale_rate + 1e-30) << "wall " << a;
      EXPECT_NEAR(lanes[k], exact.rate, 1e-5 * exact.scale_rate + 1e-30) << "wall " << a;
    }
  }
}

}  // namespace
