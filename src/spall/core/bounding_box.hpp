#pragma once
// Axis-aligned bounding boxes, and the box of many points taken in parallel: min and max are
// exact, so the box does not depend on how the points are split among threads.
#include <concepts>
#include <limits>

#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/types.hpp"

namespace spall {

struct BoundingBox {
  Vec3 lower = Vec3::Constant(std::numeric_limits<Real>::infinity());
  Vec3 upper = Vec3::Constant(-std::numeric_limits<Real>::infinity());
  bool finite = true;  // false once a point with a NaN or infinite coordinate was included

  bool empty() const { return !(lower[0] <= upper[0]); }
  void include(const Vec3& p) {
    finite = finite && p.allFinite();
    lower = lower.cwiseMin(p);
    upper = upper.cwiseMax(p);
  }
  void include(const BoundingBox& b) {
    finite = finite && b.finite;
    lower = lower.cwiseMin(b.lower);
    upper = upper.cwiseMax(b.upper);
  }
  Vec3 centre() const { return Real(0.5) * (lower + upper); }
  bool contains(const Vec3& p) const {
    return (p.array() >= lower.array()).all() && (p.array() <= upper.array()).all();
  }
  // The box widened by `margin` on every side (empty stays empty).
  BoundingBox grown(Real margin) const {
    BoundingBox box = *this;
    if (!empty()) box.lower.array() -= margin, box.upper.array() += margin;
    return box;
  }
};

// The box of every rank's points from each rank's box of its own (min and max are exact: every
// rank gets the same box, the one a single process finds). Collective.
inline BoundingBox over_ranks(const BoundingBox& mine, const parallel::Communicator& ranks) {
  double extremes[7] = {mine.lower[0],  mine.lower[1],  mine.lower[2], -mine.upper[0],
                        -mine.upper[1], -mine.upper[2], mine.finite ? 0.0 : -1.0};
  ranks.minimum(extremes);
  BoundingBox box;
  box.lower = Vec3(extremes[0], extremes[1], extremes[2]);
  box.upper = -Vec3(extremes[3], extremes[4], extremes[5]);
  box.finite = extremes[6] == 0;
  return box;
}

// The box of point(i) for i in [0, n) (empty for n = 0).
template <std::integral I, class PointAt>
BoundingBox bounding_box(I n, PointAt&& point) {
  return parallel::fold_exact(
      n, BoundingBox{}, [&](BoundingBox& box, I i) { box.include(point(i)); },
      [](BoundingBox& box, const BoundingBox& other) { box.include(other); });
}

}  // namespace spall
