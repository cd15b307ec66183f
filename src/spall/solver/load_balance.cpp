#include "spall/solver/load_balance.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace spall::solver {

bool LoadBalance::checks_at(long long step) const {
  if (interval <= 0 || step <= 0) return false;
  if (step % interval == 0) return true;
  for (long long early = first_check; early < interval; early *= 2)
    if (step == early) return true;
  return false;
}

std::vector<Index> balanced_blocks(std::span<const Index> begin, std::span<const double> work) {
  const int ranks = static_cast<int>(work.size());
  std::vector<double> w(work.begin(), work.end());
  for (double& x : w) x = std::max(x, 0.0);
  const double total = std::accumulate(w.begin(), w.end(), 0.0);
  if (!(total > 0)) return {begin.begin(), begin.end()};
  std::vector<Index> next(ranks + 1);
  next[0] = begin[0];
  next[ranks] = begin[ranks];
  int r = 0;
  double before = 0;  // the work of blocks 0 .. r - 1
  for (int k = 1; k < ranks; ++k) {
    const double target = total * k / ranks;
    while (r < ranks - 1 && before + w[r] < target) before += w[r++];
    const Index nodes = begin[r + 1] - begin[r];
    const double fraction = w[r] > 0 ? std::clamp((target - before) / w[r], 0.0, 1.0) : 0.0;
    next[k] = std::max(next[k - 1], begin[r] + static_cast<Index>(std::llround(fraction * nodes)));
  }
  return next;
}

}  // namespace spall::solver
