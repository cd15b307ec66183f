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

// The lowest key in [low, high] at or below which the points of every process weigh at least
// `weight` (the points weigh that much at or below `high`): multisection, each round counting the
// weight below up to 256 trial keys, one sum over the processes, the interval then shrunk to the
// gap between two trials.
std::uint64_t lowest_reaching(const SortedPoints& points, std::int64_t weight, std::uint64_t low,
                              std::uint64_t high, const parallel::Communicator& among) {
  constexpr std::uint64_t most_trials = 256;
  std::vector<std::uint64_t> trial;
  std::vector<std::int64_t> below;
  while (low < high) {
    const std::uint64_t span = high - low, trials = std::min(span, most_trials);
    trial.resize(trials);
    below.resize(trials);
    for (std::uint64_t j = 0; j < trials; ++j) {
      trial[j] = low + static_cast<std::uint64_t>(static_cast<unsigned __int128>(span) * j / trials);
      below[j] = points.weight_at_or_below(trial[j]);
    }
    among.sum(below);
    const auto j = std::find_if(below.begin(), below.end(), [&](std::int64_t b) { return b >= weight; }) - below.begin();
    if (j == 0) return low;
    if (j == static_cast<std::ptrdiff_t>(trials)) {
      low = trial.back() + 1;
    } else {
      low = trial[j - 1] + 1;
      high = trial[j];
    }
  }
  return low;
}

}  // namespace

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
      weight[i] = !(w[i] > 0) ? 0 : !(share < 1) ? std::int64_t{1} << 30 : std::max<std::int64_t>(1, std::llround(share * unit));
    }
  std::vector<Index> points(x.size());
  std::iota(points.begin(), points.end(), Index{0});
  regions.add(x, weight, points, 0, ranks, among);
  return regions;
}

int Regions::add(std::span<const Vec3> x, std::span<const std::int64_t> weight, std::span<Index> points, int first,
                 int count, const parallel::Communicator& among) {
  const int here = static_cast<int>(splits_.size());
  splits_.push_back({.first = first, .count = count});
  if (count == 1) return here;
  // Across the longest side of the box of the points that weigh (of all of them when none does;
  // a point that ran away counts in neither).
  BoundingBox weighing, all;
  for (const Index i : points)
    if (x[i].allFinite()) {
      all.include(x[i]);
      if (weight[i] > 0) weighing.include(x[i]);
    }
  weighing = over_ranks(weighing, among);
  const BoundingBox box = weighing.empty() ? over_ranks(all, among) : weighing;
  int axis = 0;
  if (!box.empty()) {
    const Vec3 side = box.upper - box.lower;
    for (int d = 1; d < 3; ++d)
      if (side[d] > side[axis]) axis = d;
  }
  std::sort(points.begin(), points.end(), [&](Index i, Index j) {
    const std::uint64_t ki = key_of(x[i][axis]), kj = key_of(x[j][axis]);
    return ki < kj || (ki == kj && i < j);
  });
  SortedPoints sorted;
  std::int64_t through = 0;
  for (const Index i : points) {
    sorted.key.push_back(key_of(x[i][axis]));
    sorted.weight_through.push_back(through += weight[i]);
  }
  std::int64_t totals[2] = {static_cast<std::int64_t>(points.size()), through};
  among.sum(totals);
  const std::int64_t total = totals[1];
  double extremes[2] = {std::numeric_limits<Real>::infinity(), std::numeric_limits<Real>::infinity()};
  if (!points.empty()) extremes[0] = coordinate_of(sorted.key.front()), extremes[1] = -coordinate_of(sorted.key.back());
  among.minimum(extremes);

  // The boundary after a coordinate a (not the highest) whose weight at or below is nearest
  // low_ranks / count of the whole, the lowest such a when two are as near. The weight below only
  // grows with a, so it is the highest a below the share or the lowest above it: the lowest key
  // whose weight passes the share (`above`), and the lowest key that weighs what lies below that.
  const int low_ranks = count / 2;
  std::size_t below = 0;  // this process's points on the lower side
  Real at = totals[0] > 0 ? extremes[0] : 0;
  if (totals[0] > 0) {
    const std::uint64_t lowest = key_of(extremes[0]), highest = key_of(-extremes[1]);
    const auto share = static_cast<__int128>(total) * low_ranks;  // of the weight, times count
    std::uint64_t chosen = highest;  // none yet
    if (share / count < total) {
      const auto passing = static_cast<std::int64_t>(share / count) + 1;
      const std::uint64_t above = lowest_reaching(sorted, passing, lowest, highest, among);
      std::int64_t weights[2] = {above > lowest ? sorted.weight_at_or_below(above - 1) : 0,
                                 sorted.weight_at_or_below(above)};
      among.sum(weights);
      const std::uint64_t under = weights[0] == 0 ? lowest : lowest_reaching(sorted, weights[0], lowest, above - 1, among);
      const bool under_exists = above > lowest;
      const __int128 miss_under = share - static_cast<__int128>(weights[0]) * count;
      const __int128 miss_above = static_cast<__int128>(weights[1]) * count - share;
      chosen = under_exists && under < highest && (above >= highest || miss_under <= miss_above) ? under : above;
    } else {
      chosen = lowest;  // nothing weighs: every boundary is as near, the first is taken
    }
    if (chosen < highest) {
      // The next coordinate above the one chosen, the cut half way.
      const auto next_here = std::upper_bound(sorted.key.begin(), sorted.key.end(), chosen);
      below = static_cast<std::size_t>(next_here - sorted.key.begin());
      double next = next_here == sorted.key.end() ? std::numeric_limits<Real>::infinity() : coordinate_of(*next_here);
      among.minimum({&next, 1});
      const Real a = coordinate_of(chosen), b = next;
      at = std::isfinite(b) ? a + Real(0.5) * (b - a) : b;
      if (!(at > a)) at = b;  // a and b adjacent doubles
    }
  }
  splits_[here].axis = axis;
  splits_[here].at = at;
  const int low = add(x, weight, points.first(below), first, low_ranks, among);
  const int high = add(x, weight, points.subspan(below), first + low_ranks, count - low_ranks, among);
  splits_[here].low = low;
  splits_[here].high = high;
  return here;
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
