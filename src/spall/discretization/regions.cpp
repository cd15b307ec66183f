#include "spall/discretization/regions.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <limits>
#include <numeric>
#include <vector>

#include "spall/core/bounding_box.hpp"

namespace spall::discretization {

namespace {

constexpr std::uint64_t sign_bit = std::uint64_t{1} << 63;

// A coordinate as an unsigned integer in the same order: NaN (a particle that ran away) after
// every number, -0 and 0 as one coordinate.
std::uint64_t key_of(Real c) {
  if (std::isnan(c)) c = std::numeric_limits<Real>::infinity();
  if (c == 0) c = 0;
  const auto bits = std::bit_cast<std::uint64_t>(c);
  return bits & sign_bit ? ~bits : bits | sign_bit;
}
Real coordinate_of(std::uint64_t key) { return std::bit_cast<Real>(key & sign_bit ? key & ~sign_bit : ~key); }

// A process's points of one split, ascending by coordinate along its axis: the weight at or below
// a plane is a binary search and a prefix sum.
struct SortedPoints {
  std::vector<std::uint64_t> key;
  std::vector<std::int64_t> weight_through;  // weight_through[k]: of points 0..k

  std::int64_t weight_at_or_below(std::uint64_t plane) const {
    const auto k = std::upper_bound(key.begin(), key.end(), plane) - key.begin();
    return k == 0 ? 0 : weight_through[k - 1];
  }
};

// One search of a multisection: the lowest key in [low, high] at or below which the points of
// every process weigh at least `weight` (they weigh that much at or below `high`).
struct Search {
  const SortedPoints* points;
  std::int64_t weight;
  std::uint64_t low, high;
};

// Every search to its end at once: each round every unfinished one counts the weight below up to
// 256 trial keys spread over its interval, one sum over the processes for all of them, and each
// interval shrinks to the gap between two trials (at most 9 rounds for 64-bit keys).
void run(std::span<Search> searches, const parallel::Communicator& among) {
  constexpr std::uint64_t most_trials = 256;
  std::vector<std::uint64_t> trial;
  std::vector<std::int64_t> below;
  std::vector<std::size_t> first(searches.size() + 1);
  for (;;) {
    trial.clear();
    for (std::size_t s = 0; s < searches.size(); ++s) {
      first[s] = trial.size();
      const std::uint64_t low = searches[s].low, span = searches[s].high - low, trials = std::min(span, most_trials);
      for (std::uint64_t j = 0; j < trials; ++j)
        trial.push_back(low + static_cast<std::uint64_t>(static_cast<unsigned __int128>(span) * j / trials));
    }
    first.back() = trial.size();
    if (trial.empty()) return;
    below.resize(trial.size());
    for (std::size_t s = 0; s < searches.size(); ++s)
      for (std::size_t k = first[s]; k < first[s + 1]; ++k) below[k] = searches[s].points->weight_at_or_below(trial[k]);
    among.sum(below);
    for (std::size_t s = 0; s < searches.size(); ++s) {
      if (first[s] == first[s + 1]) continue;
      Search& search = searches[s];
      const auto begin = below.begin() + first[s], end = below.begin() + first[s + 1];
      const std::size_t j = std::find_if(begin, end, [&](std::int64_t b) { return b >= search.weight; }) - begin;
      if (j == 0) {
        search.high = search.low;
      } else if (begin + j == end) {
        search.low = trial[first[s + 1] - 1] + 1;
      } else {
        search.low = trial[first[s] + j - 1] + 1;
        search.high = trial[first[s] + j];
      }
    }
  }
}

// A split still to cut: its points, [begin, end) of the list that the cuts above partitioned, and
// what the processes found of them together.
struct Part {
  int split;
  std::size_t begin, end;
  int axis = 0;
  SortedPoints sorted{};
  std::int64_t points = 0, total = 0;  // of every process
  std::uint64_t lowest = 0, highest = 0;
  int above = -1, under = -1;  // its searches
};

}  // namespace

// Level by level down the tree, every split of a level cut at once: each step below is one
// collective for the whole level, so that P regions take about 25 log2(P) collectives.
Regions Regions::cut(std::span<const Vec3> x, std::span<const double> w, int ranks,
                     const parallel::Communicator& among) {
  Regions regions;
  regions.ranks_ = ranks;
  // Weights as integers, 2^30 for the heaviest point of all, so that every sum is exact and the
  // same however the points are shared; none weighs anything: every point counts as one.
  double heaviest = 0;
  for (const double wi : w) heaviest = std::max(heaviest, wi);
  heaviest = -heaviest;
  among.minimum({&heaviest, 1});
  heaviest = -heaviest;
  constexpr double unit = 1 << 30;
  std::vector<std::int64_t> weight(x.size(), 1);
  if (heaviest > 0)
    for (std::size_t i = 0; i < x.size(); ++i) {
      const double share = w[i] / heaviest;
      weight[i] = !(w[i] > 0)     ? 0
                  : !(share < 1) ? std::int64_t{1} << 30
                                 : std::max<std::int64_t>(1, std::llround(share * unit));
    }
  std::vector<Index> points(x.size());
  std::iota(points.begin(), points.end(), Index{0});
  std::vector<Split>& splits = regions.splits_;
  splits.push_back({.first = 0, .count = ranks});
  std::vector<Part> level;
  if (ranks > 1) level.push_back({.split = 0, .begin = 0, .end = points.size()});
  constexpr Real infinity = std::numeric_limits<Real>::infinity();
  while (!level.empty()) {
    const std::size_t m = level.size();
    // Across the longest side of the box of the points that weigh (of all of them when none
    // does; a point that ran away counts in neither).
    std::vector<BoundingBox> boxes(2 * m);  // of each split: the weighing points', every point's
    for (std::size_t k = 0; k < m; ++k)
      for (std::size_t p = level[k].begin; p < level[k].end; ++p)
        if (const Index i = points[p]; x[i].allFinite()) {
          boxes[2 * k + 1].include(x[i]);
          if (weight[i] > 0) boxes[2 * k].include(x[i]);
        }
    over_ranks(boxes, among);
    std::vector<std::int64_t> totals(2 * m);
    std::vector<double> extremes(2 * m, infinity);
    for (std::size_t k = 0; k < m; ++k) {
      Part& part = level[k];
      const BoundingBox& box = boxes[2 * k].empty() ? boxes[2 * k + 1] : boxes[2 * k];
      const Vec3 side = box.upper - box.lower;
      if (!box.empty())
        for (int d = 1; d < 3; ++d)
          if (side[d] > side[part.axis]) part.axis = d;
      const auto first = points.begin() + part.begin, last = points.begin() + part.end;
      std::sort(first, last, [&](Index i, Index j) {
        const std::uint64_t ki = key_of(x[i][part.axis]), kj = key_of(x[j][part.axis]);
        return ki < kj || (ki == kj && i < j);
      });
      std::int64_t through = 0;
      for (auto i = first; i != last; ++i) {
        part.sorted.key.push_back(key_of(x[*i][part.axis]));
        part.sorted.weight_through.push_back(through += weight[*i]);
      }
      totals[2 * k] = static_cast<std::int64_t>(part.end - part.begin), totals[2 * k + 1] = through;
      if (first != last) {
        extremes[2 * k] = coordinate_of(part.sorted.key.front());
        extremes[2 * k + 1] = -coordinate_of(part.sorted.key.back());
      }
    }
    among.sum(totals);
    among.minimum(extremes);

    // The boundary after a coordinate a (not the highest) whose weight at or below is nearest
    // low_ranks / count of the whole, the lowest such a when two are as near. The weight below
    // only grows with a, so it is the highest a below the share or the lowest above it: the
    // lowest key whose weight passes the share (`above`), and the lowest key that weighs what
    // lies below that (`under`).
    std::vector<Search> above, under;
    const auto share_of = [&](const Part& part) {  // of the weight, times count
      return static_cast<__int128>(part.total) * (splits[part.split].count / 2);
    };
    for (std::size_t k = 0; k < m; ++k) {
      Part& part = level[k];
      part.points = totals[2 * k], part.total = totals[2 * k + 1];
      if (part.points == 0) continue;
      part.lowest = key_of(extremes[2 * k]), part.highest = key_of(-extremes[2 * k + 1]);
      const __int128 share = share_of(part);
      const int count = splits[part.split].count;
      if (share / count >= part.total) continue;  // nothing weighs
      part.above = static_cast<int>(above.size());
      above.push_back({&part.sorted, static_cast<std::int64_t>(share / count) + 1, part.lowest, part.highest});
    }
    run(above, among);
    std::vector<std::int64_t> weights(2 * above.size());  // at or below above - 1, and above
    for (const Part& part : level)
      if (part.above >= 0) {
        const std::uint64_t key = above[part.above].low;
        weights[2 * part.above] = key > part.lowest ? part.sorted.weight_at_or_below(key - 1) : 0;
        weights[2 * part.above + 1] = part.sorted.weight_at_or_below(key);
      }
    among.sum(weights);
    for (Part& part : level)
      if (part.above >= 0 && weights[2 * part.above] > 0) {
        part.under = static_cast<int>(under.size());
        under.push_back({&part.sorted, weights[2 * part.above], part.lowest, above[part.above].low - 1});
      }
    run(under, among);
    std::vector<std::uint64_t> chosen(m);
    std::vector<double> next(m, infinity);
    for (std::size_t k = 0; k < m; ++k) {
      const Part& part = level[k];
      chosen[k] = part.highest;  // none
      if (part.points == 0) continue;
      if (part.above < 0) {
        chosen[k] = part.lowest;  // nothing weighs: every boundary is as near, the first is taken
      } else {
        const std::uint64_t key = above[part.above].low;
        const std::uint64_t low_key = part.under >= 0 ? under[part.under].low : part.lowest;
        const __int128 share = share_of(part), count = splits[part.split].count;
        const __int128 miss_under = share - weights[2 * part.above] * count;
        const __int128 miss_above = weights[2 * part.above + 1] * count - share;
        const bool under_exists = key > part.lowest;
        chosen[k] = under_exists && (key >= part.highest || miss_under <= miss_above) ? low_key : key;
      }
      if (chosen[k] < part.highest) {
        const auto after = std::upper_bound(part.sorted.key.begin(), part.sorted.key.end(), chosen[k]);
        if (after != part.sorted.key.end()) next[k] = coordinate_of(*after);
      }
    }
    among.minimum(next);

    // The cut half way to the next coordinate above the one chosen; the children, for the next level.
    std::vector<Part> children;
    for (std::size_t k = 0; k < m; ++k) {
      const Part& part = level[k];
      Real at = part.points > 0 ? extremes[2 * k] : 0;  // no boundary: every point on the upper side
      std::size_t below = 0;
      if (part.points > 0 && chosen[k] < part.highest) {
        below = static_cast<std::size_t>(
            std::upper_bound(part.sorted.key.begin(), part.sorted.key.end(), chosen[k]) - part.sorted.key.begin());
        const Real a = coordinate_of(chosen[k]), b = next[k];
        at = std::isfinite(b) ? a + Real(0.5) * (b - a) : b;
        if (!(at > a)) at = b;  // a and b adjacent doubles
      }
      const Split split = splits[part.split];
      const int low_ranks = split.count / 2;
      splits[part.split].axis = part.axis;
      splits[part.split].at = at;
      splits[part.split].low = static_cast<int>(splits.size());
      splits.push_back({.first = split.first, .count = low_ranks});
      splits[part.split].high = static_cast<int>(splits.size());
      splits.push_back({.first = split.first + low_ranks, .count = split.count - low_ranks});
      if (low_ranks > 1)
        children.push_back({.split = splits[part.split].low, .begin = part.begin, .end = part.begin + below});
      if (split.count - low_ranks > 1)
        children.push_back({.split = splits[part.split].high, .begin = part.begin + below, .end = part.end});
    }
    level = std::move(children);
  }
  return regions;
}

int Regions::rank_of(const Vec3& p) const {
  int s = 0;
  while (splits_[s].count > 1) s = p[splits_[s].axis] < splits_[s].at ? splits_[s].low : splits_[s].high;
  return splits_[s].first;
}

BoundingBox Regions::box(int r) const {
  BoundingBox b;
  b.lower = Vec3::Constant(-std::numeric_limits<Real>::infinity());
  b.upper = Vec3::Constant(std::numeric_limits<Real>::infinity());
  int s = 0;
  while (splits_[s].count > 1) {
    const Split& split = splits_[s];
    if (r < split.first + split.count / 2) {
      b.upper[split.axis] = std::min(b.upper[split.axis], split.at);
      s = split.low;
    } else {
      b.lower[split.axis] = std::max(b.lower[split.axis], split.at);
      s = split.high;
    }
  }
  return b;
}

}  // namespace spall::discretization
