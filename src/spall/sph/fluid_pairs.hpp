#pragma once
// The SPH fluid's pair physics (sph/fluid.hpp gives the equations), written once on a number type
// P: a pack of floats of the seam (core/simd.hpp: simd::FloatPack in the pair pass, the scalar
// lanes in the unit test that compares them), one pair per lane, with the kernel a template
// parameter so that its gradient factor inlines. No threads, allocation or exceptions here: the
// pair pass (fluid.cpp) calls these per cell from the seam's loops.
#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <type_traits>

#include "spall/core/simd.hpp"
#include "spall/sph/fluid.hpp"

namespace spall::sph::fluid_pairs {

// Bit i set where particle b + i moves, for i < 16, from the bits of FluidFormulation::moving_.
inline unsigned moving_lanes(const std::uint8_t* moving, Index b) {
  std::uint32_t word;
  std::memcpy(&word, moving + b / 8, sizeof word);
  return (word >> (b % 8)) & 0xFFFFu;
}
// The same, for the slots b .. min(b + 16, end) only (end > b).
inline unsigned moving_lanes(const std::uint8_t* moving, Index b, Index end) {
  return moving_lanes(moving, b) & (0xFFFFu >> (16 - std::min<Index>(end - b, 16)));
}

// What the pair loop reads, in cell order.
struct PairInputs {
  const FluidRecord* record;
  const float* mass;
  float uniform_mass;           // FluidFormulation::uniform_mass_
  const std::uint8_t* moving;  // FluidFormulation::moving_
};

// Constants of the pair terms, in single precision.
struct PairConstants {
  float support_squared;  // H^2
  float inverse_support;  // 1 / H
  float h;                // smoothing length
  float eta2;             // (eta h)^2: regularises 1 / r^2 in Monaghan's and Morris's terms
  float alpha_c;          // alpha c0
  float beta;
  float two_mu;           // mu_a + mu_b
};

// F = (dW/dr) / r of the kernel from r^2 and 1 / r (0 < r < H), on a number type P (a float or a
// pack of them): grad_a W_ab = F x_ab.
template <typename Kernel, typename P>
[[gnu::always_inline]] inline P gradient_factor(P r2, P inverse_r, const PairConstants& c) {
  return Kernel::gradient_factor(r2 * inverse_r, inverse_r, P(c.inverse_support));
}

// The particles within H of each moving particle cluster[0, k) of one cell (except itself), over
// runs that hold each one's trimmed runs (those of the cell's bounding box), a pack P of candidates
// at a time: each pack is loaded once (up to P::width past a run's end: the records are padded,
// and those lanes are masked off) and tested against every particle of the cluster, up to
// max_cluster at a time; the runs are trimmed once per cell (docs/PERFORMANCE.md, session 21).
// Particle cluster[i]'s neighbours go to found + i * stride, count[i] of them, as its own runs
// alone would give them: the rows are the same and in the same order, and a candidate outside the
// particle's own runs lies beyond its support. Every pair is tested by the same fused operations,
// so the pair (a, b) of two moving particles is found from both sides or from neither. Each list
// needs P::width spare slots after it (a pack's indices are written whole).
template <typename P, typename Ranges>
void screen_cluster(const PairInputs& in, float H2, const Index* cluster, int k, const Ranges& ranges,
                    int range_count, Index* found, Index stride, Index* count) {
  constexpr Index pack = P::width;
  // The cluster's positions, each broadcast from here (a cell of the usual lattice holds 5-10).
  constexpr int max_cluster = 64;
  alignas(64) float own[3][max_cluster];
  for (int from = 0; from < k; from += max_cluster) {
    const Index* chunk = cluster + from;
    Index* chunk_found = found + from * stride;
    Index* chunk_count = count + from;
    const int size = std::min(k - from, max_cluster);
    for (int i = 0; i < size; ++i) {
      const FluidRecord& r = in.record[chunk[i]];
      own[0][i] = r.x, own[1][i] = r.y, own[2][i] = r.z;
      chunk_count[i] = 0;
    }
    // Screens the candidates b .. b + pack, the first `valid` of them in the run, against the
    // cluster; may_hold_self: whether the pack overlaps the cluster's slots.
    const auto test = [&](Index b, Index valid, auto may_hold_self) {
      P position[3];
      load_consecutive_rows<8>(&in.record[b].x, position);
      const int in_range = static_cast<int>((1u << valid) - 1);
      for (int i = 0; i < size; ++i) {
        const P dx = P(own[0][i]) - position[0], dy = P(own[1][i]) - position[1], dz = P(own[2][i]) - position[2];
        const P r2 = fma(dz, dz, fma(dy, dy, dx * dx));
        int lanes = (r2 < P(H2)).lanes() & in_range;
        if constexpr (decltype(may_hold_self)::value) {
          const Index self = chunk[i];
          if (self >= b && self < b + pack) lanes &= ~(1 << (self - b));
        }
        P::compress_consecutive(b, lanes, chunk_found + i * stride + chunk_count[i]);
        chunk_count[i] += std::popcount(static_cast<unsigned>(lanes));
      }
    };
    // Only the packs that overlap the cluster's own slots hold a particle of it.
    const Index first_own = chunk[0], past_own = chunk[size - 1] + 1;
    for (int r = 0; r < range_count; ++r) {
      const Index end = ranges[r].end;
      for (Index b = ranges[r].begin; b < end; b += pack) {
        const Index valid = std::min<Index>(end - b, pack);
        if (b < past_own && b + pack > first_own) test(b, valid, std::true_type{});
        else test(b, valid, std::false_type{});
      }
    }
  }
}

// The force is summed in double (momentum cancels pair by pair); its viscous part, which only
// splits the energy balance into stored and dissipated, may be summed in single precision.
struct PairSums {
  Real rate = 0;
  Real fx = 0, fy = 0, fz = 0;     // pressure + viscous force
  Real fvx = 0, fvy = 0, fvz = 0;  // its viscous part
  float max_mu = 0;                // largest -mu_ab of an approaching pair (Monaghan's time step)
};

// The pair sums of particle a over its neighbours found[0, count), a pack P of pairs at a time
// (Wide: P's double accumulator), the kernel's gradient factor inlined. The terms are evaluated in
// single precision by one sequence of operations for every pair (x_ba = -x_ab and v_ba = -v_ab
// bitwise), so the term of (a, b) is exactly minus the term of (b, a); the force is summed in
// double (PairSums), lane by lane in the order of the list, then over the lanes in a fixed order.
// `count` is a multiple of P::width, padded with a itself, whose terms are exactly zero (x_aa = 0,
// v_aa = 0). 1 / r and 1 / (r^2 + (eta h)^2) are P's reciprocals (estimates refined by a Newton
// step in the vector packs: multiplications on two ports, where a square root and a division
// queued on the one port that does those, +4 % on the dam break's pass, docs/PERFORMANCE.md).
// uniform_mass: every particle has the mass in.uniform_mass, so that m_b and the products with
// m_a m_b are loop constants.
template <typename Kernel, typename P, typename Wide, bool uniform_mass>
PairSums interact(const PairInputs& in, const PairConstants& c, Index a, const Index* found, Index count) {
  const FluidRecord& own = in.record[a];
  const P xa(own.x), ya(own.y), za(own.z), vxa(own.vx), vya(own.vy), vza(own.vz);
  const P m_a(in.mass[a]), inverse_rho_a(own.inverse_density), P_a(own.pressure_term);
  const P zero(0.0f), half(0.5f), tiny(1e-30f), eta2(c.eta2), h(c.h), beta(c.beta), minus_alpha_c(-c.alpha_c),
      two_mu(c.two_mu);
  Wide f[3];      // pressure + viscous force
  P fv[3] = {};   // its viscous part
  P rate = zero;  // the density rate needs no double sum (momentum does not depend on it)
  // The most negative mu of an approaching pair (0 if none): mu < 0 exactly where v_ab . x_ab < 0.
  P min_mu = zero;
  for (Index s = 0; s < count; s += P::width) {
    P b[8];  // x, y, z, vx, vy, vz, 1 / rho, p / rho^2 of the pack's neighbours
    load_rows<8>(&in.record->x, found + s, 0, b);
    const P d[3] = {xa - b[0], ya - b[1], za - b[2]};
    const P dv[3] = {vxa - b[3], vya - b[4], vza - b[5]};
    const P r2 = max(fma(d[2], d[2], fma(d[1], d[1], d[0] * d[0])), tiny);
    const P r2e = r2 + eta2;
    const P inverse_r = reciprocal_sqrt(r2), inverse_r2e = reciprocal(r2e);
    const P F = gradient_factor<Kernel>(r2, inverse_r, c);
    const P vr = fma(dv[2], d[2], fma(dv[1], d[1], dv[0] * d[0]));
    const P m_b = uniform_mass ? P(in.uniform_mass) : P::template gather<1>(in.mass, found + s);
    rate = fma(m_b * F, vr, rate);
    const P mm = m_a * m_b;
    const P inverse_rho_b = b[6];
    const P radial = (-mm * (P_a + b[7])) * F;
    // mu of an approaching pair, else 0, which makes Pi exactly 0.
    const P mu = min((h * vr) * inverse_r2e, zero);
    const P Pi = fma(beta, mu * mu, minus_alpha_c * mu) * (half * (inverse_rho_a + inverse_rho_b));
    min_mu = min(min_mu, mu);
    const P viscous_radial = (-mm * Pi) * F;
    const P laminar = ((mm * two_mu) * (inverse_rho_a * inverse_rho_b)) * ((F * r2) * inverse_r2e);
    const P both_radial = radial + viscous_radial;
    for (int i = 0; i < 3; ++i) {
      const P along_dv = laminar * dv[i];
      f[i].add(fma(both_radial, d[i], along_dv));
      fv[i] += fma(viscous_radial, d[i], along_dv);
    }
  }
  PairSums sums;
  sums.rate = rate.sum();
  sums.fx = f[0].sum(), sums.fy = f[1].sum(), sums.fz = f[2].sum();
  sums.fvx = fv[0].sum(), sums.fvy = fv[1].sum(), sums.fvz = fv[2].sum();
  alignas(64) float lanes[P::width];
  min_mu.store(lanes);
  sums.max_mu = -*std::min_element(lanes, lanes + P::width);
  return sums;
}

// The continuity rates of the walls w[0, count) (count <= P::width) of one cell, from the moving
// particles of the runs `spans` (their block, cut to moving spans): rate_w = sum_b m_b F_wb
// v_wb . x_wb over the moving b with r_wb < H, each pair's term by the operations interact uses,
// into rates[0, count). Walls see only moving particles, as DualSPHysics' boundary particles see
// only the fluid: walls rest (their translations are held), so a term with another wall is
// exactly zero. The walls take the lanes of a pack P and each moving neighbour is
// broadcast to all of them, so that a cell's walls read the spans once where each screened them
// on its own, about half the walls' cost (docs/PERFORMANCE.md, session 19). A wall's sum runs in
// single precision in span order: the walls' density needs no exact cancellation.
template <typename Kernel, typename P, typename Ranges>
void wall_rates(const PairInputs& in, const PairConstants& c, const Index* w, int count, const Ranges& spans,
                int span_count, Real* rates) {
  constexpr int group = P::width;
  alignas(64) float lanes[7][group];
  for (int k = 0; k < group; ++k) {  // lanes past count repeat the last wall
    const FluidRecord& own = in.record[w[std::min(k, count - 1)]];
    lanes[0][k] = own.x, lanes[1][k] = own.y, lanes[2][k] = own.z;
    lanes[3][k] = own.vx, lanes[4][k] = own.vy, lanes[5][k] = own.vz;
  }
  const P xa = P::load(lanes[0]), ya = P::load(lanes[1]), za = P::load(lanes[2]);
  const P vxa = P::load(lanes[3]), vya = P::load(lanes[4]), vza = P::load(lanes[5]);
  const P zero(0.0f), tiny(1e-30f), H2(c.support_squared);
  P rate = zero;
  for (int r = 0; r < span_count; ++r) {
    const Index end = spans[r].end;
    for (Index first = spans[r].begin; first < end; first += 16) {
      unsigned moving = moving_lanes(in.moving, first, end);
      for (; moving != 0; moving &= moving - 1) {
        const Index b = first + std::countr_zero(moving);
        const FluidRecord& other = in.record[b];
        const P dx = xa - P(other.x), dy = ya - P(other.y), dz = za - P(other.z);
        const P r2_exact = fma(dz, dz, fma(dy, dy, dx * dx));
        const P r2 = max(r2_exact, tiny);
        const P F = gradient_factor<Kernel>(r2, reciprocal_sqrt(r2), c);
        const P vr = fma(vza - P(other.vz), dz, fma(vya - P(other.vy), dy, (vxa - P(other.vx)) * dx));
        const float m_b = in.uniform_mass > 0 ? in.uniform_mass : in.mass[b];
        rate += select(r2_exact < H2, (P(m_b) * F) * vr, zero);
      }
    }
  }
  rate.store(lanes[6]);
  for (int k = 0; k < count; ++k) rates[k] = Real(lanes[6][k]);
}

}  // namespace spall::sph::fluid_pairs
