#include "spall/sph/fluid.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <cstring>
#include <functional>
#include <stdexcept>
#include <type_traits>
#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include <fmt/format.h>

#include "spall/core/error.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/simd.hpp"
#include "spall/kernels/cubic_spline.hpp"
#include "spall/neighbors/trimmed_stencil.hpp"

namespace spall::sph {

namespace {

// All three translations held: a dynamic boundary (wall) particle.
constexpr std::uint8_t all_translations = 7;

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

// Shrinks each range to the span from its first to its last moving particle, dropping the ranges
// without one, in place; returns how many are left.
template <typename Ranges>
int moving_spans(const std::uint8_t* moving, Ranges& ranges, int count) {
  int kept = 0;
  for (int r = 0; r < count; ++r) {
    Index begin = ranges[r].begin, end = ranges[r].end;
    while (begin < end) {  // the first moving particle, sixteen slots at a time
      const unsigned bits = moving_lanes(moving, begin, end);
      if (bits) {
        begin += std::countr_zero(bits);
        break;
      }
      begin += 16;
    }
    if (begin >= end) continue;
    while (true) {  // past the last one, from the end (begin moves, so this stops there)
      const Index from = std::max(begin, end - 16);
      const unsigned bits = moving_lanes(moving, from, end);
      if (bits) {
        end = from + 32 - std::countl_zero(bits);
        break;
      }
      end = from;
    }
    ranges[kept++] = {begin, end};
  }
  return kept;
}

// Time-step factors. Courant: the predictor-corrector density update is stable for w dt < 0.72
// and the fastest SPH acoustic mode has w ~ 1.04 c / h (cubic spline), so h / (c + |v| + the
// viscous signal speed) is scaled by 0.4 (w dt ~ 0.42). Force: Monaghan 1992,
// dt <= 0.25 sqrt(h / |a|). Viscous: Morris et al. 1997, dt <= 0.125 h^2 / nu.
constexpr Real courant_factor = 0.4;
constexpr Real force_factor = 0.25;
constexpr Real viscous_factor = 0.125;

// Cells of edge (support + skin) / 2, searched by the trimmed stencil: each particle screens only
// the runs of cells that can reach its support (neighbors/trimmed_stencil.hpp).
constexpr int stencil_reach = 2;
// Lanes of the pair loops (16 single-precision lanes where the build targets AVX-512, else 8 with
// AVX2, else scalar). The records have this many past the last particle, plus one, so that the
// screen's last loads of a range stay inside them (the lanes past the range are masked).
#if defined(SPALL_SIMD_AVX512)
constexpr Index simd_width = 16;
#else
constexpr Index simd_width = 8;
#endif
// Walls whose continuity sums run side by side, one per single-precision lane (wall_rates).
constexpr int wall_group = 8;

template <typename T>
void permute(std::vector<T>& values, std::span<const Index> order) {
  std::vector<T> sorted(values.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = values[order[k]];
  values.swap(sorted);
}

template <typename T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

FluidMaterial FluidMaterial::tait(Real rho0, Real c0, Real gamma, Real mu) {
  FluidMaterial m;
  m.density = rho0;
  m.eos = materials::Murnaghan{gamma, rho0 * c0 * c0 / gamma};
  m.dynamic_viscosity = mu;
  return m;
}

Real FluidMaterial::pressure(Real rho) const {
  return std::max(materials::evaluate_eos(eos, density, rho, specific_energy).pressure,
                  pressure_cutoff);
}

Real FluidMaterial::sound_speed_at(Real rho) const {
  const auto value = materials::evaluate_eos(eos, density, rho, specific_energy);
  return std::sqrt(std::max(materials::isentropic_bulk_modulus(value, rho), Real(0)) / rho);
}

FluidFormulation::FluidFormulation(const FluidParameters& parameters,
                                   const std::vector<Index>& particle_nodes,
                                   const discretization::NodeStore& nodes)
    : parameters_(parameters), support_(2 * parameters.smoothing_length) {
  const auto& m = parameters_.material;
  if (!(m.density > 0) || !(m.reference_sound_speed() > 0) || !(m.dynamic_viscosity >= 0))
    throw std::invalid_argument("SPH fluid: needs rho0 > 0, a sound speed > 0 at rho0 and mu >= 0");
  if (!(parameters_.smoothing_length > 0))
    throw std::invalid_argument("SPH fluid: the smoothing length must be > 0");
  if (parameters_.dimension != 2 && parameters_.dimension != 3)
    throw std::invalid_argument("SPH fluid: the dimension must be 2 or 3");
  if (parameters_.dimension == 2)
    for (Index i : particle_nodes)
      if (nodes.x[i].z() != nodes.x[particle_nodes.front()].z())
        throw std::invalid_argument("SPH fluid: in 2D every particle must lie in one plane z = const");
  const std::size_t n = particle_nodes.size();
  node_ = particle_nodes;
  mass_.resize(n);
  for (std::size_t a = 0; a < n; ++a) mass_[a] = static_cast<float>(nodes.mass[node_[a]]);
  if (n > 0 && std::adjacent_find(mass_.begin(), mass_.end(), std::not_equal_to<>()) == mass_.end())
    uniform_mass_ = mass_.front();
  density_.assign(n, m.density);
  rate_.assign(n, 0);
  previous_rate_.assign(n, 0);
  record_.assign(n + simd_width + 1, FluidRecord{});
  pressure_force_.assign(3 * n, 0);
  viscous_force_.assign(3 * n, 0);
  max_sound_speed_ = m.reference_sound_speed();
}

// Bins the particles into cells of edge (support + skin) / 2 and puts every per-particle array in
// cell order, so that the particles of a cell are contiguous.
void FluidFormulation::rebuild_cells(const discretization::NodeStore& nodes) {
  const Index n = particle_count();
  std::vector<Vec3> x(n);
  std::vector<Id> id(n);
  parallel::for_each(n, [&](Index a) {
    x[a] = nodes.x[node_[a]];
    id[a] = nodes.id[node_[a]];
  });
  // Within a cell by node ID: the order, and so every sum over neighbours, is the same however the
  // particles were stored (the deck's card order, earlier rebuilds, a rank's share of them).
  cells_.build(x, (1 + parameters_.skin) * support_ / stencil_reach, id);
  // The cell list keeps no order: from here on the particles are in cell order.
  const std::vector<Index> order = cells_.take_order();
  permute(node_, order);
  share_.reorder();
  permute(mass_, order);
  permute(density_, order);
  permute(rate_, order);
  permute(previous_rate_, order);
  // Moving particles before each slot, to tell in O(1) whether a slot range holds one.
  std::vector<Index> moving_before(n + 1, 0);
  // Bits to n + simd_width, and the four bytes that moving_lanes reads from the last one.
  moving_.assign((n + simd_width) / 8 + 4, 0);
  for (Index a = 0; a < n; ++a) {
    const bool moving = nodes.fixed[node_[a]] != all_translations;
    moving_[a / 8] |= static_cast<std::uint8_t>(moving << (a % 8));
    moving_before[a + 1] = moving_before[a] + moving;
  }
  const Index cell_count = cells_.cell_count();
  active_cell_.assign(cell_count, 0);
  parallel::region([&](const parallel::Team& team) {
    neighbors::TrimmedStencil stencil(cells_, stencil_reach);
    neighbors::TrimmedStencil::Ranges ranges;
    team.for_each(cell_count, [&](Index c) {
      stencil.prepare(c);
      const int range_count = stencil.block(ranges);
      for (int r = 0; r < range_count; ++r)
        if (moving_before[ranges[r].end] > moving_before[ranges[r].begin]) active_cell_[c] = 1;
    }, {.chunk = 64});
  });
  // Positions are taken relative to the grid corner, in single precision: a position and the
  // distance test carry relative errors of a few 2^-24 of the box size and of the support, which
  // the stencil's radius covers with this margin.
  origin_ = cells_.lower();
  const auto& along = cells_.cells_along();
  const Real box = cells_.cell_size() * static_cast<Real>(std::max({along[0], along[1], along[2]}));
  rounding_margin_ = 1e-6 * (box + support_);
  cells_built_ = true;
  travelled_ = 0;
}

// Copies positions and velocities in cell order, predicts the densities and evaluates the
// equation of state once per particle. The density terms only in the active cells: the walls of
// a cell without a moving particle in its block (far from the fluid) are read by no pair until
// the next rebuild (for_each_particle_candidates), and their density does not change.
void FluidFormulation::gather(const discretization::NodeStore& nodes, Real dt) {
  const Index n = particle_count();
  const auto& m = parameters_.material;
  struct Found {
    Real max_density;
    Index first_empty;  // the first particle whose density is no longer positive
  };
  const Index cell_count = cells_.cell_count();
  const auto cell_records = [&](Index c) {
    Found found{m.density, n};
    const bool active = active_cell_[c];
    const neighbors::ParticleRange own = cells_.cell(c);
    for (Index a = own.begin; a < own.end; ++a) {
      const Index i = node_[a];
      const Vec3 p = nodes.x[i] - origin_;
      const Vec3& v = nodes.v[i];
      FluidRecord& record = record_[a];
      record.x = static_cast<float>(p.x());
      record.y = static_cast<float>(p.y());
      record.z = static_cast<float>(p.z());
      record.vx = static_cast<float>(v.x());
      record.vy = static_cast<float>(v.y());
      record.vz = static_cast<float>(v.z());
      if (!active) continue;
      // rho~^n = rho^{n-1} + dt (2 rho'^{n-1} - rho'^{n-2})
      Real rho = density_[a] + dt * (2 * Real(rate_[a]) - Real(previous_rate_[a]));
      if (nodes.fixed[i] == all_translations) rho = std::max(rho, m.density);
      if (!(rho > 0)) found.first_empty = std::min(found.first_empty, a);
      record.inverse_density = static_cast<float>(1 / rho);
      record.pressure_term = static_cast<float>(m.pressure(rho) / (rho * rho));
      found.max_density = std::max(found.max_density, rho);
    }
    return found;
  };
  const auto [max_density, first_empty] = parallel::reduce_exact(
      cell_count, Found{m.density, n}, cell_records, [](const Found& x, const Found& y) {
        return Found{std::max(x.max_density, y.max_density), std::min(x.first_empty, y.first_empty)};
      });
  // Continuity can empty a particle that a splash tears from its neighbours under tension; its
  // pressure and volume then mean nothing, so the run stops rather than carry on.
  if (first_empty < n)
    throw InstabilityError(fmt::format(
        "SPH fluid: the particle on node {} has density {:.6g}: it was torn from its neighbours "
        "(a pressure cutoff PC on the *MAT_NULL, e.g. 0, keeps a liquid from taking tension)",
        nodes.id[node_[first_empty]],
        density_[first_empty] + dt * (2 * Real(rate_[first_empty]) - Real(previous_rate_[first_empty]))));
  max_sound_speed_ = m.sound_speed_at(max_density);
}

template <bool pair_pass, typename Visit, typename VisitWalls>
void FluidFormulation::for_each_particle_candidates(const parallel::Team& team, Visit&& visit,
                                                   VisitWalls&& visit_walls) const {
  neighbors::TrimmedStencil stencil(cells_, stencil_reach);
  neighbors::TrimmedStencil::Ranges ranges;
  std::vector<Index> cluster, walls;
  // A neighbour within the support now was binned within support + travelled_ of this
  // particle's position now, which is within travelled_ of its own cell: the 5 x 5 x 5 cells of
  // edge (support + skin) / 2 hold it while 2 travelled_ + margin <= skin support (compute_forces).
  const Real radius = support_ + travelled_ + rounding_margin_;
  const Index cell_count = cells_.cell_count();
  // Chunks of consecutive cells, so that the stencil mostly slides along a row of cells.
  team.for_each(cell_count, [&](Index c) {
    const neighbors::ParticleRange own = cells_.cell(c);
    if constexpr (!pair_pass) {
      stencil.prepare(c);
      for (Index a = own.begin; a < own.end; ++a) {
        const FluidRecord& r = record_[a];
        visit(a, ranges, stencil.trimmed(Vec3(r.x, r.y, r.z), radius, ranges));
      }
    } else {
      // The cell's moving particles (the cluster), its walls, and the bounding box of them all.
      cluster.clear(), walls.clear();
      Vec3 lower = Vec3::Constant(std::numeric_limits<Real>::infinity()), upper = -lower;
      // Another rank's particles bound the box (the runs are those of the serial run) but are its to compute.
      for (Index a = own.begin; a < own.end; ++a) {
        const FluidRecord& r = record_[a];
        lower = lower.cwiseMin(Vec3(r.x, r.y, r.z)), upper = upper.cwiseMax(Vec3(r.x, r.y, r.z));
        if (!owns(a)) continue;
        (moving_lanes(moving_.data(), a) & 1u ? cluster : walls).push_back(a);
      }
      // Inactive cells (walls only) have no moving particle within reach.
      int range_count = 0;
      if (active_cell_[c]) {
        stencil.prepare(c);
        range_count = stencil.trimmed(lower, upper, radius, ranges);
      }
      if (!cluster.empty()) visit(cluster.data(), static_cast<int>(cluster.size()), ranges, range_count);
      if (walls.empty()) return;
      // The walls share the cell's runs (the moving particles are done with them), each cut in
      // place to the span from its first to its last moving particle, and come wall_group at a
      // time: cheaper than trimming runs per wall (docs/PERFORMANCE.md, sessions 13, 18 and 19).
      const int span_count = moving_spans(moving_.data(), ranges, range_count);
      for (std::size_t w = 0; w < walls.size(); w += wall_group)
        visit_walls(walls.data() + w, static_cast<int>(std::min<std::size_t>(wall_group, walls.size() - w)), ranges,
                    span_count);
    }
  }, {.chunk = 16});
}

namespace {

// What the pair loop reads, in cell order.
struct PairInputs {
  const FluidRecord* record;
  const float* mass;
  float uniform_mass;           // FluidFormulation::uniform_mass_
  const std::uint8_t* moving;  // FluidFormulation::moving_
};

#if defined(__AVX2__)
// Unpacks and in-lane shuffles act on each 128-bit lane alike, for 256- and 512-bit registers.
inline __m256 unpack_low(__m256 a, __m256 b) { return _mm256_unpacklo_ps(a, b); }
inline __m256 unpack_high(__m256 a, __m256 b) { return _mm256_unpackhi_ps(a, b); }
template <int Pattern>
inline __m256 shuffle(__m256 a, __m256 b) { return _mm256_shuffle_ps(a, b, Pattern); }
#if defined(SPALL_SIMD_AVX512)
inline __m512 unpack_low(__m512 a, __m512 b) { return _mm512_unpacklo_ps(a, b); }
inline __m512 unpack_high(__m512 a, __m512 b) { return _mm512_unpackhi_ps(a, b); }
template <int Pattern>
inline __m512 shuffle(__m512 a, __m512 b) { return _mm512_shuffle_ps(a, b, Pattern); }
#endif

// The in-lane half of the 8 x 8 transpose of the records row(0) .. row(7): s[k] (k < 4) holds
// field k of rows 0-3 in each even 128-bit lane and field k + 4 in each odd one; s[k + 4] the
// same of rows 4-7. A 512-bit row holds two records, one per 256-bit half.
template <typename V, typename Row>
[[gnu::always_inline]] inline void transpose_in_lanes(const Row& row, V (&s)[8]) {
  for (int g = 0; g < 2; ++g) {
    const V r0 = row(4 * g), r1 = row(4 * g + 1), r2 = row(4 * g + 2), r3 = row(4 * g + 3);
    const V t0 = unpack_low(r0, r1), t1 = unpack_high(r0, r1);
    const V t2 = unpack_low(r2, r3), t3 = unpack_high(r2, r3);
    s[4 * g + 0] = shuffle<_MM_SHUFFLE(1, 0, 1, 0)>(t0, t2);
    s[4 * g + 1] = shuffle<_MM_SHUFFLE(3, 2, 3, 2)>(t0, t2);
    s[4 * g + 2] = shuffle<_MM_SHUFFLE(1, 0, 1, 0)>(t1, t3);
    s[4 * g + 3] = shuffle<_MM_SHUFFLE(3, 2, 3, 2)>(t1, t3);
  }
}
#endif

#if defined(SPALL_SIMD_AVX512)
// The positions x, y, z of the sixteen consecutive records r[0..15], lane i from r[i]: eight
// loads and eleven two-source permutes (the three fields of four records per register, then of
// eight, then of sixteen). This is what the records cost the screen, which read three contiguous
// arrays before; the pair terms gain far more (docs/PERFORMANCE.md, session 12).
[[gnu::always_inline]] inline void load_positions(const FluidRecord* r, __m512& first, __m512& second,
                                                  __m512& third) {
  const float* p = &r->x;
  // Records 4j .. 4j + 3: the fields in lanes 0-3, 4-7 and 8-11 (lanes 12-15 are not used).
  const __m512i of_four = _mm512_setr_epi32(0, 8, 16, 24, 1, 9, 17, 25, 2, 10, 18, 26, 0, 8, 16, 24);
  __m512 four[4];
  for (int j = 0; j < 4; ++j)
    four[j] = _mm512_permutex2var_ps(_mm512_loadu_ps(p + 32 * j), of_four, _mm512_loadu_ps(p + 32 * j + 16));
  // Of eight records: the first two fields in lanes 0-7 and 8-15, and the third in lanes 0-7.
  const __m512i two_of_eight = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 4, 5, 6, 7, 20, 21, 22, 23);
  const __m512i third_of_eight = _mm512_setr_epi32(8, 9, 10, 11, 24, 25, 26, 27, 8, 9, 10, 11, 24, 25, 26, 27);
  const __m512 low = _mm512_permutex2var_ps(four[0], two_of_eight, four[1]);
  const __m512 high = _mm512_permutex2var_ps(four[2], two_of_eight, four[3]);
  const __m512 third_low = _mm512_permutex2var_ps(four[0], third_of_eight, four[1]);
  const __m512 third_high = _mm512_permutex2var_ps(four[2], third_of_eight, four[3]);
  first = _mm512_shuffle_f32x4(low, high, _MM_SHUFFLE(1, 0, 1, 0));
  second = _mm512_shuffle_f32x4(low, high, _MM_SHUFFLE(3, 2, 3, 2));
  third = _mm512_shuffle_f32x4(third_low, third_high, _MM_SHUFFLE(1, 0, 1, 0));
}

// The eight fields of the records r[index[0..15]], transposed: field k in out[k]. Lane order
// index 0-3, 8-11, 4-7, 12-15 (lane_order), the same for every field: sixteen loads and 32
// shuffles where eight gathers would take about 28 cycles each.
constexpr int lane_order[16] = {0, 1, 2, 3, 8, 9, 10, 11, 4, 5, 6, 7, 12, 13, 14, 15};
[[gnu::always_inline]] inline void load_records(const FluidRecord* r, const Index* index, __m512 (&out)[8]) {
  const auto rows = [&](int i) {  // record index[i] in lanes 0-7, index[i + 8] in lanes 8-15
    return _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_load_ps(&r[index[i]].x)),
                              _mm256_load_ps(&r[index[i + 8]].x), 1);
  };
  // Within each 256-bit half: s[k] holds field k of records 0-3 and 8-11 in its 128-bit lanes 0
  // and 2, field k + 4 in lanes 1 and 3; s[k + 4] the same of records 4-7 and 12-15.
  __m512 s[8];
  transpose_in_lanes(rows, s);
  for (int k = 0; k < 4; ++k) {
    out[k] = _mm512_shuffle_f32x4(s[k], s[k + 4], _MM_SHUFFLE(2, 0, 2, 0));
    out[k + 4] = _mm512_shuffle_f32x4(s[k], s[k + 4], _MM_SHUFFLE(3, 1, 3, 1));
  }
}
#elif defined(__AVX2__)
// The positions x, y, z of the eight consecutive records r[0..7], lane i from r[i]: the first
// halves of records i and i + 4 in one register (four loads and inserts), then the 4 x 4
// transpose within the 128-bit lanes, seven shuffles where the whole 8 x 8 one takes seventeen.
[[gnu::always_inline]] inline void load_positions(const FluidRecord* r, __m256& x, __m256& y, __m256& z) {
  const auto rows = [&](int i) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(&r[i].x)), _mm_load_ps(&r[i + 4].x), 1);
  };
  const __m256 r0 = rows(0), r1 = rows(1), r2 = rows(2), r3 = rows(3);
  const __m256 xy01 = _mm256_unpacklo_ps(r0, r1), xy23 = _mm256_unpacklo_ps(r2, r3);
  const __m256 zw01 = _mm256_unpackhi_ps(r0, r1), zw23 = _mm256_unpackhi_ps(r2, r3);
  x = _mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(1, 0, 1, 0));
  y = _mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(3, 2, 3, 2));
  z = _mm256_shuffle_ps(zw01, zw23, _MM_SHUFFLE(1, 0, 1, 0));
}

