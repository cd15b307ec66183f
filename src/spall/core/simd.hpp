#pragma once
// A pack of doubles processed as one (simd::Pack): the lanes of the neighbour search's distance
// tests and of the one-point hexahedra (fem/solid_elements.cpp, an element a lane). Eight lanes with AVX-512 (x86-64-v4, chosen
// by the build where the machine has it), four with AVX2 and FMA (x86-64-v3), otherwise four
// scalars with the same operations lane by lane, so that a loop is written once (the trimmed
// stencil's row reach takes the same pack). The solid's pair loops and the kernels' gradient
// factor run on eight floats (Float8: AVX2 where the build has it, else scalars), the fluid's on
// the widest float pack (FloatPack: sixteen lanes with AVX-512), each with a double accumulator
// for the sums that must cancel pair by pair (WideSum8, WideFloatSum). Every operation is lane-wise and exactly rounded (fused multiply-adds only where
// written; the vector packs' reciprocals are estimates refined to a few ulp), so a lane's result
// does not depend on its neighbours or on the thread count; the sums over lanes go in one fixed
// order (pairs of neighbouring lanes, then pairs of those, ...).
#include <cmath>
#include <cstdint>

#include "spall/core/types.hpp"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define SPALL_SIMD_AVX2 1
#endif
// The AVX-512 subsets of x86-64-v4 that the vector paths use: one definition of "the build
// targets AVX-512".
#if defined(SPALL_SIMD_AVX2) && defined(__AVX512F__) && defined(__AVX512BW__) && defined(__AVX512DQ__) && \
    defined(__AVX512VL__)
#define SPALL_SIMD_AVX512 1
#endif

