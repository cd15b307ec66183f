#pragma once
// A pack of doubles processed as one: the lanes of the SPH pair loops, which take a particle's
// neighbours a pack at a time. Eight lanes with AVX-512 (x86-64-v4, chosen by the build where the
// machine has it), four with AVX2 and FMA (x86-64-v3), otherwise four scalars with the same
// operations lane by lane, so that the pair loops are written once over simd::Pack. Every
// operation is lane-wise and exactly rounded (fused multiply-adds only where written), so a lane's
// result does not depend on its neighbours or on the thread count; the sums over lanes go in one
// fixed order (pairs of neighbouring lanes, then pairs of those, ...). The solid's pair loops run
// on eight floats instead (Float8: AVX2 where the build has it, else scalars), with a double
// accumulator for the sums that must cancel pair by pair (WideSum8).
#include <cmath>
#include <cstdint>

#include "spall/core/types.hpp"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define SPALL_SIMD_AVX2 1
#endif
// The AVX-512 subsets of x86-64-v4 that the vector paths use (here, in the fluid's pair pass and
// in the trimmed stencil): one definition of "the build targets AVX-512".
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
  friend Mask operator&(Mask a, Mask b) {
    Mask m;
    for (int i = 0; i < W; ++i) m.bit[i] = a.bit[i] && b.bit[i];
    return m;
  }
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
  // a few ulp in the AVX-512 pack.
  friend Pack reciprocal_sqrt(Pack a) { return from([&](int i) { return 1 / std::sqrt(a.v[i]); }); }
  friend Pack reciprocal(Pack a) { return from([&](int i) { return 1 / a.v[i]; }); }
  friend Pack abs(Pack a) { return from([&](int i) { return std::abs(a.v[i]); }); }
  friend Pack max(Pack a, Pack b) { return from([&](int i) { return a.v[i] < b.v[i] ? b.v[i] : a.v[i]; }); }
  friend Pack select(Mask<W> m, Pack a, Pack b) { return from([&](int i) { return m.bit[i] ? a.v[i] : b.v[i]; }); }
  // Writes the indices in[i] whose bit i is set in `lanes` to out[0..], in order.
  static void compress_indices(const Index* in, int lanes, Index* out) {
    for (int i = 0; i < W; ++i)
      if (lanes & (1 << i)) *out++ = in[i];
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

// Four consecutive doubles from each of W rows (base + Stride index[i] + offset), transposed:
// out[j] holds element j of the W rows.
template <int Stride, int W>
inline void load_transposed(const Real* base, const Index* index, int offset, Pack<W> (&out)[4]) {
  for (int j = 0; j < 4; ++j) out[j] = Pack<W>::template gather<Stride>(base, index, offset + j);
}

// The three components of the vectors v[index[i]] of an array of 3-vectors (x, y, z, x, ...).
template <int W>
inline void load_vectors(const Real* v, const Index* index, Pack<W>& x, Pack<W>& y, Pack<W>& z) {
  x = Pack<W>::template gather<3>(v, index, 0);
  y = Pack<W>::template gather<3>(v, index, 1);
  z = Pack<W>::template gather<3>(v, index, 2);
}

// N consecutive floats from each of W rows (base + Stride index[i] + offset), transposed: out[j]
// holds element j of the W rows.
template <int Stride, int N, int W>
inline void load_rows(const float* base, const Index* index, int offset, Pack<W, float> (&out)[N]) {
  for (int j = 0; j < N; ++j) out[j] = Pack<W, float>::template gather<Stride>(base, index, offset + j);
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
  friend Mask4 operator&(Mask4 a, Mask4 b) { return {_mm256_and_pd(a.bits, b.bits)}; }
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
  // base[stride * index[i] + offset] for i = 0..3.
  template <int Stride>
  static Real4 gather(const Real* base, const Index* index, int offset = 0) {
    __m128i i = _mm_loadu_si128(reinterpret_cast<const __m128i*>(index));
    if constexpr (Stride != 1) i = _mm_mullo_epi32(i, _mm_set1_epi32(Stride));
    // The masked form: GCC 12 warns that the plain one reads an uninitialized source.
    const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
    return {_mm256_mask_i32gather_pd(_mm256_setzero_pd(), base + offset, i, all, 8)};
  }
  friend Real4 operator+(Real4 a, Real4 b) { return {_mm256_add_pd(a.v, b.v)}; }
  friend Real4 operator-(Real4 a, Real4 b) { return {_mm256_sub_pd(a.v, b.v)}; }
  friend Real4 operator*(Real4 a, Real4 b) { return {_mm256_mul_pd(a.v, b.v)}; }
  friend Real4 operator/(Real4 a, Real4 b) { return {_mm256_div_pd(a.v, b.v)}; }
  friend Real4 operator-(Real4 a) { return {_mm256_xor_pd(a.v, _mm256_set1_pd(-0.0))}; }
  Real4& operator+=(Real4 b) { return *this = *this + b; }
  Real4& operator-=(Real4 b) { return *this = *this - b; }
  Real4& operator*=(Real4 b) { return *this = *this * b; }
  friend Mask4 operator<(Real4 a, Real4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask4 operator<=(Real4 a, Real4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_LE_OQ)}; }
  friend Mask4 operator>(Real4 a, Real4 b) { return {_mm256_cmp_pd(a.v, b.v, _CMP_GT_OQ)}; }
  // a + b c, rounded once.
  friend Real4 fma(Real4 b, Real4 c, Real4 a) { return {_mm256_fmadd_pd(b.v, c.v, a.v)}; }
  friend Real4 reciprocal_sqrt(Real4 a) { return {_mm256_div_pd(_mm256_set1_pd(1), _mm256_sqrt_pd(a.v))}; }
  friend Real4 reciprocal(Real4 a) { return {_mm256_div_pd(_mm256_set1_pd(1), a.v)}; }
  friend Real4 abs(Real4 a) { return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)}; }
  friend Real4 max(Real4 a, Real4 b) { return {_mm256_max_pd(a.v, b.v)}; }
  friend Real4 select(Mask4 m, Real4 a, Real4 b) { return {_mm256_blendv_pd(b.v, a.v, m.bits)}; }
  // Writes the indices in[i] whose bit i is set in `lanes` to out[0..], in order; may write all
  // four.
  static void compress_indices(const Index* in, int lanes, Index* out);
  // Bit i set where in[i] > a.
  static int indices_above(const Index* in, Index a) {
    const __m128i above = _mm_cmpgt_epi32(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in)), _mm_set1_epi32(a));
    return _mm_movemask_ps(_mm_castsi128_ps(above));
  }
  // (l0 + l1) + (l2 + l3): one fixed order.
  Real sum() const {
    const __m128d low = _mm256_castpd256_pd128(v), high = _mm256_extractf128_pd(v, 1);
    const __m128d pairs = _mm_hadd_pd(low, high);  // (l0 + l1, l2 + l3)
    return _mm_cvtsd_f64(_mm_add_sd(pairs, _mm_unpackhi_pd(pairs, pairs)));
  }
};