// The 8 x 8 transpose of the eight records row(0) .. row(7): field k of the eight in out[k].
template <typename Row>
[[gnu::always_inline]] inline void transpose_records(const Row& row, __m256 (&out)[8]) {
  __m256 s[8];
  transpose_in_lanes(row, s);
  for (int k = 0; k < 4; ++k) {
    out[k] = _mm256_permute2f128_ps(s[k], s[k + 4], 0x20);
    out[k + 4] = _mm256_permute2f128_ps(s[k], s[k + 4], 0x31);
  }
}
#endif

// Constants of the pair terms, in single precision.
struct PairConstants {
  float support_squared;  // H^2
  float inverse_support;  // 1 / H
  float kernel;           // k = sigma / H^(d+2): F = k (18 q - 12) or -6 k (1 - q)^2 / q
  float h;                // smoothing length
  float eta2;             // (eta h)^2: regularises 1 / r^2 in Monaghan's and Morris's terms
  float alpha_c;          // alpha c0
  float beta;
  float two_mu;           // mu_a + mu_b
};

// F = (dW/dr) / r of the cubic spline (seed 000 eq. 3 differentiated) from r^2 and 1 / r:
// k (18 q - 12) for q = r / H <= 1/2, -6 k (1 - q)^2 / q beyond, with 1 / q = H / r.
inline float gradient_factor(float r2, float inverse_r, const PairConstants& c) {
  const float q = std::min(r2 * inverse_r * c.inverse_support, 1.0f);
  return q <= 0.5f ? 18 * c.kernel * q - 12 * c.kernel
                   : -(6 * c.kernel / c.inverse_support) * ((1 - q) * (1 - q)) * inverse_r;
}
#if defined(__AVX2__)
// 1 / r and 1 / x of eight pairs from the estimates and one Newton step (simd::Float8): the
// square root and the division queue on one port (docs/PERFORMANCE.md, session 17).
[[gnu::always_inline]] inline __m256 inverse_sqrt(__m256 r2) { return reciprocal_sqrt(simd::Float8(r2)).v; }
[[gnu::always_inline]] inline __m256 inverse(__m256 x) { return reciprocal(simd::Float8(x)).v; }
// gradient_factor of eight pairs, by the same operations.
[[gnu::always_inline]] inline __m256 gradient_factor(__m256 r2, __m256 inverse_r, const PairConstants& c) {
  const __m256 one = _mm256_set1_ps(1), half = _mm256_set1_ps(0.5f);
  const __m256 q = _mm256_min_ps(_mm256_mul_ps(_mm256_mul_ps(r2, inverse_r), _mm256_set1_ps(c.inverse_support)), one);
  const __m256 near = _mm256_sub_ps(_mm256_mul_ps(_mm256_set1_ps(18 * c.kernel), q), _mm256_set1_ps(12 * c.kernel));
  const __m256 one_minus_q = _mm256_sub_ps(one, q);
  const __m256 far = _mm256_mul_ps(
      _mm256_mul_ps(_mm256_set1_ps(-(6 * c.kernel / c.inverse_support)), _mm256_mul_ps(one_minus_q, one_minus_q)),
      inverse_r);
  return _mm256_blendv_ps(far, near, _mm256_cmp_ps(q, half, _CMP_LE_OQ));
}
#endif

