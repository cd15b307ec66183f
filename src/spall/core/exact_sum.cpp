#include "spall/core/exact_sum.hpp"

#include <cmath>
#include <limits>

namespace spall {

void ExactSum::flush() {
  for (int e = lowest_bin_; e <= highest_bin_; ++e) {
    if (bin_[e] == 0) continue;
    // bin 2^e, cut at the chunk boundaries: two 32-bit pieces and a signed rest (below 2^31).
    __int128 rest = static_cast<__int128>(bin_[e]) << (e % chunk_bits);
    std::int64_t* chunk = &chunk_[e / chunk_bits];
    chunk[0] += static_cast<std::int64_t>(rest & 0xffffffff);
    rest >>= chunk_bits;
    chunk[1] += static_cast<std::int64_t>(rest & 0xffffffff);
    chunk[2] += static_cast<std::int64_t>(rest >> chunk_bits);
    bin_[e] = 0;
  }
  lowest_bin_ = 2047, highest_bin_ = 0;
  room_ = terms_per_flush;
  if (++flushes_ == flushes_per_carry) normalize();
}

void ExactSum::normalize() {
  if (room_ != terms_per_flush) flush();
  for (int k = 0; k + 1 < chunk_count; ++k) {
    const std::int64_t carry = chunk_[k] >> chunk_bits;  // floor(chunk / 2^32), also when negative
    chunk_[k] -= carry * (std::int64_t(1) << chunk_bits);
    chunk_[k + 1] += carry;
  }
  flushes_ = 0;
}

ExactSum& ExactSum::operator+=(const ExactSum& other) {
  ExactSum addend = other;
  addend.normalize();
  normalize();
  for (int k = 0; k < chunk_count; ++k) chunk_[k] += addend.chunk_[k];
  flushes_ = 1;  // each chunk now below 2^33: as after a flush
  special_ |= other.special_;
  return *this;
}

double ExactSum::value() const {
  if (special_ & not_a_number || special_ == (positive_infinity | negative_infinity))
    return std::numeric_limits<double>::quiet_NaN();
  if (special_) return special_ == positive_infinity ? HUGE_VAL : -HUGE_VAL;

  // The magnitude as 32-bit digits, and its sign.
  ExactSum magnitude = *this;
  magnitude.normalize();
  std::array<std::int64_t, chunk_count>& digit = magnitude.chunk_;
  const bool negative = digit[chunk_count - 1] < 0;
  if (negative) {
    for (std::int64_t& d : digit) d = -d;
    magnitude.normalize();
  }
  if (digit[chunk_count - 1] >> chunk_bits != 0) return negative ? -HUGE_VAL : HUGE_VAL;
  int top = chunk_count - 1;
  while (top >= 0 && digit[top] == 0) --top;
  if (top < 0) return 0.0;

  // The highest set bit, P, in units of 2^-1075. Up to P = 52 the sum is a multiple of 2^-1074
  // below 2^-1022 (bit 0 is never set: e >= 1), a subnormal or the smallest normals: exact.
  const auto d = [&](int k) { return k < 0 ? std::uint64_t(0) : static_cast<std::uint64_t>(digit[k]); };
  const int top_bit = chunk_bits * top + std::bit_width(d(top)) - 1;
  if (top_bit <= 52) {
    const double result = std::ldexp(static_cast<double>(d(1) << chunk_bits | d(0)), -1075);
    return negative ? -result : result;
  }

  // Otherwise 53 bits from P down, rounded to nearest, ties to even, by the bits below: the window
  // of three digits holds P and at least 64 bits under it, the digits further down only decide
  // whether the remainder is exactly a half.
  const unsigned __int128 window =
      static_cast<unsigned __int128>(d(top)) << 64 | static_cast<unsigned __int128>(d(top - 1)) << 32 | d(top - 2);
  const int dropped = top_bit - chunk_bits * (top - 2) - 52;  // bits of the window below the 53 kept
  auto significand = static_cast<std::uint64_t>(window >> dropped);
  const unsigned __int128 remainder = window & ((static_cast<unsigned __int128>(1) << dropped) - 1);
  const unsigned __int128 half = static_cast<unsigned __int128>(1) << (dropped - 1);
  bool below_exact = remainder == half;
  for (int k = top - 3; below_exact && k >= 0; --k) below_exact = digit[k] == 0;
  if (remainder > half || (remainder == half && (!below_exact || (significand & 1)))) ++significand;
  const double result = std::ldexp(static_cast<double>(significand), top_bit - 52 - 1075);
  return negative ? -result : result;
}

}  // namespace spall