// Four consecutive doubles from each of four rows (base + Stride index[i] + offset), transposed:
// out[j] holds element j of the four rows. Whole 256-bit row loads where gathering would load the
// same 16 doubles one by one.
template <int Stride>
inline void load_transposed(const Real* base, const Index* index, int offset, Real4 (&out)[4]) {
  const __m256d r0 = _mm256_loadu_pd(base + Stride * index[0] + offset);
  const __m256d r1 = _mm256_loadu_pd(base + Stride * index[1] + offset);
  const __m256d r2 = _mm256_loadu_pd(base + Stride * index[2] + offset);
  const __m256d r3 = _mm256_loadu_pd(base + Stride * index[3] + offset);
  const __m256d t0 = _mm256_unpacklo_pd(r0, r1), t1 = _mm256_unpackhi_pd(r0, r1);
  const __m256d t2 = _mm256_unpacklo_pd(r2, r3), t3 = _mm256_unpackhi_pd(r2, r3);
  out[0] = {_mm256_permute2f128_pd(t0, t2, 0x20)};
  out[1] = {_mm256_permute2f128_pd(t1, t3, 0x20)};
  out[2] = {_mm256_permute2f128_pd(t0, t2, 0x31)};
  out[3] = {_mm256_permute2f128_pd(t1, t3, 0x31)};
}