// The force is summed in double (momentum cancels pair by pair); its viscous part, which only
// splits the energy balance into stored and dissipated, may be summed in single precision.
struct PairSums {
  Real rate = 0;
  Real fx = 0, fy = 0, fz = 0;     // pressure + viscous force
  Real fvx = 0, fvy = 0, fvz = 0;  // its viscous part
  float max_mu = 0;                // largest -mu_ab of an approaching pair (Monaghan's time step)
};

// The particles within H of each moving particle cluster[0, k) of one cell (except itself), over
// runs that hold each one's trimmed runs (those of the cell's bounding box). The vector paths load
// each pack of simd_width candidates once (up to simd_width past a run's end: the records are
// padded, and those lanes are masked off) and test it against every particle of the cluster, up
// to max_cluster at a time; the runs are trimmed once per cell (docs/PERFORMANCE.md, session 21).
// Particle cluster[i]'s neighbours go to found + i * stride, count[i] of them, as its own runs
// alone would give them: the rows are the same and in the same order, and a candidate outside the
// particle's own runs lies beyond its support. Every path tests by the same fused operations, so
// the pair (a, b) of two moving particles is found from both sides or from neither. Each list
// needs simd_width spare slots after it (the vector paths write simd_width entries at a time).
template <typename Ranges>
void screen_cluster(const PairInputs& in, float H2, const Index* cluster, int k, const Ranges& ranges,
                    int range_count, Index* found, Index stride, Index* count) {
#if defined(SPALL_SIMD_AVX512) || (defined(__AVX2__) && defined(__BMI2__))
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
    // test(b, valid, may_hold_self) screens the pack of candidates b .. b + pack, the first valid
    // of them in the run, against the cluster; may_hold_self: whether the pack overlaps its slots.
#if defined(SPALL_SIMD_AVX512)
    constexpr Index pack = 16;
    const __m512 vH2 = _mm512_set1_ps(H2);
    const __m512i lane = _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15);
    const auto test = [&](Index b, Index valid, auto may_hold_self) {
      __m512 xb, yb, zb;
      load_positions(in.record + b, xb, yb, zb);
      const __m512i index = _mm512_add_epi32(_mm512_set1_epi32(b), lane);
      const unsigned in_range = 0xFFFFu >> (16 - valid);
      for (int i = 0; i < size; ++i) {
        const __m512 dx = _mm512_sub_ps(_mm512_set1_ps(own[0][i]), xb);
        const __m512 dy = _mm512_sub_ps(_mm512_set1_ps(own[1][i]), yb);
        const __m512 dz = _mm512_sub_ps(_mm512_set1_ps(own[2][i]), zb);
        const __m512 r2 = _mm512_fmadd_ps(dz, dz, _mm512_fmadd_ps(dy, dy, _mm512_mul_ps(dx, dx)));
        unsigned lanes = in_range;
        if constexpr (decltype(may_hold_self)::value) {
          const Index self = chunk[i];
          if (self >= b && self < b + pack) lanes &= ~(1u << (self - b));
        }
        const __mmask16 mask = _mm512_mask_cmp_ps_mask(static_cast<__mmask16>(lanes), r2, vH2, _CMP_LT_OQ);
        // Left-pack in a register and store all 16 lanes (the list has the spare slots): the
        // compressing store to memory is no faster on Intel cores and microcoded, far slower, on
        // AMD Zen 4.
        _mm512_storeu_si512(chunk_found + i * stride + chunk_count[i], _mm512_maskz_compress_epi32(mask, index));
        chunk_count[i] += std::popcount(static_cast<unsigned>(mask));
      }
    };
