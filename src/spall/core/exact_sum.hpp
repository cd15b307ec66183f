#pragma once
// A sum of doubles kept exact until one final rounding, so that it does not depend on the order of
// its terms: not on the thread count, the storage order of the particles or, with MPI, on how they
// are spread over the ranks (docs/SCALING.md §2, "Sums"). The "large superaccumulator" of Neal,
// "Fast exact summation using small and large superaccumulators" (arXiv:1505.05571, 2015): a
// double m 2^(e - 1075) (m the 53-bit integer significand, e the biased exponent) is the integer
// m 2^e in units of 2^-1075. Each term's signed m is added to a 64-bit bin of its exponent, one
// integer add a term; 1024 of them fit in a bin. Then the bins are flushed into the "small"
// accumulator, 32-bit chunks of the whole binary range held in signed 64-bit integers, which
// takes 2^24 flushes before its carries must be moved up. Integer adds are exact and associative.
#include <algorithm>
#include <array>
#include <bit>
#include <cstdint>

namespace spall {

class ExactSum {
 public:
  // e up to 2046 and a bin of 63 bits shifted by up to 31: bits up to 2140, chunks 0..66.
  static constexpr int chunk_bits = 32;
  static constexpr int chunk_count = 67;

  void add(double x) {
    const auto bits = std::bit_cast<std::uint64_t>(x);
    const auto exponent = static_cast<int>((bits >> 52) & 0x7ff);
    std::uint64_t significand = bits & ((std::uint64_t(1) << 52) - 1);
    if (exponent == 0x7ff) return add_special(significand != 0, bits >> 63);
    if (exponent != 0) significand |= std::uint64_t(1) << 52;
    if (significand == 0) return;
    const auto m = static_cast<std::int64_t>(significand);
    const int e = exponent == 0 ? 1 : exponent;  // subnormals: the smallest normal's scale
    bin_[e] += bits >> 63 ? -m : m;
    lowest_bin_ = std::min(lowest_bin_, e), highest_bin_ = std::max(highest_bin_, e);
    if (--room_ == 0) flush();
  }
  ExactSum& operator+=(double x) {
    add(x);
    return *this;
  }
  ExactSum& operator+=(const ExactSum& other);

  // The sum rounded once, to the nearest double (ties to even); ±inf beyond the double range, NaN
  // if a term was NaN or both infinities were added (as an ordinary sum would give).
  double value() const;

  // Flushes the bins and moves each chunk's carry into the next, leaving chunks 0 .. chunk_count - 2
  // in [0, 2^32) and the sign in the top chunk; the value is unchanged.
  void normalize();

  // The chunks and the non-finite terms seen, for a sum across ranks: after normalize(), adding
  // the chunks of up to 2^31 sums element by element as integers, and or-ing the flags, gives
  // the chunks and flags of the total.
  std::array<std::int64_t, chunk_count>& chunks() { return chunk_; }
  std::uint32_t& special() { return special_; }

 private:
  static constexpr int terms_per_flush = 1 << 10;        // 2^10 terms below 2^53: a bin stays below 2^63
  static constexpr std::int32_t flushes_per_carry = 1 << 20;  // each adds below 2^39 to a chunk (96 bins)
  enum : std::uint32_t { positive_infinity = 1, negative_infinity = 2, not_a_number = 4 };
  void add_special(bool nan, bool negative) {
    special_ |= nan ? not_a_number : negative ? negative_infinity : positive_infinity;
  }
  void flush();

  std::array<std::int64_t, 2048> bin_{};
  std::array<std::int64_t, chunk_count> chunk_{};
  // The bins a flush visits: those added to since the last (a sum's terms span a few dozen
  // binades; visiting all 2046 bins cost two loads a term).
  int lowest_bin_ = 2047, highest_bin_ = 0;
  std::int32_t room_ = terms_per_flush;          // terms the bins take before a flush
  std::int32_t flushes_ = 0;                     // since the chunks were last normalized
  std::uint32_t special_ = 0;
};

}  // namespace spall