// The x and y components of the vectors v[index[i]] of an array of 3-vectors (x, y, z, x, ...),
// as one 128-bit load a vector, interleaved. Reads only the vectors' own components (a 256-bit
// load would read past the last vector).
inline void load_xy(const Real* v, const Index* index, Real4& x, Real4& y) {
  const __m256d low = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(v + 3 * index[0])),
                                           _mm_loadu_pd(v + 3 * index[2]), 1);  // x0 y0 x2 y2
  const __m256d high = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(v + 3 * index[1])),
                                            _mm_loadu_pd(v + 3 * index[3]), 1);  // x1 y1 x3 y3
  x = {_mm256_unpacklo_pd(low, high)};
  y = {_mm256_unpackhi_pd(low, high)};
}

// All three components: x and y by load_xy, z gathered.
inline void load_vectors(const Real* v, const Index* index, Real4& x, Real4& y, Real4& z) {
  load_xy(v, index, x, y);
  z = Real4::gather<3>(v, index, 2);
}

inline void Real4::compress_indices(const Index* in, int lanes, Index* out) {
  const __m128i lane = _mm_load_si128(reinterpret_cast<const __m128i*>(compress_lanes.lanes[lanes]));
  const __m128 values = _mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in)));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_castps_si128(_mm_permutevar_ps(values, lane)));
}