#else
    constexpr Index pack = 8;
    const __m256 vH2 = _mm256_set1_ps(H2);
    const auto test = [&](Index b, Index valid, auto may_hold_self) {
      __m256 xb, yb, zb;
      load_positions(in.record + b, xb, yb, zb);
      const __m256i base = _mm256_set1_epi32(b);
      for (int i = 0; i < size; ++i) {
        const __m256 dx = _mm256_sub_ps(_mm256_broadcast_ss(&own[0][i]), xb);
        const __m256 dy = _mm256_sub_ps(_mm256_broadcast_ss(&own[1][i]), yb);
        const __m256 dz = _mm256_sub_ps(_mm256_broadcast_ss(&own[2][i]), zb);
        const __m256 r2 = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
        unsigned mask = _bzhi_u32(static_cast<unsigned>(_mm256_movemask_ps(_mm256_cmp_ps(r2, vH2, _CMP_LT_OQ))),
                                  static_cast<unsigned>(valid));
        if constexpr (decltype(may_hold_self)::value) {
          const Index self = chunk[i];
          if (self >= b && self < b + pack) mask &= ~(1u << (self - b));
        }
        // Left-pack the lanes whose bit is set: their numbers from the table, one byte each (a load
        // where pdep, a multiplication and pext made a chain of three).
        const std::uint64_t lanes = simd::avx2::compress_lanes8.order[mask];
        const __m256i index = _mm256_add_epi32(base, _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(lanes))));
        _mm256_storeu_si256(reinterpret_cast<__m256i*>(chunk_found + i * stride + chunk_count[i]), index);
        chunk_count[i] += std::popcount(mask);
      }
    };
#endif
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
#else
  for (int i = 0; i < k; ++i) {
    const Index self = cluster[i];
    const FluidRecord& own = in.record[self];
    Index* list = found + i * stride;
    count[i] = 0;
    for (int r = 0; r < range_count; ++r)
      for (Index b = ranges[r].begin; b < ranges[r].end; ++b) {
        const FluidRecord& other = in.record[b];
        const float dx = own.x - other.x, dy = own.y - other.y, dz = own.z - other.z;
        list[count[i]] = b;
        count[i] += (std::fma(dz, dz, std::fma(dy, dy, dx * dx)) < H2) & (b != self);
      }
  }
#endif
}