namespace spall::simd {

// W scalars, lane by lane: the portable implementation, and the reference the vector ones are
// tested against (tests/unit/test_simd.cpp).
namespace lanes {

template <int W>
struct Mask {
  bool bit[W];
  // Bit i set when lane i is true.
  int lanes() const {
    int bits = 0;
    for (int i = 0; i < W; ++i) bits |= int(bit[i]) << i;
    return bits;
  }
};

template <int W, typename T = Real>
struct Pack {
  static constexpr int width = W;
  T v[W];
  Pack() : Pack(T(0)) {}
  Pack(T value) {
    for (T& x : v) x = value;
  }
  static Pack load(const T* p) { return from([&](int i) { return p[i]; }); }
  void store(T* p) const {
    for (int i = 0; i < W; ++i) p[i] = v[i];
  }
  template <int Stride>
  static Pack gather(const T* base, const Index* index, int offset = 0) {
    return from([&](int i) { return base[Stride * index[i] + offset]; });
  }
  template <typename F>
  static Pack from(F&& f) {
    Pack r;
    for (int i = 0; i < W; ++i) r.v[i] = f(i);
    return r;
  }
  friend Pack operator+(Pack a, Pack b) { return from([&](int i) { return a.v[i] + b.v[i]; }); }
  friend Pack operator-(Pack a, Pack b) { return from([&](int i) { return a.v[i] - b.v[i]; }); }
  friend Pack operator*(Pack a, Pack b) { return from([&](int i) { return a.v[i] * b.v[i]; }); }
  friend Pack operator/(Pack a, Pack b) { return from([&](int i) { return a.v[i] / b.v[i]; }); }
  friend Pack operator-(Pack a) { return from([&](int i) { return -a.v[i]; }); }
  Pack& operator+=(Pack b) { return *this = *this + b; }
  Pack& operator-=(Pack b) { return *this = *this - b; }
  Pack& operator*=(Pack b) { return *this = *this * b; }
  template <typename C>
  static Mask<W> compare(Pack a, Pack b, C&& c) {
    Mask<W> m;
    for (int i = 0; i < W; ++i) m.bit[i] = c(a.v[i], b.v[i]);
    return m;
  }
  friend Mask<W> operator<(Pack a, Pack b) { return compare(a, b, [](T x, T y) { return x < y; }); }
  friend Mask<W> operator<=(Pack a, Pack b) { return compare(a, b, [](T x, T y) { return x <= y; }); }
  friend Mask<W> operator>(Pack a, Pack b) { return compare(a, b, [](T x, T y) { return x > y; }); }
  friend Pack fma(Pack b, Pack c, Pack a) { return from([&](int i) { return std::fma(b.v[i], c.v[i], a.v[i]); }); }
  // 1 / sqrt(a) and 1 / a (a > 0): by a square root and a division here (an ulp or two); within
  // a few ulp in the AVX-512 pack and the AVX2 floats.
  friend Pack reciprocal_sqrt(Pack a) { return from([&](int i) { return 1 / std::sqrt(a.v[i]); }); }
  friend Pack reciprocal(Pack a) { return from([&](int i) { return 1 / a.v[i]; }); }
  friend Pack abs(Pack a) { return from([&](int i) { return std::abs(a.v[i]); }); }
  // As the x86 instructions: b where the lanes compare false (a NaN in either, or equal).
  friend Pack max(Pack a, Pack b) { return from([&](int i) { return a.v[i] > b.v[i] ? a.v[i] : b.v[i]; }); }
  friend Pack min(Pack a, Pack b) { return from([&](int i) { return a.v[i] < b.v[i] ? a.v[i] : b.v[i]; }); }
  friend Pack sqrt(Pack a) { return from([&](int i) { return std::sqrt(a.v[i]); }); }
  friend Pack floor(Pack a) { return from([&](int i) { return std::floor(a.v[i]); }); }
  friend Pack select(Mask<W> m, Pack a, Pack b) { return from([&](int i) { return m.bit[i] ? a.v[i] : b.v[i]; }); }
  // Writes the indices in[i] whose bit i is set in `lanes` to out[0..], in order.
  static void compress_indices(const Index* in, int lanes, Index* out) {
    for (int i = 0; i < W; ++i)
      if (lanes & (1 << i)) *out++ = in[i];
  }
  // Writes first + i for the lanes i whose bit is set in `lanes` to out[0..], in order.
  static void compress_consecutive(Index first, int lanes, Index* out) {
    for (int i = 0; i < W; ++i)
      if (lanes & (1 << i)) *out++ = first + i;
  }
  // out[i] = in[i] for i < count, else fill (0 <= count < W); reads in[0 .. count) only.
  static void padded_indices(const Index* in, int count, Index fill, Index* out) {
    for (int i = 0; i < W; ++i) out[i] = i < count ? in[i] : fill;
  }
  // Bit i set where in[i] > a.
  static int indices_above(const Index* in, Index a) {
    int lanes = 0;
    for (int i = 0; i < W; ++i) lanes |= int(in[i] > a) << i;
    return lanes;
  }
  // Neighbouring lanes in pairs, then the pairs in pairs, ...: ((l0 + l1) + (l2 + l3)) + ..., in
  // the lanes' precision.
  Real sum() const {
    T partial[W];
    for (int i = 0; i < W; ++i) partial[i] = v[i];
    for (int n = W; n > 1; n /= 2)
      for (int i = 0; i < n / 2; ++i) partial[i] = partial[2 * i] + partial[2 * i + 1];
    return partial[0];
  }
};

// N consecutive floats from each of W rows (base + Stride index[i] + offset), transposed: out[j]
// holds element j of the W rows.
template <int Stride, int N, int W>
inline void load_rows(const float* base, const Index* index, int offset, Pack<W, float> (&out)[N]) {
  for (int j = 0; j < N; ++j) out[j] = Pack<W, float>::template gather<Stride>(base, index, offset + j);
}

// The first N floats of W consecutive rows of Stride floats from `first_row`, transposed: out[j]
// holds element j of the W rows (the positions of a run of particle records).
template <int Stride, int N, int W>
inline void load_consecutive_rows(const float* first_row, Pack<W, float> (&out)[N]) {
  for (int j = 0; j < N; ++j) out[j] = Pack<W, float>::from([&](int i) { return first_row[Stride * i + j]; });
}

// W doubles that accumulate packs of floats, each lane widened exactly: the sums of
// single-precision pair terms that must cancel pair by pair to double round-off (momentum).
template <int W>
struct WideSum {
  Pack<W> lanes;
  void add(const Pack<W, float>& x) {
    for (int i = 0; i < W; ++i) lanes.v[i] += x.v[i];
  }
  Real sum() const { return lanes.sum(); }
};

// rows[4 index[i]..] -= (d[0][i], d[1][i], d[2][i], 0) in double for every lane i, in lane order
// (lanes may share a row): three packs scattered, transposed, into rows of four doubles.
template <int W>
inline void subtract_from_rows(const Pack<W, float> (&d)[3], const Index* index, double* rows) {
  for (int lane = 0; lane < W; ++lane) {
    double* row = rows + 4 * static_cast<std::size_t>(index[lane]);
    row[0] -= d[0].v[lane], row[1] -= d[1].v[lane], row[2] -= d[2].v[lane];
  }
}

}  // namespace lanes

#if defined(SPALL_SIMD_AVX2)
namespace avx2 {

// For each 4-bit lane mask, the permutation of four 32-bit lanes that moves the selected ones to
// the front in order (the rest unspecified).
struct CompressTable {
  alignas(16) std::int32_t lanes[16][4];
  constexpr CompressTable() : lanes{} {
    for (int mask = 0; mask < 16; ++mask) {
      int k = 0;
      for (int lane = 0; lane < 4; ++lane)
        if (mask & (1 << lane)) lanes[mask][k++] = lane;
      for (; k < 4; ++k) lanes[mask][k] = 0;
    }
  }
};
inline constexpr CompressTable compress_lanes;

struct Mask4 {
  __m256d bits;
  // Bit i set when lane i is true.
  int lanes() const { return _mm256_movemask_pd(bits); }
};

struct Real4 {
  static constexpr int width = 4;
  __m256d v;
  Real4() : v(_mm256_setzero_pd()) {}
  Real4(__m256d value) : v(value) {}
  Real4(Real value) : v(_mm256_set1_pd(value)) {}
  static Real4 load(const Real* p) { return {_mm256_loadu_pd(p)}; }
  void store(Real* p) const { _mm256_storeu_pd(p, v); }
  friend Real4 operator+(Real4 a, Real4 b) { return {_mm256_add_pd(a.v, b.v)}; }
  friend Real4 operator-(Real4 a, Real4 b) { return {_mm256_sub_pd(a.v, b.v)}; }
  friend Real4 operator*(Real4 a, Real4 b) { return {_mm256_mul_pd(a.v, b.v)}; }
  friend Real4 operator/(Real4 a, Real4 b) { return {_mm256_div_pd(a.v, b.v)}; }
  Real4& operator+=(Real4 b) { return *this = *this + b; }
  friend Real4 abs(Real4 a) { return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)}; }
  friend Mask4 operator<(Real4 a, Real4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
  // a + b c, rounded once.
  friend Real4 fma(Real4 b, Real4 c, Real4 a) { return {_mm256_fmadd_pd(b.v, c.v, a.v)}; }
  friend Real4 max(Real4 a, Real4 b) { return {_mm256_max_pd(a.v, b.v)}; }
  friend Real4 min(Real4 a, Real4 b) { return {_mm256_min_pd(a.v, b.v)}; }
  friend Real4 sqrt(Real4 a) { return {_mm256_sqrt_pd(a.v)}; }
  friend Real4 floor(Real4 a) { return {_mm256_floor_pd(a.v)}; }
  friend Real4 select(Mask4 m, Real4 a, Real4 b) { return {_mm256_blendv_pd(b.v, a.v, m.bits)}; }
  // base[stride * index[i] + offset] for i = 0..3.
  template <int Stride>
  static Real4 gather(const Real* base, const Index* index, int offset = 0) {
    __m128i i = _mm_loadu_si128(reinterpret_cast<const __m128i*>(index));
    if constexpr (Stride != 1) i = _mm_mullo_epi32(i, _mm_set1_epi32(Stride));
    // The masked form with every lane on and a zero source: GCC 12 warns that the plain one's
    // undefined source may be used uninitialized where it inlines (GCC bug 105593).
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    return {_mm256_mask_i32gather_pd(_mm256_setzero_pd(), base + offset, i, all, 8)};
  }
  // Writes the indices in[i] whose bit i is set in `lanes` to out[0..], in order; may write all
  // four.
  static void compress_indices(const Index* in, int lanes, Index* out);
};

inline void Real4::compress_indices(const Index* in, int lanes, Index* out) {
  const __m128i lane = _mm_load_si128(reinterpret_cast<const __m128i*>(compress_lanes.lanes[lanes]));
  const __m128 values = _mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in)));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_castps_si128(_mm_permutevar_ps(values, lane)));
}