// Eight floats processed as one (the solid's pair loops, sph/solid.cpp): the operations of Real4,
// exactly rounded, on twice the lanes.
struct Mask8f {
  __m256 bits;
  friend Mask8f operator&(Mask8f a, Mask8f b) { return {_mm256_and_ps(a.bits, b.bits)}; }
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
  friend Float8 reciprocal_sqrt(Float8 a) { return {_mm256_div_ps(_mm256_set1_ps(1), _mm256_sqrt_ps(a.v))}; }
  friend Float8 reciprocal(Float8 a) { return {_mm256_div_ps(_mm256_set1_ps(1), a.v)}; }
  friend Float8 abs(Float8 a) { return {_mm256_andnot_ps(_mm256_set1_ps(-0.0f), a.v)}; }
  friend Float8 max(Float8 a, Float8 b) { return {_mm256_max_ps(a.v, b.v)}; }
  friend Float8 select(Mask8f m, Float8 a, Float8 b) { return {_mm256_blendv_ps(b.v, a.v, m.bits)}; }
  // Writes the indices in[i] whose bit i is set in `lanes` to out[0..], in order; writes all
  // eight.
  static void compress_indices(const Index* in, int lanes, Index* out) {
    const __m256i order = _mm256_cvtepu8_epi32(_mm_cvtsi64_si128(static_cast<long long>(compress_lanes8.order[lanes])));
    const __m256i all = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_permutevar8x32_epi32(all, order));
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

// Four consecutive floats from each of eight rows (base + Stride index[i] + offset), transposed:
// out[j] holds element j of the eight rows. Rows i and i + 4 share a register, then a 4 x 4
// transpose within each 128-bit half: eight loads and twelve shuffles.
template <int Stride>
[[gnu::always_inline]] inline void load_rows(const float* base, const Index* index, int offset, Float8 (&out)[4]) {
  const auto pair = [&](int i) {
    return _mm256_insertf128_ps(_mm256_castps128_ps256(_mm_loadu_ps(base + Stride * index[i] + offset)),
                                _mm_loadu_ps(base + Stride * index[i + 4] + offset), 1);
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
    const auto row = [&](int i) { return _mm256_loadu_ps(base + Stride * index[4 * g + i] + offset); };
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

}  // namespace avx2
#endif

#if defined(SPALL_SIMD_AVX512)
namespace avx512 {

// GCC 12 warns that the unmasked forms of some AVX-512 intrinsics (max, the reciprocal estimates,
// the 256-bit halves' inserts, extracts and casts) read an undefined source; their zero-masked
// forms with every lane on compile to the same instructions without the warning.
constexpr __mmask8 all_lanes = 0xFF;

struct Mask8 {
  __mmask8 bits;
  friend Mask8 operator&(Mask8 a, Mask8 b) { return {static_cast<__mmask8>(a.bits & b.bits)}; }
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
  // base[stride * index[i] + offset] for i = 0..7.
  template <int Stride>
  static Real8 gather(const Real* base, const Index* index, int offset = 0) {
    __m256i i = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(index));
    if constexpr (Stride != 1) i = _mm256_mullo_epi32(i, _mm256_set1_epi32(Stride));
    return {_mm512_mask_i32gather_pd(_mm512_setzero_pd(), all_lanes, i, base + offset, 8)};
  }
  friend Real8 operator+(Real8 a, Real8 b) { return {_mm512_add_pd(a.v, b.v)}; }
  friend Real8 operator-(Real8 a, Real8 b) { return {_mm512_sub_pd(a.v, b.v)}; }
  friend Real8 operator*(Real8 a, Real8 b) { return {_mm512_mul_pd(a.v, b.v)}; }
  friend Real8 operator/(Real8 a, Real8 b) { return {_mm512_div_pd(a.v, b.v)}; }
  friend Real8 operator-(Real8 a) { return {_mm512_xor_pd(a.v, _mm512_set1_pd(-0.0))}; }
  Real8& operator+=(Real8 b) { return *this = *this + b; }
  Real8& operator-=(Real8 b) { return *this = *this - b; }
  Real8& operator*=(Real8 b) { return *this = *this * b; }
  friend Mask8 operator<(Real8 a, Real8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LT_OQ)}; }
  friend Mask8 operator<=(Real8 a, Real8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_LE_OQ)}; }
  friend Mask8 operator>(Real8 a, Real8 b) { return {_mm512_cmp_pd_mask(a.v, b.v, _CMP_GT_OQ)}; }
  // a + b c, rounded once.
  friend Real8 fma(Real8 b, Real8 c, Real8 a) { return {_mm512_fmadd_pd(b.v, c.v, a.v)}; }
  // 1 / sqrt(a) and 1 / a for a > 0 (normal), to within a few ulp: the 14-bit estimates refined by
  // two Newton steps (each doubles the bits), multiplications and FMAs on two ports where a square
  // root and a division would queue on the one port that does those.
  friend Real8 reciprocal_sqrt(Real8 a) {
    const __m512d y0 = _mm512_maskz_rsqrt14_pd(all_lanes, a.v), half_a = _mm512_mul_pd(_mm512_set1_pd(0.5), a.v);
    const auto step = [&](__m512d y) {  // y (3/2 - a/2 y^2)
      return _mm512_mul_pd(y, _mm512_fnmadd_pd(half_a, _mm512_mul_pd(y, y), _mm512_set1_pd(1.5)));
    };
    return {step(step(y0))};
  }
  friend Real8 reciprocal(Real8 a) {
    const __m512d y0 = _mm512_maskz_rcp14_pd(all_lanes, a.v);
    const auto step = [&](__m512d y) {  // y + y (1 - a y)
      return _mm512_fmadd_pd(y, _mm512_fnmadd_pd(a.v, y, _mm512_set1_pd(1)), y);
    };
    return {step(step(y0))};
  }
  friend Real8 abs(Real8 a) { return {_mm512_abs_pd(a.v)}; }
  friend Real8 max(Real8 a, Real8 b) { return {_mm512_maskz_max_pd(all_lanes, a.v, b.v)}; }
  friend Real8 select(Mask8 m, Real8 a, Real8 b) { return {_mm512_mask_blend_pd(m.bits, b.v, a.v)}; }
  // Writes the indices in[i] whose bit i is set in `lanes` to out[0..], in order; writes all
  // eight. Compressed in a register and stored whole: a compressing store to memory is several
  // times slower on the processors measured (docs/PERFORMANCE.md).
  static void compress_indices(const Index* in, int lanes, Index* out) {
    const __m256i all = _mm256_loadu_si256(reinterpret_cast<const __m256i*>(in));
    _mm256_storeu_si256(reinterpret_cast<__m256i*>(out), _mm256_maskz_compress_epi32(static_cast<__mmask8>(lanes), all));
  }
  // Bit i set where in[i] > a.
  static int indices_above(const Index* in, Index a) {
    return _mm256_cmpgt_epi32_mask(_mm256_loadu_si256(reinterpret_cast<const __m256i*>(in)), _mm256_set1_epi32(a));
  }
  // ((l0 + l1) + (l2 + l3)) + ((l4 + l5) + (l6 + l7)), the order of lanes::Pack<8>::sum.
  Real sum() const {
    const __m256d low = _mm512_maskz_extractf64x4_pd(all_lanes, v, 0);
    const __m256d high = _mm512_maskz_extractf64x4_pd(all_lanes, v, 1);
    const __m256d pairs = _mm256_hadd_pd(low, high);
    // pairs = (l0 + l1, l4 + l5, l2 + l3, l6 + l7)
    const __m128d quads = _mm_add_pd(_mm256_castpd256_pd128(pairs), _mm256_extractf128_pd(pairs, 1));
    return _mm_cvtsd_f64(_mm_add_sd(quads, _mm_unpackhi_pd(quads, quads)));
  }
};