// The pair sums of particle a over its neighbours found[0, count). The terms are evaluated in
// single precision by one sequence of operations for every pair (x_ba = -x_ab and v_ba = -v_ab
// bitwise), so the term of (a, b) is exactly minus the term of (b, a); the force is summed in
// double (PairSums).
// `count` is a multiple of simd_width, padded with a itself, whose terms are exactly zero
// (x_aa = 0, v_aa = 0). The vector paths take 1 / r and 1 / (r^2 + (eta h)^2) from the
// hardware's estimates refined by a Newton step, where the scalar path divides and takes a square
// root; one build runs one path, so the pair (a, b) and the pair (b, a) always see the same
// operations. Within a path, the order of the double sums is fixed. uniform_mass: every particle
// has the mass in.uniform_mass, so that m_b and the products with m_a m_b are loop constants.
template <bool uniform_mass>
PairSums interact(const PairInputs& in, const PairConstants& c, Index a, const Index* found,
                  Index count) {
  const FluidRecord& own = in.record[a];
  const float xa = own.x, ya = own.y, za = own.z;
  const float vxa = own.vx, vya = own.vy, vza = own.vz;
  const float m_a = in.mass[a], inverse_rho_a = own.inverse_density, P_a = own.pressure_term;
  PairSums sums;
  Index s = 0;
#if defined(SPALL_SIMD_AVX512)
  // gradient_factor's constants.
  const float k18 = 18 * c.kernel, k12 = 12 * c.kernel, k6H = 6 * c.kernel / c.inverse_support;
  const auto splat = [](float v) { return _mm512_set1_ps(v); };
  const __m512 one = splat(1), half = splat(0.5f), tiny = splat(1e-30f), zero = _mm512_setzero_ps();
  // (The zero-masked estimates with every lane on: GCC 12 warns on the unmasked forms, simd.hpp.)
  constexpr __mmask16 all_lanes = 0xFFFF;
  // Lanes 0-7 of a term go to sum[0], lanes 8-15 to sum[1], each in 8 doubles.
  __m512d fp[3][2] = {}, fv[3][2] = {};
  __m512 rate = zero;  // the density rate needs no double sum (momentum does not depend on it)
  __m512 max_mu = zero;
  const auto accumulate = [](__m512d (&sum)[2], __m512 v) {
    sum[0] = _mm512_add_pd(sum[0], _mm512_cvtps_pd(_mm512_castps512_ps256(v)));
    sum[1] = _mm512_add_pd(sum[1], _mm512_cvtps_pd(_mm512_extractf32x8_ps(v, 1)));
  };
  const __m512i lanes_of_records = _mm512_loadu_si512(lane_order);
  for (; s < count; s += 16) {
    __m512 field[8];
    load_records(in.record, found + s, field);
    const __m512 dx = _mm512_sub_ps(splat(xa), field[0]);
    const __m512 dy = _mm512_sub_ps(splat(ya), field[1]);
    const __m512 dz = _mm512_sub_ps(splat(za), field[2]);
    const __m512 r2 = _mm512_max_ps(
        _mm512_fmadd_ps(dz, dz, _mm512_fmadd_ps(dy, dy, _mm512_mul_ps(dx, dx))), tiny);
    // 1 / r and 1 / (r^2 + (eta h)^2) from the 14-bit estimates and one Newton step each (to a
    // few single-precision ulp): multiplications on two ports, where a square root and a division
    // queued on the one port that does those (+4 % on the dam break's pass, docs/PERFORMANCE.md).
    const __m512 r2e = _mm512_add_ps(r2, splat(c.eta2));
    const __m512 y = _mm512_maskz_rsqrt14_ps(all_lanes, r2);  // y (3/2 - r^2/2 y^2)
    const __m512 inverse_r =
        _mm512_mul_ps(y, _mm512_fnmadd_ps(_mm512_mul_ps(half, r2), _mm512_mul_ps(y, y), splat(1.5f)));
    const __m512 z = _mm512_maskz_rcp14_ps(all_lanes, r2e);  // z + z (1 - r2e z)
    const __m512 inverse_r2e = _mm512_fmadd_ps(z, _mm512_fnmadd_ps(r2e, z, one), z);
    const __m512 q = _mm512_min_ps(_mm512_mul_ps(_mm512_mul_ps(r2, inverse_r), splat(c.inverse_support)), one);
    const __m512 near = _mm512_sub_ps(_mm512_mul_ps(splat(k18), q), splat(k12));
    const __m512 one_minus_q = _mm512_sub_ps(one, q);
    const __m512 far = _mm512_mul_ps(_mm512_mul_ps(splat(-k6H), _mm512_mul_ps(one_minus_q, one_minus_q)), inverse_r);
    const __m512 F = _mm512_mask_blend_ps(_mm512_cmp_ps_mask(q, half, _CMP_LE_OQ), far, near);
    const __m512 dvx = _mm512_sub_ps(splat(vxa), field[3]);
    const __m512 dvy = _mm512_sub_ps(splat(vya), field[4]);
    const __m512 dvz = _mm512_sub_ps(splat(vza), field[5]);
    const __m512 vr = _mm512_fmadd_ps(dvz, dz, _mm512_fmadd_ps(dvy, dy, _mm512_mul_ps(dvx, dx)));
    const __m512 m_b =
        uniform_mass
            ? splat(in.uniform_mass)
            : _mm512_i32gather_ps(_mm512_permutexvar_epi32(lanes_of_records, _mm512_loadu_si512(found + s)), in.mass, 4);
    rate = _mm512_fmadd_ps(_mm512_mul_ps(m_b, F), vr, rate);
    const __m512 mm = _mm512_mul_ps(splat(m_a), m_b);
    const __m512 inverse_rho_b = field[6];
    const __m512 radial =
        _mm512_mul_ps(_mm512_mul_ps(_mm512_sub_ps(zero, mm), _mm512_add_ps(splat(P_a), field[7])), F);
    const __m512 mu = _mm512_mul_ps(_mm512_mul_ps(splat(c.h), vr), inverse_r2e);
    const __mmask16 approaching = _mm512_cmp_ps_mask(vr, zero, _CMP_LT_OQ);
    const __m512 Pi = _mm512_maskz_mul_ps(
        approaching,
        _mm512_fmadd_ps(splat(c.beta), _mm512_mul_ps(mu, mu), _mm512_mul_ps(splat(-c.alpha_c), mu)),
        _mm512_mul_ps(half, _mm512_add_ps(splat(inverse_rho_a), inverse_rho_b)));
    max_mu = _mm512_mask_max_ps(max_mu, approaching, _mm512_sub_ps(zero, mu), max_mu);
    const __m512 viscous_radial = _mm512_mul_ps(_mm512_mul_ps(_mm512_sub_ps(zero, mm), Pi), F);
    const __m512 laminar = _mm512_mul_ps(
        _mm512_mul_ps(_mm512_mul_ps(mm, splat(c.two_mu)),
                      _mm512_mul_ps(splat(inverse_rho_a), inverse_rho_b)),
        _mm512_mul_ps(_mm512_mul_ps(F, r2), inverse_r2e));
    const __m512 d[3] = {dx, dy, dz}, dv[3] = {dvx, dvy, dvz};
    for (int i = 0; i < 3; ++i) {
      accumulate(fp[i], _mm512_mul_ps(radial, d[i]));
      accumulate(fv[i], _mm512_fmadd_ps(viscous_radial, d[i], _mm512_mul_ps(laminar, dv[i])));
    }
  }
  const auto total = [](const __m512d (&sum)[2]) {
    alignas(64) double lanes[8];
    _mm512_store_pd(lanes, _mm512_add_pd(sum[0], sum[1]));
    return ((lanes[0] + lanes[1]) + (lanes[2] + lanes[3])) + ((lanes[4] + lanes[5]) + (lanes[6] + lanes[7]));
  };
  {
    alignas(64) float lanes[16];
    _mm512_store_ps(lanes, rate);
    for (float lane : lanes) sums.rate += Real(lane);
  }
  sums.fvx = total(fv[0]), sums.fvy = total(fv[1]), sums.fvz = total(fv[2]);
  sums.fx = total(fp[0]) + sums.fvx, sums.fy = total(fp[1]) + sums.fvy, sums.fz = total(fp[2]) + sums.fvz;
  alignas(64) float lanes[16];
  _mm512_store_ps(lanes, max_mu);
  sums.max_mu = *std::max_element(lanes, lanes + 16);
#elif defined(__AVX2__)
  const auto splat = [](float v) { return _mm256_set1_ps(v); };
  const __m256 half = splat(0.5f), tiny = splat(1e-30f), zero = _mm256_setzero_ps();
  // The force in one 4-double sum per component, lanes i and i + 4 added first (twelve sums of
  // pressure and viscous parts apart spilled to the stack with sixteen registers); the viscous
  // part in floats.
  __m256d f[3] = {};
  __m256 fv[3] = {zero, zero, zero};
  __m256 rate = zero;  // the density rate needs no double sum (momentum does not depend on it)
  // The most negative mu of an approaching pair (0 if none): mu < 0 exactly where v_ab . x_ab < 0.
  __m256 min_mu = zero;
  // m_b, m_a m_b, -m_a m_b and m_a m_b (mu_a + mu_b) of every pair, when all masses are equal.
  const float mm_uniform = m_a * in.uniform_mass;
  const __m256 uniform_mb = splat(in.uniform_mass), uniform_mm = splat(mm_uniform),
               uniform_minus_mm = splat(-mm_uniform), uniform_mm_mu = splat(mm_uniform * c.two_mu);
  const auto accumulate = [](__m256d& sum, __m256 v) {
    sum = _mm256_add_pd(sum, _mm256_add_pd(_mm256_cvtps_pd(_mm256_castps256_ps128(v)),
                                           _mm256_cvtps_pd(_mm256_extractf128_ps(v, 1))));
  };
  for (; s < count; s += 8) {
    __m256 field[8];
    transpose_records([&](int i) { return _mm256_load_ps(&in.record[found[s + i]].x); }, field);
    const __m256 dx = _mm256_sub_ps(splat(xa), field[0]);
    const __m256 dy = _mm256_sub_ps(splat(ya), field[1]);
    const __m256 dz = _mm256_sub_ps(splat(za), field[2]);
    const __m256 r2 = _mm256_max_ps(
        _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx))), tiny);
    // 1 / r and 1 / (r^2 + (eta h)^2) from the 12-bit estimates and one Newton step each, as on
    // AVX-512.
    const __m256 r2e = _mm256_add_ps(r2, splat(c.eta2));
    const __m256 inverse_r = inverse_sqrt(r2);
    const __m256 inverse_r2e = inverse(r2e);
    const __m256 F = gradient_factor(r2, inverse_r, c);
    const __m256 dvx = _mm256_sub_ps(splat(vxa), field[3]);
    const __m256 dvy = _mm256_sub_ps(splat(vya), field[4]);
    const __m256 dvz = _mm256_sub_ps(splat(vza), field[5]);
    const __m256 vr = _mm256_fmadd_ps(dvz, dz, _mm256_fmadd_ps(dvy, dy, _mm256_mul_ps(dvx, dx)));
    const __m256 m_b =
        uniform_mass ? uniform_mb
                     : _mm256_i32gather_ps(in.mass, _mm256_loadu_si256(reinterpret_cast<const __m256i*>(found + s)), 4);
    rate = _mm256_fmadd_ps(_mm256_mul_ps(m_b, F), vr, rate);
    const __m256 mm = uniform_mass ? uniform_mm : _mm256_mul_ps(splat(m_a), m_b);
    const __m256 minus_mm = uniform_mass ? uniform_minus_mm : _mm256_sub_ps(zero, mm);
    const __m256 mm_mu = uniform_mass ? uniform_mm_mu : _mm256_mul_ps(mm, splat(c.two_mu));
    const __m256 inverse_rho_b = field[6];
    const __m256 radial = _mm256_mul_ps(_mm256_mul_ps(minus_mm, _mm256_add_ps(splat(P_a), field[7])), F);
    // mu of an approaching pair, else 0, which makes Pi exactly 0 (+0, as a blend would).
    const __m256 mu = _mm256_min_ps(_mm256_mul_ps(_mm256_mul_ps(splat(c.h), vr), inverse_r2e), zero);
    const __m256 Pi = _mm256_mul_ps(
        _mm256_fmadd_ps(splat(c.beta), _mm256_mul_ps(mu, mu), _mm256_mul_ps(splat(-c.alpha_c), mu)),
        _mm256_mul_ps(half, _mm256_add_ps(splat(inverse_rho_a), inverse_rho_b)));
    min_mu = _mm256_min_ps(min_mu, mu);
    const __m256 viscous_radial = _mm256_mul_ps(_mm256_mul_ps(minus_mm, Pi), F);
    const __m256 laminar = _mm256_mul_ps(_mm256_mul_ps(mm_mu, _mm256_mul_ps(splat(inverse_rho_a), inverse_rho_b)),
                                         _mm256_mul_ps(_mm256_mul_ps(F, r2), inverse_r2e));
    const __m256 both_radial = _mm256_add_ps(radial, viscous_radial);
    const __m256 d[3] = {dx, dy, dz}, dv[3] = {dvx, dvy, dvz};
    for (int i = 0; i < 3; ++i) {
      const __m256 along_dv = _mm256_mul_ps(laminar, dv[i]);
      accumulate(f[i], _mm256_fmadd_ps(both_radial, d[i], along_dv));
      fv[i] = _mm256_add_ps(fv[i], _mm256_fmadd_ps(viscous_radial, d[i], along_dv));
    }
  }
  const auto total = [](__m256d sum) {
    alignas(32) double lanes[4];
    _mm256_store_pd(lanes, sum);
    return (lanes[0] + lanes[1]) + (lanes[2] + lanes[3]);
  };
  const auto float_total = [](__m256 sum) {  // the lanes in order, added in double
    alignas(32) float lanes[8];
    _mm256_store_ps(lanes, sum);
    Real total = 0;
    for (float lane : lanes) total += Real(lane);
    return total;
  };
  sums.rate = float_total(rate);
  sums.fx = total(f[0]), sums.fy = total(f[1]), sums.fz = total(f[2]);
  sums.fvx = float_total(fv[0]), sums.fvy = float_total(fv[1]), sums.fvz = float_total(fv[2]);
  alignas(32) float lanes[8];
  _mm256_store_ps(lanes, min_mu);
  sums.max_mu = -*std::min_element(lanes, lanes + 8);