// Eight floats processed as one (the solid's pair loops, sph/solid.cpp), every operation exactly
// rounded.
struct Mask8f {
  __m256 bits;
  // Bit i set when lane i is true.
  int lanes() const { return _mm256_movemask_ps(bits); }
};

// For each 8-bit lane mask, the numbers of the selected lanes in order, one byte each.
struct CompressTable8 {
  std::uint64_t order[256];
  constexpr CompressTable8() : order{} {
    for (int mask = 0; mask < 256; ++mask) {
      int k = 0;
      for (int lane = 0; lane < 8; ++lane)
        if (mask & (1 << lane)) order[mask] |= std::uint64_t(lane) << (8 * k++);
    }
  }
};
inline constexpr CompressTable8 compress_lanes8;

struct Float8 {
  static constexpr int width = 8;
  __m256 v;
  Float8() : v(_mm256_setzero_ps()) {}
  Float8(__m256 value) : v(value) {}
  Float8(float value) : v(_mm256_set1_ps(value)) {}
  static Float8 load(const float* p) { return {_mm256_loadu_ps(p)}; }
  void store(float* p) const { _mm256_storeu_ps(p, v); }
  // base[stride * index[i] + offset] for i = 0..7.
  template <int Stride>
  static Float8 gather(const float* base, const Index* index, int offset = 0) {
    __m256i i = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index));
    if constexpr (Stride != 1) i = _mm256_mullo_epi32(i, _mm256_set1_epi32(Stride));
    const __m256 all = _mm256_castsi256_ps(_mm256_set1_epi32(-1));
    return {_mm256_mask_i32gather_ps(_mm256_setzero_ps(), base + offset, i, all, 4)};
  }
  friend Float8 operator+(Float8 a, Float8 b) { return {_mm256_add_ps(a.v, b.v)}; }
  friend Float8 operator-(Float8 a, Float8 b) { return {_mm256_sub_ps(a.v, b.v)}; }
  friend Float8 operator*(Float8 a, Float8 b) { return {_mm256_mul_ps(a.v, b.v)}; }
  friend Float8 operator/(Float8 a, Float8 b) { return {_mm256_div_ps(a.v, b.v)}; }
  friend Float8 operator-(Float8 a) { return {_mm256_xor_ps(a.v, _mm256_set1_ps(-0.0f))}; }
  Float8& operator+=(Float8 b) { return *this = *this + b; }
  Float8& operator-=(Float8 b) { return *this = *this - b; }
  Float8& operator*=(Float8 b) { return *this = *this * b; }
  friend Mask8f operator<(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask8f operator<=(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_LE_OQ)}; }
  friend Mask8f operator>(Float8 a, Float8 b) { return {_mm256_cmp_ps(a.v, b.v, _CMP_GT_OQ)}; }
  // a + b c, rounded once.
  friend Float8 fma(Float8 b, Float8 c, Float8 a) { return {_mm256_fmadd_ps(b.v, c.v, a.v)}; }
  // 1 / sqrt(a) and 1 / a (a > 0) from the 12-bit estimates and one Newton step each, within a
  // few ulp: y (3/2 - a/2 y^2) and z + z (1 - a z). A square root and a division share one unit,
  // which the pair loops kept busy (docs/PERFORMANCE.md, sessions 17 and 20). The estimates are
  // the processor's own, so the last bits may differ between makers.
  friend Float8 reciprocal_sqrt(Float8 a) {
    const __m256 y = _mm256_rsqrt_ps(a.v);
    return {_mm256_mul_ps(y, _mm256_fnmadd_ps(_mm256_mul_ps(_mm256_set1_ps(0.5f), a.v), _mm256_mul_ps(y, y),
                                              _mm256_set1_ps(1.5f)))};
  }
  friend Float8 reciprocal(Float8 a) {
    const __m256 z = _mm256_rcp_ps(a.v);
    return {_mm256_fmadd_ps(z, _mm256_fnmadd_ps(a.v, z, _mm256_set1_ps(1)), z)};
  }
  friend Float8 abs(Float8 a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)}; }
  friend Float8 max(Float8 a, Float8 b) { return {_mm256_max_ps(a.v, b.v)}; }
  friend Float8 min(Float8 a, Float8 b) { return {_mm256_min_ps(a.v, b.v)}; }
  friend Float8 select(Mask8f m, Float8 a, Float8 b) { return {_mm256_blendv_ps(b.v, a.v, m.bits)}; }
  // Writes the indices in[i] whose bit i is set in `lanes` to out[0..], in order; writes all
  // eight.
  static void compress_indices(const Index* in, int lanes, Index* out) {
    const __m256i order = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(compress_lanes8.order[lanes])));
    const __m256i all = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_permutevar8x32_epi32(all, order));
  }
  // Writes first + i for the lanes i whose bit is set in `lanes` to out[0..], in order; writes all
  // eight. The lanes' numbers from the table, one byte each (a load where pdep, a multiplication
  // and pext made a chain of three).
  static void compress_consecutive(Index first, int lanes, Index* out) {
    const __m256i order = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(compress_lanes8.order[lanes])));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_add_epi32(_mm256_set1_epi32(first), order));
  }
  // out[i] = in[i] for i < count, else fill (0 <= count < 8); reads in[0 .. count) only (a
  // masked load, which does not fault past the end of an array).
  static void padded_indices(const Index* in, int count, Index fill, Index* out) {
    const __m256i present = _mm256_cmpgt_epi32(_mm256_set1_epi32(count), _mm256_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7));
    const __m256i values = _mm256_maskload_epi32(in, present);
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out),
                        _mm256_blendv_epi8(_mm256_set1_epi32(fill), values, present));
  }
  // Bit i set where in[i] > a.
  static int indices_above(const Index* in, Index a) {
    const __m256i above = _mm256_cmpgt_epi32(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(in)), _mm256_set1_epi32(a));
    return _mm256_movemask_ps(_mm256_castsi256_ps(above));
  }
  // ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)) in float, the order of lanes::Pack<8>::sum.
  Real sum() const {
    const __m256 pairs = _mm256_hadd_ps(v, v);       // l0 + l1, l2 + l3, ... | l4 + l5, l6 + l7, ...
    const __m256 quads = _mm256_hadd_ps(pairs, pairs);  // (l0 + l1) + (l2 + l3) | (l4 + l5) + (l6 + l7)
    return _mm_cvtss_f32(_mm_add_ss(_mm256_castps256_ps128(quads), _mm256_extractf128_ps(quads, 1)));
  }
};