// Rows i and i + 4 of a transpose in the low and high halves of one register.
inline __m512d row_pair(__m256d low, __m256d high) {
  return _mm512_maskz_insertf64x4(all_lanes, _mm512_zextpd256_pd512(low), high, 1);
}

// Element j of the eight rows packed in t (rows 0, 1 | 4, 5 interleaved by unpack) and u (rows
// 2, 3 | 6, 7): `even` picks elements 0 and 1 of each 128-bit lane pair, else 2 and 3.
inline __m512d transposed_column(__m512d t, __m512d u, bool even) {
  const __m512i low = _mm512_set_epi64(13, 12, 5, 4, 9, 8, 1, 0), high = _mm512_set_epi64(15, 14, 7, 6, 11, 10, 3, 2);
  return _mm512_permutex2var_pd(t, even ? low : high, u);
}

// The eight 256-bit rows row(0) .. row(7), transposed: out[j] holds element j of each row. Twelve
// shuffles: rows i and i + 4 paired in one register, then an unpack and a two-source permute per
// column. Always inlined, like its callers.
template <typename Row>
[[gnu::always_inline]] inline void transpose_rows(const Row& row, __m512d (&out)[4]) {
  const __m512d r04 = row_pair(row(0), row(4)), r15 = row_pair(row(1), row(5));
  const __m512d r26 = row_pair(row(2), row(6)), r37 = row_pair(row(3), row(7));
  const __m512d t0 = _mm512_unpacklo_pd(r04, r15), t1 = _mm512_unpackhi_pd(r04, r15);
  const __m512d t2 = _mm512_unpacklo_pd(r26, r37), t3 = _mm512_unpackhi_pd(r26, r37);
  out[0] = transposed_column(t0, t2, true);
  out[1] = transposed_column(t1, t3, true);
  out[2] = transposed_column(t0, t2, false);
  out[3] = transposed_column(t1, t3, false);
}

// Four consecutive doubles from each of eight rows (base + Stride index[i] + offset), transposed:
// eight 256-bit loads and transpose_rows, where gathering would load 32 doubles one by one.
template <int Stride>
inline void load_transposed(const Real* base, const Index* index, int offset, Real8 (&out)[4]) {
  __m512d columns[4];
  transpose_rows([&](int i) { return _mm256_loadu_pd(base + Stride * index[i] + offset); }, columns);
  for (int j = 0; j < 4; ++j) out[j] = {columns[j]};
}