#endif
  for (; s < count; ++s) {
    const Index b = found[s];
    const FluidRecord& other = in.record[b];
    const float dx = xa - other.x, dy = ya - other.y, dz = za - other.z;
    const float r2 = std::max(std::fma(dz, dz, std::fma(dy, dy, dx * dx)), 1e-30f);
    const float r = std::sqrt(r2);
    const float r2e = r2 + c.eta2;
    const float inverse_product = 1.0f / (r * r2e);
    const float F = gradient_factor(r2, inverse_product * r2e, c);
    const float dvx = vxa - other.vx, dvy = vya - other.vy, dvz = vza - other.vz;
    const float vr = std::fma(dvz, dz, std::fma(dvy, dy, dvx * dx));
    const float m_b = in.mass[b];
    sums.rate += Real(m_b * F * vr);
    const float mm = m_a * m_b;
    const float inverse_rho_b = other.inverse_density;
    const float radial = (-mm * (P_a + other.pressure_term)) * F;
    const float inverse_r2e = inverse_product * r;
    const float mu = (c.h * vr) * inverse_r2e;
    const float Pi = vr < 0 ? std::fma(c.beta, mu * mu, -c.alpha_c * mu) * (0.5f * (inverse_rho_a + inverse_rho_b)) : 0.0f;
    if (vr < 0) sums.max_mu = std::max(sums.max_mu, -mu);
    const float viscous_radial = (-mm * Pi) * F;
    const float laminar = ((mm * c.two_mu) * (inverse_rho_a * inverse_rho_b)) * ((F * r2) * inverse_r2e);
    const float both_radial = radial + viscous_radial;
    sums.fx += Real(std::fma(both_radial, dx, laminar * dvx));
    sums.fy += Real(std::fma(both_radial, dy, laminar * dvy));
    sums.fz += Real(std::fma(both_radial, dz, laminar * dvz));
    sums.fvx += Real(std::fma(viscous_radial, dx, laminar * dvx));
    sums.fvy += Real(std::fma(viscous_radial, dy, laminar * dvy));
    sums.fvz += Real(std::fma(viscous_radial, dz, laminar * dvz));
  }
  return sums;
}