// The lane sums of eight packs into out[0..7], out[i] = packs[i].sum() bit for bit: the same
// additions, with the packs transposed in a tree while they are added (neighbouring lanes of two
// packs by shuffles, then pairs of pairs, then the 128-bit halves), 15 shuffles and 7 additions
// where eight sum() take about 50 instructions.
inline void sum_lanes(const Float8 (&packs)[8], Real* out) {
  const auto pairs = [&](int i) {  // lanes 2k + 2k+1 of packs i, i + 1: (i: 0, 2, i+1: 0, 2 | i: 4, 6, i+1: 4, 6)
    const __m256 a = packs[i].v, b = packs[i + 1].v;
    return _mm256_add_ps(_mm256_shuffle_ps(a, b, _MM_SHUFFLE(2, 0, 2, 0)), _mm256_shuffle_ps(a, b, _MM_SHUFFLE(3, 1, 3, 1)));
  };
  const auto quads = [](__m256 x, __m256 y) {  // (l0..l3 of four packs | l4..l7 of the same four)
    return _mm256_add_ps(_mm256_shuffle_ps(x, y, _MM_SHUFFLE(2, 0, 2, 0)), _mm256_shuffle_ps(x, y, _MM_SHUFFLE(3, 1, 3, 1)));
  };
  const __m256 low = quads(pairs(0), pairs(2)), high = quads(pairs(4), pairs(6));
  const __m256 sums = _mm256_add_ps(_mm256_permute2f128_ps(low, high, 0x20), _mm256_permute2f128_ps(low, high, 0x31));
  _mm256_storeu_pd(out, _mm256_cvtps_pd(_mm256_castps256_ps128(sums)));
  _mm256_storeu_pd(out + 4, _mm256_cvtps_pd(_mm256_extractf128_ps(sums, 1)));
}

// Eight doubles that accumulate Float8s widened exactly (lanes::WideSum).
struct WideSum8 {
  __m256d low = _mm256_setzero_pd(), high = _mm256_setzero_pd();
  void add(Float8 x) {
    low = _mm256_add_pd(low, _mm256_cvtps_pd(_mm256_castps256_ps128(x.v)));
    high = _mm256_add_pd(high, _mm256_cvtps_pd(_mm256_extractf128_ps(x.v, 1)));
  }
  // ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)).
  Real sum() const {
    const __m256d pairs = _mm256_hadd_pd(low, high);  // (l0 + l1, l4 + l5, l2 + l3, l6 + l7)
    const __m128d quads = _mm_add_pd(_mm256_castpd256_pd128(pairs), _mm256_extractf128_pd(pairs, 1));
    return _mm_cvtsd_f64(_mm_add_sd(quads, _mm_unpackhi_pd(quads, quads)));
  }
};

// Row `index` of a table of rows of Stride floats. An index is never negative: taken as unsigned
// it is scaled without a sign extension first, one instruction less at each of the two hundred
// row loads that a particle-step of the SPH solid makes.
template <int Stride>
[[gnu::always_inline]] inline const float* row_of(const float* base, Index index) {
  return base + static_cast<std::size_t>(static_cast<std::uint32_t>(index)) * Stride;
}