// The three components of eight 3-vectors, transposed from 256-bit loads masked to the vector's
// own three doubles (a masked-off element is not read, so the last vector of an array is safe),
// with no gather.
// Always inlined: called through the pair loops' lambdas, GCC 12 otherwise keeps it a call.
[[gnu::always_inline]] inline void load_vectors(const Real* v, const Index* index, Real8& x, Real8& y,
                                                Real8& z) {
  __m512d columns[4];
  transpose_rows([&](int i) { return _mm256_maskz_loadu_pd(0b0111, v + 3 * index[i]); }, columns);
  x = {columns[0]}, y = {columns[1]}, z = {columns[2]};
}

}  // namespace avx512
#endif

// The pack the pair loops use: the widest the build targets.
#if defined(SPALL_SIMD_AVX512)
using Pack = avx512::Real8;
using PackMask = avx512::Mask8;
using avx512::load_transposed;
using avx512::load_vectors;
#elif defined(SPALL_SIMD_AVX2)
using Pack = avx2::Real4;
using PackMask = avx2::Mask4;
using avx2::load_transposed;
using avx2::load_vectors;
#else
using Pack = lanes::Pack<4>;
using PackMask = lanes::Mask<4>;
using lanes::load_transposed;
using lanes::load_vectors;
#endif

// Eight single-precision lanes, the solid's pair loops (sph/solid.cpp), with their double
// accumulator and transposed row loads: AVX2 where the build has it (also with AVX-512).
#if defined(SPALL_SIMD_AVX2)
using Float8 = avx2::Float8;
using WideSum8 = avx2::WideSum8;
using avx2::load_rows;
using avx2::sum_lanes;
#else
using Float8 = lanes::Pack<8, float>;
using WideSum8 = lanes::WideSum<8>;
using lanes::load_rows;
#endif

// The lane sums of eight packs into out[0..7], out[i] = packs[i].sum() bit for bit (the same
// additions in the same pairs).
template <typename P>
inline void sum_lanes(const P (&packs)[8], Real* out) {
  for (int i = 0; i < 8; ++i) out[i] = packs[i].sum();
}
#if defined(SPALL_SIMD_AVX512)
// The eight packs transposed in a tree while they are added: neighbouring lanes of two packs by
// unpacks, then pairs of pairs and quads of quads by 128-bit shuffles, 21 instructions where eight
// sum() take 64, two thirds of them shuffles on the one port that does those. (The zero-masked
// forms with every lane on: see all_lanes.)
inline void sum_lanes(const avx512::Real8 (&packs)[8], Real* out) {
  __m512d pairs[4];  // pairs[k] = (a0 + a1, b0 + b1, a2 + a3, b2 + b3, ...) of packs 2k (a), 2k + 1 (b)
  for (int k = 0; k < 4; ++k) {
    const __m512d a = packs[2 * k].v, b = packs[2 * k + 1].v;
    pairs[k] = _mm512_add_pd(_mm512_maskz_unpacklo_pd(avx512::all_lanes, a, b),
                             _mm512_maskz_unpackhi_pd(avx512::all_lanes, a, b));
  }
  // 128-bit lanes 0 and 2 of x, then of y; and lanes 1 and 3: (l0 + l1) + (l2 + l3) of each pack in
  // the first, (l4 + l5) + (l6 + l7) in the second half of each 128-bit lane's pair.
  const auto halves = [](__m512d x, __m512d y) {
    return _mm512_add_pd(_mm512_maskz_shuffle_f64x2(avx512::all_lanes, x, y, 0x88),
                         _mm512_maskz_shuffle_f64x2(avx512::all_lanes, x, y, 0xDD));
  };
  const __m512d quads_low = halves(pairs[0], pairs[1]), quads_high = halves(pairs[2], pairs[3]);
  _mm512_storeu_pd(out, halves(quads_low, quads_high));
}
#endif

// The scalar forms, so that a kernel written with select/max serves both Real and a Pack.
inline Real select(bool m, Real a, Real b) { return m ? a : b; }
using std::max;

}  // namespace spall::simd