// The continuity rates of the walls w[0, count) (count <= wall_group) of one cell, from the moving
// particles of the runs `spans` (their block, cut to moving spans): rate_w = sum_b m_b F_wb
// v_wb . x_wb over the moving b with r_wb < H, each pair's term by the operations interact uses,
// into rates[0, count). Walls see only moving particles, as DualSPHysics' boundary particles see
// only the fluid: walls rest (their translations are held), so a term with another wall is
// exactly zero. The walls take lanes and each moving neighbour is broadcast to all of
// them, so that a cell's walls read the spans once where each screened them on its own, about
// half the walls' cost (docs/PERFORMANCE.md, session 19). A wall's sum runs in single precision
// in span order: the walls' density needs no exact cancellation.
template <typename Ranges>
void wall_rates(const PairInputs& in, const PairConstants& c, const Index* w, int count, const Ranges& spans,
                int span_count, Real* rates) {
#if defined(__AVX2__)
  alignas(32) float lanes[7][wall_group];
  for (int k = 0; k < wall_group; ++k) {  // lanes past count repeat the last wall
    const FluidRecord& own = in.record[w[std::min(k, count - 1)]];
    lanes[0][k] = own.x, lanes[1][k] = own.y, lanes[2][k] = own.z;
    lanes[3][k] = own.vx, lanes[4][k] = own.vy, lanes[5][k] = own.vz;
  }
  const auto splat = [](float v) { return _mm256_set1_ps(v); };
  const __m256 xa = _mm256_load_ps(lanes[0]), ya = _mm256_load_ps(lanes[1]), za = _mm256_load_ps(lanes[2]);
  const __m256 vxa = _mm256_load_ps(lanes[3]), vya = _mm256_load_ps(lanes[4]), vza = _mm256_load_ps(lanes[5]);
  const __m256 tiny = splat(1e-30f), H2 = splat(c.support_squared);
  __m256 rate = _mm256_setzero_ps();
  for (int r = 0; r < span_count; ++r) {
    const Index end = spans[r].end;
    for (Index first = spans[r].begin; first < end; first += 16) {
      unsigned moving = moving_lanes(in.moving, first, end);
      for (; moving != 0; moving &= moving - 1) {
        const Index b = first + std::countr_zero(moving);
        const FluidRecord& other = in.record[b];
        const __m256 dx = _mm256_sub_ps(xa, splat(other.x));
        const __m256 dy = _mm256_sub_ps(ya, splat(other.y));
        const __m256 dz = _mm256_sub_ps(za, splat(other.z));
        const __m256 r2_exact = _mm256_fmadd_ps(dz, dz, _mm256_fmadd_ps(dy, dy, _mm256_mul_ps(dx, dx)));
        const __m256 inside = _mm256_cmp_ps(r2_exact, H2, _CMP_LT_OQ);
        const __m256 r2 = _mm256_max_ps(r2_exact, tiny);
        const __m256 F = gradient_factor(r2, inverse_sqrt(r2), c);
        const __m256 dvx = _mm256_sub_ps(vxa, splat(other.vx));
        const __m256 dvy = _mm256_sub_ps(vya, splat(other.vy));
        const __m256 dvz = _mm256_sub_ps(vza, splat(other.vz));
        const __m256 vr = _mm256_fmadd_ps(dvz, dz, _mm256_fmadd_ps(dvy, dy, _mm256_mul_ps(dvx, dx)));
        const float m_b = in.uniform_mass > 0 ? in.uniform_mass : in.mass[b];
        rate = _mm256_add_ps(rate, _mm256_and_ps(inside, _mm256_mul_ps(_mm256_mul_ps(splat(m_b), F), vr)));
      }
    }
  }
  _mm256_store_ps(lanes[6], rate);
  for (int k = 0; k < count; ++k) rates[k] = Real(lanes[6][k]);
#else
  for (int k = 0; k < count; ++k) {
    const FluidRecord& own = in.record[w[k]];
    float rate = 0;
    for (int r = 0; r < span_count; ++r)
      for (Index b = spans[r].begin; b < spans[r].end; ++b) {
        if (!(moving_lanes(in.moving, b) & 1u)) continue;
        const FluidRecord& other = in.record[b];
        const float dx = own.x - other.x, dy = own.y - other.y, dz = own.z - other.z;
        const float r2_exact = std::fma(dz, dz, std::fma(dy, dy, dx * dx));
        if (!(r2_exact < c.support_squared)) continue;
        const float r2 = std::max(r2_exact, 1e-30f);
        const float r = std::sqrt(r2);
        const float F = gradient_factor(r2, (1.0f / (r * (r2 + c.eta2))) * (r2 + c.eta2), c);  // as interact
        const float vr = std::fma(own.vz - other.vz, dz, std::fma(own.vy - other.vy, dy, (own.vx - other.vx) * dx));
        rate += in.mass[b] * F * vr;
      }
    rates[k] = Real(rate);
  }
#endif
}

}  // namespace

void FluidFormulation::pair_pass(discretization::NodeStore& nodes, Real dt) {
  const auto& m = parameters_.material;
  const auto& av = parameters_.viscosity;
  const Real H = support_;
  const Real h = parameters_.smoothing_length;
  // grad_a W_ab = F(r) x_ab with F = (dW/dr) / r = k (18 q - 12) for q <= 1/2 and
  // -6 k (1 - q)^2 / q beyond, k = sigma / H^(d+2) (seed 000 eq. 3 differentiated).
  const Real k = parameters_.dimension == 2
                     ? kernels::CubicSpline<2>::normalisation() / (H * H * H * H)
                     : kernels::CubicSpline<3>::normalisation() / (H * H * H * H * H);
  const PairConstants constants{static_cast<float>(H * H),
                                static_cast<float>(1 / H),
                                static_cast<float>(k),
                                static_cast<float>(h),
                                static_cast<float>(av.eta * av.eta * h * h),
                                static_cast<float>(av.alpha * m.reference_sound_speed()),
                                static_cast<float>(av.beta),
                                static_cast<float>(2 * m.dynamic_viscosity)};
  const PairInputs in{record_.data(), mass_.data(), uniform_mass_, moving_.data()};
  Real max_acceleration = 0, max_mu = 0;

  parallel::region([&](const parallel::Team& team) {
    Real max_acceleration_here = 0, max_mu_here = 0;
    std::vector<Index> found;
    // rho^n = rho^{n-1} + dt rho'^n.
    const auto update_density = [&](Index a, Real rate) {
      density_[a] += dt * rate;
      previous_rate_[a] = first_pass_ ? static_cast<float>(rate) : rate_[a];
      rate_[a] = static_cast<float>(rate);
    };
    const auto moving_particle = [&](Index a, Index* neighbours, Index count) {
      while (count % simd_width != 0) neighbours[count++] = a;
      const PairSums sums = uniform_mass_ > 0 ? interact<true>(in, constants, a, neighbours, count)
                                              : interact<false>(in, constants, a, neighbours, count);
      const Vec3 f(sums.fx, sums.fy, sums.fz), fv(sums.fvx, sums.fvy, sums.fvz);
      nodes.f[node_[a]] += f;
      for (int d = 0; d < 3; ++d) {
        pressure_force_[3 * a + d] = static_cast<float>(f[d] - fv[d]);
        viscous_force_[3 * a + d] = static_cast<float>(fv[d]);
      }
      max_acceleration_here = std::max(max_acceleration_here, f.norm() / Real(mass_[a]));
      max_mu_here = std::max(max_mu_here, Real(sums.max_mu));
      update_density(a, sums.rate);
    };
    std::vector<Index> counts;
    const auto moving_cluster = [&](const Index* cluster, int k, const auto& ranges, int range_count) {
      Index candidates = 0;
      for (int r = 0; r < range_count; ++r) candidates += ranges[r].end - ranges[r].begin;
      const Index stride = candidates + 2 * simd_width;
      if (found.size() < static_cast<std::size_t>(stride) * k) found.resize(static_cast<std::size_t>(stride) * k);
      if (counts.size() < static_cast<std::size_t>(k)) counts.resize(k);
      screen_cluster(in, constants.support_squared, cluster, k, ranges, range_count, found.data(), stride, counts.data());
      for (int i = 0; i < k; ++i) moving_particle(cluster[i], found.data() + i * stride, counts[i]);
    };

    // Walls rest and feel no force; their density follows continuity and never goes below rho0.
    const auto walls = [&](const Index* w, int count, const auto& spans, int span_count) {
      Real rates[wall_group];
      wall_rates(in, constants, w, count, spans, span_count, rates);
      for (int k = 0; k < count; ++k) {
        const Index a = w[k];
        for (int d = 0; d < 3; ++d) pressure_force_[3 * a + d] = viscous_force_[3 * a + d] = 0;
        update_density(a, rates[k]);
        density_[a] = std::max(density_[a], m.density);
      }
    };
    for_each_particle_candidates<true>(team, moving_cluster, walls);
    team.one_at_a_time([&] {
      max_acceleration = std::max(max_acceleration, max_acceleration_here);
      max_mu = std::max(max_mu, max_mu_here);
    });
  });
  // Over every rank's particles (MPI): the step is global.
  double negated_maxima[2] = {-max_acceleration, -max_mu};
  parallel::world().minimum(negated_maxima);
  max_acceleration_ = -negated_maxima[0];
  max_mu_ = -negated_maxima[1];
  first_pass_ = false;
}