// Two consecutive floats from each of eight rows (base + Stride index[i] + offset), transposed:
// out[0] holds element 0 of the eight rows, out[1] element 1. Eight 64-bit loads and four
// shuffles, where two gathers of eight floats (a gather costs a load per lane and more) took an
// eighth of the rates pass (docs/PERFORMANCE.md, session 25).
template <int Stride>
[[gnu::always_inline]] inline void load_rows(const float* base, const Index* index, int offset, Float8 (&out)[2]) {
  const auto pair = [&](int i, int j) {  // (element 0, 1 of row i, element 0, 1 of row j)
    const __m128i low = _mm_loadl_epi64(reinterpret_cast<const __m128i*>(row_of<Stride>(base, index[i]) + offset));
    return _mm_loadh_pi(_mm_castsi128_ps(low), reinterpret_cast<const __m64*>(row_of<Stride>(base, index[j]) + offset));
  };
  const __m256 rows0145 = _mm256_insertf128_ps(_mm256_castps128_ps256(pair(0, 1)), pair(4, 5), 1);
  const __m256 rows2367 = _mm256_insertf128_ps(_mm256_castps128_ps256(pair(2, 3)), pair(6, 7), 1);
  out[0] = {_mm256_shuffle_ps(rows0145, rows2367, _MM_SHUFFLE(2, 0, 2, 0))};
  out[1] = {_mm256_shuffle_ps(rows0145, rows2367, _MM_SHUFFLE(3, 1, 3, 1))};
}

// Four consecutive floats from each of eight rows (base + Stride index[i] + offset), transposed:
// out[j] holds element j of the eight rows. Rows i and i + 4 share a register, then a 4 x 4
// transpose within each 128-bit half: eight loads and twelve shuffles.
template <int Stride>
[[gnu::always_inline]] inline void load_rows(const float* base, const Index* index, int offset, Float8 (&out)[4]) {
  const auto pair = [&](int i) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(row_of<Stride>(base, index[i]) + offset)),
                                _mm_loadu_ps(row_of<Stride>(base, index[i + 4]) + offset), 1);
  };
  const __m256 r04 = pair(0), r15 = pair(1), r26 = pair(2), r37 = pair(3);
  const __m256 t0 = _mm256_unpacklo_ps(r04, r15), t1 = _mm256_unpackhi_ps(r04, r15);
  const __m256 t2 = _mm256_unpacklo_ps(r26, r37), t3 = _mm256_unpackhi_ps(r26, r37);
  out[0] = {_mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0))};
  out[1] = {_mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2))};
  out[2] = {_mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0))};
  out[3] = {_mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2))};
}

// Eight consecutive floats from each of eight rows, transposed: a 4 x 4 transpose within each
// 128-bit half of rows 0-3 and of rows 4-7, then the halves exchanged: eight loads and 24 shuffles.
template <int Stride>
[[gnu::always_inline]] inline void load_rows(const float* base, const Index* index, int offset, Float8 (&out)[8]) {
  __m256 s[8];  // s[k], k < 4: element k of rows 0-3 in the low half, element k + 4 in the high
  for (int g = 0; g < 2; ++g) {
    const auto row = [&](int i) { return _mm256_loadu_ps(row_of<Stride>(base, index[4 * g + i]) + offset); };
    const __m256 r0 = row(0), r1 = row(1), r2 = row(2), r3 = row(3);
    const __m256 t0 = _mm256_unpacklo_ps(r0, r1), t1 = _mm256_unpackhi_ps(r0, r1);
    const __m256 t2 = _mm256_unpacklo_ps(r2, r3), t3 = _mm256_unpackhi_ps(r2, r3);
    s[4 * g + 0] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    s[4 * g + 1] = _mm256_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    s[4 * g + 2] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
    s[4 * g + 3] = _mm256_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  }
  for (int k = 0; k < 4; ++k) {
    out[k] = {_mm256_permute2f128_ps(s[k], s[k + 4], 0x20)};
    out[k + 4] = {_mm256_permute2f128_ps(s[k], s[k + 4], 0x31)};
  }
}

// The first three floats of eight consecutive rows of eight (the positions of eight particle
// records), lane i from row i: the first halves of rows i and i + 4 in one register (four loads
// and inserts), then the 4 x 4 transpose within the 128-bit lanes, seven shuffles where the whole
// 8 x 8 one takes seventeen.
template <int Stride, int N>
[[gnu::always_inline]] inline void load_consecutive_rows(const float* first_row, Float8 (&out)[N]) {
  static_assert(Stride == 8 && N == 3, "the records' positions only");
  const auto rows = [&](int i) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_load_ps(first_row + 8 * i)),
                                _mm_load_ps(first_row + 8 * (i + 4)), 1);
  };
  const __m256 r0 = rows(0), r1 = rows(1), r2 = rows(2), r3 = rows(3);
  const __m256 xy01 = _mm256_unpacklo_ps(r0, r1), xy23 = _mm256_unpacklo_ps(r2, r3);
  const __m256 zw01 = _mm256_unpackhi_ps(r0, r1), zw23 = _mm256_unpackhi_ps(r2, r3);
  out[0] = {_mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(1, 0, 1, 0))};
  out[1] = {_mm256_shuffle_ps(xy01, xy23, _MM_SHUFFLE(3, 2, 3, 2))};
  out[2] = {_mm256_shuffle_ps(zw01, zw23, _MM_SHUFFLE(1, 0, 1, 0))};
}

