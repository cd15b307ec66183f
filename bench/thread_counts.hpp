#pragma once
// The OpenMP thread counts the scene benchmarks run at: 1 and 2 (issue 3's targets are set on a
// two-core machine), or the comma-separated list in SPALL_BENCH_THREADS, e.g. "1,4,16" for the
// scaling on a larger machine.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <vector>

namespace spall::bench {

inline std::vector<int> thread_counts() {
  const char* list = std::getenv("SPALL_BENCH_THREADS");
  if (list == nullptr || *list == '\0') return {1, 2};
  std::vector<int> counts;
  const std::string text = list;
  std::size_t from = 0;
  while (from <= text.size()) {
    const std::size_t comma = std::min(text.find(',', from), text.size());
    const std::string item = text.substr(from, comma - from);
    char* end = nullptr;
    const long count = std::strtol(item.c_str(), &end, 10);
    if (item.empty() || *end != '\0' || count < 1 || count > 4096) {
      std::fprintf(stderr, "SPALL_BENCH_THREADS=%s: expected thread counts >= 1 separated by commas\n", list);
      std::exit(2);
    }
    counts.push_back(static_cast<int>(count));
    from = comma + 1;
  }
  return counts;
}

}  // namespace spall::bench