// The continuity state of the other ranks' particles: every rank's share in, in place.
void FluidFormulation::share_state(const discretization::NodeStore&) {
  share_(node_, density_, rate_, previous_rate_);
}

void FluidFormulation::compute_forces(discretization::NodeStore& nodes, Real dt) {
  // Every particle moved by dt v^{n-1/2} since the last call.
  const Index n = particle_count();
  const Real max_speed = parallel::reduce_exact(
      n, Real(0), [&](Index a) { return nodes.v[node_[a]].norm(); }, [](Real x, Real y) { return std::max(x, y); });
  max_speed_ = max_speed;
  travelled_ += dt * max_speed;
  share_.bind(nodes);
  // Two particles approach each other by at most twice the bound; the search also widens by the
  // rounding margin, and all of it must stay within the skin (see for_each_particle_candidates).
  if (!cells_built_ || 2 * travelled_ + rounding_margin_ > parameters_.skin * support_) rebuild_cells(nodes);
  gather(nodes, dt);
  pair_pass(nodes, dt);
}

Real FluidFormulation::stable_time_step(const discretization::NodeStore&) const {
  const Real h = parameters_.smoothing_length;
  // Monaghan 1992: the artificial viscosity adds the signal speed 1.2 (alpha c + beta max mu_ab).
  const auto& av = parameters_.viscosity;
  const Real viscous_signal = 1.2 * (av.alpha * max_sound_speed_ + av.beta * max_mu_);
  Real dt = courant_factor * h / (max_sound_speed_ + max_speed_ + viscous_signal);
  if (max_acceleration_ > 0) dt = std::min(dt, force_factor * std::sqrt(h / max_acceleration_));
  const auto& m = parameters_.material;
  if (m.dynamic_viscosity > 0)
    dt = std::min(dt, viscous_factor * h * h * m.density / m.dynamic_viscosity);
  return dt;
}

discretization::InternalPower FluidFormulation::internal_power(std::span<const Vec3> v) const {
  // Stored (compression) energy grows by -f_pressure . v; viscosity dissipates -f_viscous . v.
  // Exact sums over every rank's own particles: independent of threads, ranks and the particles' order.
  const Sums<2> sums = parallel::exact_sum(
      particle_count(),
      [&](Index a) {
        const Vec3& va = v[node_[a]];
        Sums<2> term;
        if (!owns(a)) return term;  // another rank's
        for (int d = 0; d < 3; ++d) {
          term[0] += Real(pressure_force_[3 * a + d]) * va[d];
          term[1] += Real(viscous_force_[3 * a + d]) * va[d];
        }
        return term;
      },
      &parallel::world());
  discretization::InternalPower p;
  p.stored = -sums[0];
  p.dissipated = -sums[1];
  return p;
}

std::vector<Index> FluidFormulation::neighbour_counts() const {
  std::vector<Index> counts(particle_count(), 0);
  if (!cells_built_) return counts;
  const float H2 = static_cast<float>(support_ * support_);
  const auto no_walls = [](const Index*, int, const auto&, int) {};  // pair_pass false: none
  parallel::region([&](const parallel::Team& team) {
    for_each_particle_candidates<false>(team, [&](Index a, const auto& ranges, int range_count) {
      Index count = 0;
      for (int r = 0; r < range_count; ++r)
        for (Index b = ranges[r].begin; b < ranges[r].end; ++b) {
          const float dx = record_[a].x - record_[b].x, dy = record_[a].y - record_[b].y,
                      dz = record_[a].z - record_[b].z;
          count += (dx * dx + dy * dy + dz * dz < H2) & (b != a);
        }
      counts[a] = count;
    }, no_walls);
  });
  return counts;
}

void FluidFormulation::book_energies(discretization::EnergyLedger& ledger, std::span<const Vec3> v, Real dt) const {
  discretization::book_internal_power(ledger, internal_power(v), dt);
}

void FluidFormulation::write_fields(discretization::FieldSet& fields, const discretization::NodeStore&) const {
  const auto pressure = fields.node_real("pressure"), density = fields.node_real("density"),
             smoothing = fields.node_real("smoothing_length");
  const auto neighbour_count = fields.node_integer("neighbour_count");
  const auto counts = neighbour_counts();
  for (Index a = 0; a < particle_count(); ++a) {
    const Index i = node_[a];
    pressure[i] = parameters_.material.pressure(density_[a]);
    density[i] = density_[a];
    smoothing[i] = parameters_.smoothing_length;
    neighbour_count[i] = counts[a];
  }
}

std::size_t FluidFormulation::memory_bytes() const {
  std::size_t total = bytes(node_) + bytes(mass_) + bytes(density_) + bytes(rate_) +
                      bytes(previous_rate_) + bytes(record_) + bytes(pressure_force_) +
                      bytes(viscous_force_) + bytes(moving_) + bytes(active_cell_);
  return total + cells_.memory_bytes();
}

Real FluidFormulation::max_wave_speed() const { return max_sound_speed_; }

// The particles in their cell order with their state, the cells as last built, and what decides
// the next rebuild.
void FluidFormulation::checkpoint(Archive& a) {
  a.section("sph fluid");
  a.expect_size("SPH fluid particles", node_.size());
  a(support_, node_, mass_, uniform_mass_, density_, rate_, previous_rate_, record_, pressure_force_, viscous_force_,
    moving_, cells_, active_cell_, origin_, rounding_margin_, cells_built_, first_pass_, travelled_, max_speed_,
    max_sound_speed_, max_acceleration_, max_mu_);
}

}  // namespace spall::sph