// The same as lanes::subtract_from_rows: the three packs transposed into the lanes' rows of four
// floats, each widened and subtracted from its row at once; about a third of the instructions of
// 24 scalar read-modify-writes (docs/PERFORMANCE.md).
[[gnu::always_inline]] inline void subtract_from_rows(const Float8 (&d)[3], const Index* index, double* rows) {
  const __m256 zero = _mm256_setzero_ps();
  const __m256 xy_0145 = _mm256_unpacklo_ps(d[0].v, d[1].v), xy_2367 = _mm256_unpackhi_ps(d[0].v, d[1].v);
  const __m256 z_0145 = _mm256_unpacklo_ps(d[2].v, zero), z_2367 = _mm256_unpackhi_ps(d[2].v, zero);
  // Lane i's row (x, y, z, 0) in the low half of rows_of[i % 4], lane i + 4's in the high half.
  const __m256 rows_of[4] = {_mm256_shuffle_ps(xy_0145, z_0145, _MM_SHUFFLE(1, 0, 1, 0)),
                             _mm256_shuffle_ps(xy_0145, z_0145, _MM_SHUFFLE(3, 2, 3, 2)),
                             _mm256_shuffle_ps(xy_2367, z_2367, _MM_SHUFFLE(1, 0, 1, 0)),
                             _mm256_shuffle_ps(xy_2367, z_2367, _MM_SHUFFLE(3, 2, 3, 2))};
  for (int lane = 0; lane < 8; ++lane) {
    const __m128 row = lane < 4 ? _mm256_castps256_ps128(rows_of[lane]) : _mm256_extractf128_ps(rows_of[lane - 4], 1);
    // The index taken as unsigned: scaled without a sign extension first (row_of).
    double* f = rows + 4 * static_cast<std::size_t>(static_cast<std::uint32_t>(index[lane]));
    _mm256_storeu_pd(f, _mm256_sub_pd(_mm256_loadu_pd(f), _mm256_cvtps_pd(row)));
  }
}

}  // namespace avx2
#endif

#if defined(SPALL_SIMD_AVX512)
namespace avx512 {

struct Mask8 {
  __mmask8 bits;
  // Bit i set when lane i is true.
  int lanes() const { return bits; }
};

struct Real8 {
  static constexpr int width = 8;
  __m512d v;
  Real8() : v(_mm512_setzero_pd()) {}
  Real8(__m512d value) : v(value) {}
  Real8(Real value) : v(_mm512_set1_pd(value)) {}
  static Real8 load(const Real* p) { return {_mm512_loadu_pd(p)}; }
  void store(Real* p) const { _mm512_storeu_pd(p, v); }
  friend Real8 operator+(Real8 a, Real8 b) { return {_mm512_add_pd(a.v, b.v)}; }
  friend Real8 operator-(Real8 a, Real8 b) { return {_mm512_sub_pd(a.v, b.v)}; }
  friend Real8 operator*(Real8 a, Real8 b) { return {_mm512_mul_pd(a.v, b.v)}; }
  friend Real8 operator/(Real8 a, Real8 b) { return {_mm512_div_pd(a.v, b.v)}; }
  Real8& operator+=(Real8 b) { return *this = *this + b; }
  friend Real8 abs(Real8 a) { return {_mm512_abs_pd(a.v)}; }
  friend Mask8 operator<(Real8 a, Real8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LT_OQ)}; }
  // a + b c, rounded once.
  friend Real8 fma(Real8 b, Real8 c, Real8 a) { return {_mm512_fmadd_pd(b.v, c.v, a.v)}; }
  // The zero-masked forms of max, min and gather: GCC 12 warns that the plain ones' undefined
  // pass-through operand is used uninitialized where they inline (GCC bug 105593); same instructions.
  friend Real8 max(Real8 a, Real8 b) { return {_mm512_maskz_max_pd(0xFF, a.v, b.v)}; }
  friend Real8 min(Real8 a, Real8 b) { return {_mm512_maskz_min_pd(0xFF, a.v, b.v)}; }
  friend Real8 sqrt(Real8 a) { return {_mm512_sqrt_pd(a.v)}; }
  friend Real8 floor(Real8 a) { return {_mm512_floor_pd(a.v)}; }
  friend Real8 select(Mask8 m, Real8 a, Real8 b) { return {_mm512_mask_blend_pd(m.bits, b.v, a.v)}; }
  // base[stride * index[i] + offset] for i = 0..7.
  template <int Stride>
  static Real8 gather(const Real* base, const Index* index, int offset = 0) {
    __m256i i = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index));
    if constexpr (Stride != 1) i = _mm256_mullo_epi32(i, _mm256_set1_epi32(Stride));
    return {_mm512_mask_i32gather_pd(_mm512_setzero_pd(), 0xFF, i, base + offset, 8)};
  }
  // Writes the indices in[i] whose bit i is set in `lanes` to out[0..], in order; writes all
  // eight. Compressed in a register and stored whole: a compressing store to memory is several
  // times slower on the processors measured (docs/PERFORMANCE.md).
  static void compress_indices(const Index* in, int lanes, Index* out) {
    const __m256i all = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_maskz_compress_epi32(static_cast<__mmask8>(lanes), all));
  }
};

// Sixteen floats processed as one (the SPH fluid's pair loops), every operation exactly rounded,
// the reciprocals estimates refined by a Newton step (as Float8's).
struct Mask16 {
  __mmask16 bits;
  // Bit i set when lane i is true.
  int lanes() const { return bits; }
};

