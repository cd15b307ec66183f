// parallel::CoreShare (core/parallel.hpp) lowers the loops' thread count while the machine's cores
// are shared and raises it back: it must never go above the count in force when it was made nor
// below one, and must leave that count in force when it ends, so that whatever runs next (another
// run in the same process, a test) gets the threads it asked for; a count the user fixed
// (--threads, set_thread_count, OMP_NUM_THREADS) it keeps throughout. Its decisions depend on the
// machine's load, which no test controls: what it decides is not asserted here (the timing is in
// bench/two_runs.sh and docs/PERFORMANCE.md).
#include <gtest/gtest.h>

#include <algorithm>
#include <chrono>

#include "spall/core/parallel.hpp"

using namespace spall;

namespace {

// Steps of busy loops for 0.35 s (three and a half of CoreShare's looks), asking between steps;
// check(threads) after each.
template <typename Check>
void busy_steps(parallel::CoreShare& cores, Check&& check) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(350);
  double sink = 0;
  while (std::chrono::steady_clock::now() < end) {
    sink += parallel::reduce_exact(100000, 0.0, [](int i) { return double(i); },
                                   [](double a, double b) { return std::max(a, b); });
    cores.between_steps();
    check(cores.threads());
  }
  EXPECT_EQ(sink > 0, true);
}

}  // namespace

TEST(CoreShare, StaysWithinOneAndTheThreadCountItFoundAndRestoresIt) {
  for (int most : {1, 2, 3}) {
    parallel::set_thread_count(most);
    {
      parallel::CoreShare cores(true);
      busy_steps(cores, [&](int threads) {
        ASSERT_GE(threads, 1);
        ASSERT_LE(threads, most);
        ASSERT_EQ(parallel::thread_count(), threads);
      });
    }
    EXPECT_EQ(parallel::thread_count(), most);
  }
}

TEST(CoreShare, KeepsTheCountTheUserFixed) {
  parallel::set_thread_count(2);
  ASSERT_TRUE(parallel::thread_count_fixed());
  parallel::CoreShare cores;
  busy_steps(cores, [](int threads) {
    ASSERT_EQ(threads, 2);
    ASSERT_EQ(parallel::thread_count(), 2);
  });
}
