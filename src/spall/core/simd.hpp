#pragma once
// Four doubles processed as one: the lanes of the SPH pair loops, which take a particle's
// neighbours four at a time. AVX2 and FMA when the build targets them (x86-64-v3, the project's
// default), otherwise four scalars with the same operations lane by lane, so that the pair loops
// are written once. Every operation is lane-wise and exactly rounded (fused multiply-adds only
// where written), so a lane's result does not depend on its neighbours or on the thread count.
#include <cmath>
#include <cstdint>

#include "spall/core/types.hpp"

#if defined(__AVX2__) && defined(__FMA__)
#include <immintrin.h>
#define SPALL_SIMD_AVX2 1
#endif

namespace spall::simd {

// Four scalars, lane by lane: the portable implementation, and the reference the vector one is
// tested against (tests/unit/test_simd.cpp).
namespace lanes {

struct Mask4 {
  bool bit[4];
  friend Mask4 operator&(Mask4 a, Mask4 b) {
    return {{a.bit[0] && b.bit[0], a.bit[1] && b.bit[1], a.bit[2] && b.bit[2], a.bit[3] && b.bit[3]}};
  }
  int lanes() const { return bit[0] | bit[1] << 1 | bit[2] << 2 | bit[3] << 3; }
};

struct Real4 {
  Real v[4];
  Real4() : v{0, 0, 0, 0} {}
  Real4(Real value) : v{value, value, value, value} {}
  static Real4 load(const Real* p) { return from([&](int i) { return p[i]; }); }
  void store(Real* p) const {
    for (int i = 0; i < 4; ++i) p[i] = v[i];
  }
  template <int Stride>
  static Real4 gather(const Real* base, const Index* index, int offset = 0) {
    return from([&](int i) { return base[Stride * index[i] + offset]; });
  }
  template <typename F>
  static Real4 from(F&& f) {
    Real4 r;
    for (int i = 0; i < 4; ++i) r.v[i] = f(i);
    return r;
  }
  friend Real4 operator+(Real4 a, Real4 b) { return from([&](int i) { return a.v[i] + b.v[i]; }); }
  friend Real4 operator-(Real4 a, Real4 b) { return from([&](int i) { return a.v[i] - b.v[i]; }); }
  friend Real4 operator*(Real4 a, Real4 b) { return from([&](int i) { return a.v[i] * b.v[i]; }); }
  friend Real4 operator/(Real4 a, Real4 b) { return from([&](int i) { return a.v[i] / b.v[i]; }); }
  friend Real4 operator-(Real4 a) { return from([&](int i) { return -a.v[i]; }); }
  Real4& operator+=(Real4 b) { return *this = *this + b; }
  Real4& operator-=(Real4 b) { return *this = *this - b; }
  Real4& operator*=(Real4 b) { return *this = *this * b; }
  template <typename C>
  static Mask4 compare(Real4 a, Real4 b, C&& c) {
    return {{c(a.v[0], b.v[0]), c(a.v[1], b.v[1]), c(a.v[2], b.v[2]), c(a.v[3], b.v[3])}};
  }
  friend Mask4 operator<(Real4 a, Real4 b) { return compare(a, b, [](Real x, Real y) { return x < y; }); }
  friend Mask4 operator<=(Real4 a, Real4 b) { return compare(a, b, [](Real x, Real y) { return x <= y; }); }
  friend Mask4 operator>(Real4 a, Real4 b) { return compare(a, b, [](Real x, Real y) { return x > y; }); }
  friend Real4 fma(Real4 b, Real4 c, Real4 a) { return from([&](int i) { return std::fma(b.v[i], c.v[i], a.v[i]); }); }
  friend Real4 sqrt(Real4 a) { return from([&](int i) { return std::sqrt(a.v[i]); }); }
  friend Real4 abs(Real4 a) { return from([&](int i) { return std::abs(a.v[i]); }); }
  friend Real4 max(Real4 a, Real4 b) { return from([&](int i) { return a.v[i] < b.v[i] ? b.v[i] : a.v[i]; }); }
  friend Real4 select(Mask4 m, Real4 a, Real4 b) { return from([&](int i) { return m.bit[i] ? a.v[i] : b.v[i]; }); }
  void compress_store(Real* out, int lanes) const {
    for (int i = 0; i < 4; ++i)
      if (lanes & (1 << i)) *out++ = v[i];
  }
  Real sum() const { return (v[0] + v[1]) + (v[2] + v[3]); }
};

template <int Stride>
inline void load_transposed(const Real* base, const Index* index, int offset, Real4 (&out)[4]) {
  for (int j = 0; j < 4; ++j) out[j] = Real4::gather<Stride>(base, index, offset + j);
}

inline void load_vectors(const Real* v, const Index* index, Real4& x, Real4& y, Real4& z) {
  x = Real4::gather<3>(v, index, 0);
  y = Real4::gather<3>(v, index, 1);
  z = Real4::gather<3>(v, index, 2);
}

inline void compress_store(const Index* in, int lanes, Index* out) {
  for (int i = 0; i < 4; ++i)
    if (lanes & (1 << i)) *out++ = in[i];
}

}  // namespace lanes

#if defined(SPALL_SIMD_AVX2)
namespace avx2 {

// For each 4-bit lane mask, the 32-bit permutation that moves the selected double lanes to the
// front in order (the rest unspecified).
struct CompressTable {
  alignas(32) std::int32_t lanes[16][8];
  constexpr CompressTable() : lanes{} {
    for (int mask = 0; mask < 16; ++mask) {
      int k = 0;
      for (int lane = 0; lane < 4; ++lane)
        if (mask & (1 << lane)) lanes[mask][2 * k] = 2 * lane, lanes[mask][2 * k + 1] = 2 * lane + 1, ++k;
      for (; k < 4; ++k) lanes[mask][2 * k] = 0, lanes[mask][2 * k + 1] = 1;
    }
  }
};
inline constexpr CompressTable compress_lanes;
inline __m256i compress_permutation(int mask) {
  return _mm256_load_si256(reinterpret_cast<const __m256i*>(compress_lanes.lanes[mask]));
}

struct Mask4 {
  __m256d bits;
  friend Mask4 operator&(Mask4 a, Mask4 b) { return {_mm256_and_pd(a.bits, b.bits)}; }
  // Bit i set when lane i is true.
  int lanes() const { return _mm256_movemask_pd(bits); }
};

struct Real4 {
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
  friend Real4 sqrt(Real4 a) { return {_mm256_sqrt_pd(a.v)}; }
  friend Real4 abs(Real4 a) { return {_mm256_andnot_pd(_mm256_set1_pd(-0.0), a.v)}; }
  friend Real4 max(Real4 a, Real4 b) { return {_mm256_max_pd(a.v, b.v)}; }
  friend Real4 select(Mask4 m, Real4 a, Real4 b) { return {_mm256_blendv_pd(b.v, a.v, m.bits)}; }
  // Writes the lanes whose bit is set in `lanes` to out[0..], in order; may write all four.
  void compress_store(Real* out, int lanes) const {
    _mm256_storeu_pd(out, _mm256_castps_pd(_mm256_permutevar8x32_ps(_mm256_castpd_ps(v), compress_permutation(lanes))));
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

// The three components of the vectors v[index[i]] of an array of 3-vectors (x, y, z, x, ...):
// x and y as one 128-bit load a vector, interleaved; z gathered. Reads only the vectors' own
// components (a 256-bit load would read past the last vector).
inline void load_vectors(const Real* v, const Index* index, Real4& x, Real4& y, Real4& z) {
  const __m256d low = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(v + 3 * index[0])),
                                           _mm_loadu_pd(v + 3 * index[2]), 1);  // x0 y0 x2 y2
  const __m256d high = _mm256_insertf128_pd(_mm256_castpd128_pd256(_mm_loadu_pd(v + 3 * index[1])),
                                            _mm_loadu_pd(v + 3 * index[3]), 1);  // x1 y1 x3 y3
  x = {_mm256_unpacklo_pd(low, high)};
  y = {_mm256_unpackhi_pd(low, high)};
  z = Real4::gather<3>(v, index, 2);
}

// The same for four indices.
inline void compress_store(const Index* in, int lanes, Index* out) {
  const __m256i index = compress_permutation(lanes);
  // Even float lanes of the double permutation are the 32-bit lane numbers times two.
  const __m128i lane = _mm_srli_epi32(_mm256_castsi256_si128(_mm256_permutevar8x32_epi32(index, _mm256_setr_epi32(0, 2, 4, 6, 0, 2, 4, 6))), 1);
  const __m128 values = _mm_castsi128_ps(_mm_loadu_si128(reinterpret_cast<const __m128i*>(in)));
  _mm_storeu_si128(reinterpret_cast<__m128i*>(out), _mm_castps_si128(_mm_permutevar_ps(values, lane)));
}

}  // namespace avx2
using avx2::compress_store;
using avx2::load_transposed;
using avx2::load_vectors;
using avx2::Mask4;
using avx2::Real4;
#else
using lanes::compress_store;
using lanes::load_transposed;
using lanes::load_vectors;
using lanes::Mask4;
using lanes::Real4;
#endif

// The scalar forms, so that a kernel written with select/max serves both Real and Real4.
inline Real select(bool m, Real a, Real b) { return m ? a : b; }
using std::max;

}  // namespace spall::simd