struct Float16 {
  static constexpr int width = 16;
  __m512 v;
  Float16() : v(_mm512_setzero_ps()) {}
  Float16(__m512 value) : v(value) {}
  Float16(float value) : v(_mm512_set1_ps(value)) {}
  static Float16 load(const float* p) { return {_mm512_loadu_ps(p)}; }
  void store(float* p) const { _mm512_storeu_ps(p, v); }
  // base[stride * index[i] + offset] for i = 0..15.
  template <int Stride>
  static Float16 gather(const float* base, const Index* index, int offset = 0) {
    __m512i i = _mm512_loadu_si512(index);
    if constexpr (Stride != 1) i = _mm512_mullo_epi32(i, _mm512_set1_epi32(Stride));
    return {_mm512_i32gather_ps(i, base + offset, 4)};
  }
  friend Float16 operator+(Float16 a, Float16 b) { return {_mm512_add_ps(a.v, b.v)}; }
  friend Float16 operator-(Float16 a, Float16 b) { return {_mm512_sub_ps(a.v, b.v)}; }
  friend Float16 operator*(Float16 a, Float16 b) { return {_mm512_mul_ps(a.v, b.v)}; }
  friend Float16 operator/(Float16 a, Float16 b) { return {_mm512_div_ps(a.v, b.v)}; }
  friend Float16 operator-(Float16 a) {
    return {_mm512_castsi512_ps(_mm512_xor_si512(_mm512_castps_si512(a.v), _mm512_set1_epi32(INT32_MIN)))};
  }
  Float16& operator+=(Float16 b) { return *this = *this + b; }
  Float16& operator-=(Float16 b) { return *this = *this - b; }
  Float16& operator*=(Float16 b) { return *this = *this * b; }
  friend Mask16 operator<(Float16 a, Float16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask16 operator<=(Float16 a, Float16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_LE_OQ)}; }
  friend Mask16 operator>(Float16 a, Float16 b) { return {_mm512_cmp_ps_mask(a.v, b.v, _CMP_GT_OQ)}; }
  // a + b c, rounded once.
  friend Float16 fma(Float16 b, Float16 c, Float16 a) { return {_mm512_fmadd_ps(b.v, c.v, a.v)}; }
  // 1 / sqrt(a) and 1 / a (a > 0) from the 14-bit estimates and one Newton step each (Float8's
  // steps). The zero-masked estimates with every lane on: GCC 12 warns on the unmasked forms.
  friend Float16 reciprocal_sqrt(Float16 a) {
    const __m512 y = _mm512_maskz_rsqrt14_ps(0xFFFF, a.v);
    return {_mm512_mul_ps(y, _mm512_fnmadd_ps(_mm512_mul_ps(_mm512_set1_ps(0.5f), a.v), _mm512_mul_ps(y, y),
                                              _mm512_set1_ps(1.5f)))};
  }
  friend Float16 reciprocal(Float16 a) {
    const __m512 z = _mm512_maskz_rcp14_ps(0xFFFF, a.v);
    return {_mm512_fmadd_ps(z, _mm512_fnmadd_ps(a.v, z, _mm512_set1_ps(1)), z)};
  }
  friend Float16 abs(Float16 a) { return {_mm512_abs_ps(a.v)}; }
  friend Float16 max(Float16 a, Float16 b) { return {_mm512_max_ps(a.v, b.v)}; }
  friend Float16 min(Float16 a, Float16 b) { return {_mm512_min_ps(a.v, b.v)}; }
  friend Float16 select(Mask16 m, Float16 a, Float16 b) { return {_mm512_mask_blend_ps(m.bits, b.v, a.v)}; }
  // Writes first + i for the lanes i whose bit is set in `lanes` to out[0..], in order; writes all
  // sixteen. Left-packed in a register and stored whole: the compressing store to memory is no
  // faster on Intel cores and microcoded, far slower, on AMD Zen 4.
  static void compress_consecutive(Index first, int lanes, Index* out) {
    const __m512i index = _mm512_add_epi32(_mm512_set1_epi32(first),
                                           _mm512_setr_epi32(0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15));
    _mm512_storeu_si512(out, _mm512_maskz_compress_epi32(static_cast<__mmask16>(lanes), index));
  }
  // The lanes in pairs of neighbours, then the pairs in pairs, ... (lanes::Pack<16, float>::sum).
  Real sum() const {
    alignas(64) float lanes[16];
    _mm512_store_ps(lanes, v);
    for (int n = 16; n > 1; n /= 2)
      for (int i = 0; i < n / 2; ++i) lanes[i] = lanes[2 * i] + lanes[2 * i + 1];
    return lanes[0];
  }
};

// Sixteen doubles that accumulate Float16s widened exactly (lanes::WideSum).
struct WideSum16 {
  __m512d low = _mm512_setzero_pd(), high = _mm512_setzero_pd();
  void add(Float16 x) {
    low = _mm512_add_pd(low, _mm512_cvtps_pd(_mm512_castps512_ps256(x.v)));
    high = _mm512_add_pd(high, _mm512_cvtps_pd(_mm512_extractf32x8_ps(x.v, 1)));
  }
  // The lanes in pairs of neighbours, then the pairs in pairs, ... (lanes::WideSum<16>::sum).
  Real sum() const {
    alignas(64) double lanes[16];
    _mm512_store_pd(lanes, low);
    _mm512_store_pd(lanes + 8, high);
    for (int n = 16; n > 1; n /= 2)
      for (int i = 0; i < n / 2; ++i) lanes[i] = lanes[2 * i] + lanes[2 * i + 1];
    return lanes[0];
  }
};

// Eight consecutive floats from each of sixteen rows (base + Stride index[i] + offset), transposed:
// out[j] holds element j of the sixteen rows. Two rows a register (i and i + 4 of each group of
// eight, one per 256-bit half), the 4 x 4 transposes within the 128-bit lanes, then the lanes
// exchanged: sixteen loads and 32 shuffles where eight gathers would take about 28 cycles each
// on the hosts measured (docs/PERFORMANCE.md).
template <int Stride>
[[gnu::always_inline]] inline void load_rows(const float* base, const Index* index, int offset, Float16 (&out)[8]) {
  const auto row = [&](int i) { return base + static_cast<std::size_t>(static_cast<std::uint32_t>(index[i])) * Stride + offset; };
  // Register i < 4: rows i (low half) and i + 4 (high half); register i >= 4: rows i + 4 and i + 8.
  const auto rows = [&](int i) {
    const int first = i < 4 ? i : i + 4;
    return _mm512_insertf32x8(_mm512_castps256_ps512(_mm256_loadu_ps(row(first))), _mm256_loadu_ps(row(first + 4)), 1);
  };
  // s[k] (k < 4): element k of rows 0-3 in 128-bit lane 0, element k + 4 in lane 1, the same of
  // rows 4-7 in lanes 2 and 3; s[k + 4] the same of rows 8-11 and 12-15.
  __m512 s[8];
  for (int g = 0; g < 2; ++g) {
    const __m512 r0 = rows(4 * g), r1 = rows(4 * g + 1), r2 = rows(4 * g + 2), r3 = rows(4 * g + 3);
    const __m512 t0 = _mm512_unpacklo_ps(r0, r1), t1 = _mm512_unpackhi_ps(r0, r1);
    const __m512 t2 = _mm512_unpacklo_ps(r2, r3), t3 = _mm512_unpackhi_ps(r2, r3);
    s[4 * g + 0] = _mm512_shuffle_ps(t0, t2, _MM_SHUFFLE(1, 0, 1, 0));
    s[4 * g + 1] = _mm512_shuffle_ps(t0, t2, _MM_SHUFFLE(3, 2, 3, 2));
    s[4 * g + 2] = _mm512_shuffle_ps(t1, t3, _MM_SHUFFLE(1, 0, 1, 0));
    s[4 * g + 3] = _mm512_shuffle_ps(t1, t3, _MM_SHUFFLE(3, 2, 3, 2));
  }
  for (int k = 0; k < 4; ++k) {
    out[k] = {_mm512_shuffle_f32x4(s[k], s[k + 4], _MM_SHUFFLE(2, 0, 2, 0))};
    out[k + 4] = {_mm512_shuffle_f32x4(s[k], s[k + 4], _MM_SHUFFLE(3, 1, 3, 1))};
  }
}

