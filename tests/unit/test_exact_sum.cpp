// The exact sum (core/exact_sum.hpp): the correctly rounded sum of its terms, whatever their order,
// their split into partial sums or the thread count. References: integer sums, exact in __int128
// and rounded to nearest by the compiler's conversion (IEEE 754 round to nearest, ties to even),
// scaled by powers of two; and sums whose exact value is known by construction.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include "spall/core/exact_sum.hpp"
#include "spall/core/parallel.hpp"

namespace spall {
namespace {

double sum_of(const std::vector<double>& terms) {
  ExactSum s;
  for (double x : terms) s += x;
  return s.value();
}

TEST(ExactSum, CancellationLeavesTheSmallTerm) {
  // A plain left-to-right sum gives 0 here.
  EXPECT_EQ(sum_of({1e100, 1.0, -1e100}), 1.0);
  EXPECT_EQ(sum_of({1e308, 3e-320, -1e308}), 3e-320);
  // 0.1, 0.2 and 0.3 are 3602879701896397 2^-55, 3602879701896397 2^-54 and 5404319552844595 2^-54:
  // their sum is 2^-55 exactly (a plain sum gives 2^-54).
  EXPECT_EQ(sum_of({0.1, 0.2, -0.3}), std::ldexp(1.0, -55));
  EXPECT_EQ(sum_of({}), 0.0);
  EXPECT_EQ(sum_of({2.5, -2.5}), 0.0);
}

TEST(ExactSum, TiesRoundToEvenAndTheRestDecides) {
  const double two53 = 9007199254740992.0;  // 2^53: neighbours 2^53 - 1, 2^53 + 2
  EXPECT_EQ(sum_of({two53, 1.0}), two53);                      // tie, even below
  EXPECT_EQ(sum_of({two53, 3.0}), two53 + 4);                  // tie, even above
  EXPECT_EQ(sum_of({two53, 1.0, std::ldexp(1.0, -60)}), two53 + 2);  // just above the tie
  EXPECT_EQ(sum_of({two53, 1.0, -std::ldexp(1.0, -60)}), two53);     // just below
  EXPECT_EQ(sum_of({-two53, -3.0}), -two53 - 4);
  // The same far below the top digit: the tie is decided by a term 1000 binades down.
  EXPECT_EQ(sum_of({1.0, std::ldexp(1.0, -53), std::ldexp(1.0, -1000)}), 1.0 + std::ldexp(1.0, -52));
}

TEST(ExactSum, SubnormalsOverflowAndNonFiniteTerms) {
  const double tiny = std::numeric_limits<double>::denorm_min(), big = std::numeric_limits<double>::max();
  EXPECT_EQ(sum_of({tiny, tiny, tiny}), 3 * tiny);
  EXPECT_EQ(sum_of({tiny, -2 * tiny}), -tiny);
  EXPECT_EQ(sum_of({std::numeric_limits<double>::min(), -tiny}), std::numeric_limits<double>::min() - tiny);
  EXPECT_EQ(sum_of({big, big, -big}), big);  // the intermediate 2 max is held exactly
  EXPECT_EQ(sum_of({big, big}), HUGE_VAL);
  EXPECT_EQ(sum_of({-big, -big}), -HUGE_VAL);
  EXPECT_EQ(sum_of({HUGE_VAL, 1.0}), HUGE_VAL);
  EXPECT_EQ(sum_of({-HUGE_VAL, 1.0}), -HUGE_VAL);
  EXPECT_TRUE(std::isnan(sum_of({HUGE_VAL, -HUGE_VAL})));
  EXPECT_TRUE(std::isnan(sum_of({1.0, std::numeric_limits<double>::quiet_NaN()})));
  EXPECT_EQ(std::signbit(sum_of({-0.0})), false);  // an exact zero is +0, as x + (-x) gives
}

// Random integers up to 2^62 in magnitude, scaled by 2^s: the exact sum is an __int128 times 2^s,
// and its rounding to double is the conversion's.
TEST(ExactSum, EqualsTheRoundedExactSumOfScaledIntegers) {
  std::mt19937_64 random(20261129);
  int checked = 0;
  for (int scale : {-1074, -1030, -600, -64, 0, 1, 31, 32, 33, 500, 900}) {
    for (int trial = 0; trial < 200; ++trial) {
      const int n = 1 + static_cast<int>(random() % 60);
      const int bits = 1 + static_cast<int>(random() % 62);
      __int128 exact = 0;
      ExactSum s;
      for (int i = 0; i < n; ++i) {
        const std::int64_t magnitude = static_cast<std::int64_t>(random() >> (64 - bits));
        const std::int64_t term = (random() & 1) ? -magnitude : magnitude;
        // Each term must itself be a double: keep its 53 leading bits.
        const int width = std::bit_width(static_cast<std::uint64_t>(magnitude));
        const std::int64_t unit = width > 53 ? std::int64_t(1) << (width - 53) : 1;
        const std::int64_t kept = term / unit * unit;
        exact += kept;
        s += std::ldexp(static_cast<double>(kept), scale);
      }
      const double reference = std::ldexp(static_cast<double>(exact), scale);
      const bool exact_integer = exact < (__int128(1) << 53) && exact > -(__int128(1) << 53);
      if (!exact_integer && std::fabs(reference) < std::numeric_limits<double>::min()) {
        continue;  // ldexp would round the rounded integer a second time, into the subnormals
      }
      ASSERT_EQ(s.value(), reference) << "scale " << scale << " trial " << trial;
      ++checked;
    }
  }
  EXPECT_GT(checked, 2000) << "of 2200: too many sums skipped";
}

TEST(ExactSum, OrderSplitAndNormalizationDoNotChangeTheBits) {
  std::mt19937_64 random(7);
  std::lognormal_distribution<double> size(0.0, 8.0);
  std::vector<double> terms(20000);
  for (double& x : terms) x = (random() & 1 ? 1 : -1) * size(random);
  const double once = sum_of(terms);
  for (int shuffle = 0; shuffle < 5; ++shuffle) {
    std::shuffle(terms.begin(), terms.end(), random);
    ExactSum parts[3];
    for (std::size_t i = 0; i < terms.size(); ++i) parts[random() % 3] += terms[i];
    parts[1].normalize();
    ExactSum total = parts[2];
    total += parts[0];
    total += parts[1];
    EXPECT_EQ(total.value(), once);
    EXPECT_EQ(sum_of(terms), once);
  }
}

TEST(ExactSum, ParallelSumIsTheSameForAnyThreadCount) {
  std::mt19937_64 random(11);
  std::normal_distribution<double> normal(0.0, 1e3);
  std::vector<double> terms(100000);
  for (double& x : terms) x = normal(random);
  const auto sum_with = [&](int threads) {
    parallel::set_thread_count(threads);
    return parallel::exact_sum(static_cast<Index>(terms.size()), [&](Index i) {
      Sums<2> t;
      t[0] = terms[i];
      t[1] = terms[i] * terms[i];
      return t;
    });
  };
  const Sums<2> one = sum_with(1), two = sum_with(2), three = sum_with(3);
  parallel::set_thread_count(1);
  EXPECT_EQ(one[0], sum_of(terms));
  for (const Sums<2>& s : {two, three}) {
    EXPECT_EQ(s[0], one[0]);
    EXPECT_EQ(s[1], one[1]);
  }
}

}  // namespace
}  // namespace spall
