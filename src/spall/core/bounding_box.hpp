#pragma once
// Axis-aligned bounding boxes, and the box of many points taken in parallel: min and max are
// exact, so the box does not depend on how the points are split among threads.
#include <concepts>
#include <limits>

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
};

// The box of point(i) for i in [0, n) (empty for n = 0).
template <std::integral I, class PointAt>
BoundingBox bounding_box(I n, PointAt&& point) {
  return parallel::fold_exact(
      n, BoundingBox{}, [&](BoundingBox& box, I i) { box.include(point(i)); },
      [](BoundingBox& box, const BoundingBox& other) { box.include(other); });
}

}  // namespace spall