// The first three floats of sixteen consecutive rows of eight (the positions of sixteen particle
// records), lane i from row i: eight loads and eleven two-source permutes (the three elements of
// four rows per register, then of eight, then of sixteen).
template <int Stride, int N>
[[gnu::always_inline]] inline void load_consecutive_rows(const float* first_row, Float16 (&out)[N]) {
  static_assert(Stride == 8 && N == 3, "the records' positions only");
  // Rows 4j .. 4j + 3: the elements in lanes 0-3, 4-7 and 8-11 (lanes 12-15 are not used).
  const __m512i of_four = _mm512_setr_epi32(0, 8, 16, 24, 1, 9, 17, 25, 2, 10, 18, 26, 0, 8, 16, 24);
  __m512 four[4];
  for (int j = 0; j < 4; ++j)
    four[j] = _mm512_permutex2var_ps(_mm512_loadu_ps(first_row + 32 * j), of_four,
                                     _mm512_loadu_ps(first_row + 32 * j + 16));
  // Of eight rows: the first two elements in lanes 0-7 and 8-15, and the third in lanes 0-7.
  const __m512i two_of_eight = _mm512_setr_epi32(0, 1, 2, 3, 16, 17, 18, 19, 4, 5, 6, 7, 20, 21, 22, 23);
  const __m512i third_of_eight = _mm512_setr_epi32(8, 9, 10, 11, 24, 25, 26, 27, 8, 9, 10, 11, 24, 25, 26, 27);
  const __m512 low = _mm512_permutex2var_ps(four[0], two_of_eight, four[1]);
  const __m512 high = _mm512_permutex2var_ps(four[2], two_of_eight, four[3]);
  const __m512 third_low = _mm512_permutex2var_ps(four[0], third_of_eight, four[1]);
  const __m512 third_high = _mm512_permutex2var_ps(four[2], third_of_eight, four[3]);
  out[0] = {_mm512_shuffle_f32x4(low, high, _MM_SHUFFLE(1, 0, 1, 0))};
  out[1] = {_mm512_shuffle_f32x4(low, high, _MM_SHUFFLE(3, 2, 3, 2))};
  out[2] = {_mm512_shuffle_f32x4(third_low, third_high, _MM_SHUFFLE(1, 0, 1, 0))};
}

}  // namespace avx512
#endif

// The widest single-precision pack the build targets and its double accumulator: the SPH fluid's
// pair loops (sixteen lanes with AVX-512, else eight).
#if defined(SPALL_SIMD_AVX512)
using FloatPack = avx512::Float16;
using WideFloatSum = avx512::WideSum16;
#elif defined(SPALL_SIMD_AVX2)
using FloatPack = avx2::Float8;
using WideFloatSum = avx2::WideSum8;
#else
using FloatPack = lanes::Pack<8, float>;
using WideFloatSum = lanes::WideSum<8>;
#endif

// The double pack of the neighbour search (neighbors/verlet_list.cpp): the widest the build targets.
#if defined(SPALL_SIMD_AVX512)
using Pack = avx512::Real8;
using PackMask = avx512::Mask8;
#elif defined(SPALL_SIMD_AVX2)
using Pack = avx2::Real4;
using PackMask = avx2::Mask4;
#else
using Pack = lanes::Pack<4>;
using PackMask = lanes::Mask<4>;
#endif

// Eight single-precision lanes, the solid's pair loops (sph/solid.cpp), with their double
// accumulator and transposed row loads: AVX2 where the build has it (also with AVX-512).
#if defined(SPALL_SIMD_AVX2)
using Float8 = avx2::Float8;
using WideSum8 = avx2::WideSum8;
using avx2::load_rows;
using avx2::subtract_from_rows;
using avx2::sum_lanes;
#else
using Float8 = lanes::Pack<8, float>;
using WideSum8 = lanes::WideSum<8>;
using lanes::load_rows;
using lanes::subtract_from_rows;
#endif

// The lane sums of eight packs into out[0..7], out[i] = packs[i].sum() bit for bit (the same
// additions in the same pairs).
template <typename P>
inline void sum_lanes(const P (&packs)[8], Real* out) {
  for (int i = 0; i < 8; ++i) out[i] = packs[i].sum();
}

// The scalar forms, so that a kernel written with select/max serves both Real and a Pack.
inline Real select(bool m, Real a, Real b) { return m ? a : b; }
using std::max;

}  // namespace spall::simd
