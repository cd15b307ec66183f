#include "spall/discretization/regions.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>

#include "spall/core/bounding_box.hpp"

namespace spall::discretization {

namespace {
// A coordinate to sort by: NaN (a particle that ran away) after every number.
Real key(Real c) { return std::isnan(c) ? std::numeric_limits<Real>::infinity() : c; }
}  // namespace

Regions Regions::cut(std::span<const Vec3> x, std::span<const double> w, int ranks) {
  Regions regions;
  regions.ranks_ = ranks;
  std::vector<Index> points(x.size());
  std::iota(points.begin(), points.end(), Index{0});
  // No point weighs anything: every point counts as one.
  const bool weighs = std::any_of(w.begin(), w.end(), [](double wi) { return wi > 0; });
  const std::vector<double> ones(weighs ? 0 : x.size(), 1.0);
  regions.add(x, weighs ? w : std::span<const double>(ones), points, 0, ranks);
  return regions;
}

int Regions::add(std::span<const Vec3> x, std::span<const double> w, std::span<Index> points, int first, int count) {
  const int here = static_cast<int>(splits_.size());
  splits_.push_back({.first = first, .count = count});
  if (count == 1) return here;
  // Across the longest side of the box of the points that weigh (of all of them when none does).
  BoundingBox box;
  for (const Index i : points)
    if (w[i] > 0) box.include(x[i]);
  if (box.empty())
    for (const Index i : points) box.include(x[i]);
  int axis = 0;
  if (!box.empty()) {
    const Vec3 side = box.upper - box.lower;
    for (int d = 1; d < 3; ++d)
      if (side[d] > side[axis]) axis = d;
  }
  std::sort(points.begin(), points.end(), [&](Index i, Index j) {
    const Real ci = key(x[i][axis]), cj = key(x[j][axis]);
    return ci < cj || (ci == cj && i < j);
  });
  // The boundary between two distinct coordinates whose weight below is nearest low_ranks / count
  // of the whole (the first such when two are as near); none: every point on the upper side.
  const int low_ranks = count / 2;
  double total = 0;
  for (const Index i : points) total += std::max(w[i], 0.0);
  const double target = total * low_ranks / count;
  const std::size_t n = points.size();
  std::size_t below = 0;
  double best = std::numeric_limits<double>::infinity(), prefix = 0;
  for (std::size_t k = 1; k < n; ++k) {
    prefix += std::max(w[points[k - 1]], 0.0);
    const Real a = key(x[points[k - 1]][axis]), b = key(x[points[k]][axis]);
    if (!(b > a) || std::abs(prefix - target) >= best) continue;
    best = std::abs(prefix - target);
    below = k;
  }
  Real at = n > 0 ? key(x[points[0]][axis]) : 0;
  if (below > 0) {
    const Real a = key(x[points[below - 1]][axis]), b = key(x[points[below]][axis]);
    at = std::isfinite(b) ? a + Real(0.5) * (b - a) : b;
    if (!(at > a)) at = b;  // a and b adjacent doubles
  }
  splits_[here].axis = axis;
  splits_[here].at = at;
  const int low = add(x, w, points.first(below), first, low_ranks);
  const int high = add(x, w, points.subspan(below), first + low_ranks, count - low_ranks);
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
