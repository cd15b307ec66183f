#pragma once
// Axis-aligned bounding boxes, and the box of many points taken in parallel: min and max are
// exact, so the box does not depend on how the points are split among threads.
#include <concepts>
#include <limits>
#include <span>
#include <vector>

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
  // Whether the two boxes share a point (their faces included).
  bool meets(const BoundingBox& other) const {
    return (lower.array() <= other.upper.array()).all() && (other.lower.array() <= upper.array()).all();
  }
  // The box widened by `margin` on every side (empty stays empty).
  BoundingBox grown(Real margin) const {
    BoundingBox box = *this;
    if (!empty()) box.lower.array() -= margin, box.upper.array() += margin;
    return box;
  }
};

// In place, each box the box of every rank's points from each rank's box of its own (min and max
// are exact: every rank gets the same boxes, the ones a single process finds); one collective for
// them all. Collective.
inline void over_ranks(std::span<BoundingBox> boxes, const parallel::Communicator& ranks) {
  std::vector<double> extremes(7 * boxes.size());
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    for (int d = 0; d < 3; ++d) extremes[7 * k + d] = boxes[k].lower[d], extremes[7 * k + 3 + d] = -boxes[k].upper[d];
    extremes[7 * k + 6] = boxes[k].finite ? 0.0 : -1.0;
  }
  ranks.minimum(extremes);
  for (std::size_t k = 0; k < boxes.size(); ++k) {
    const double* e = &extremes[7 * k];
    boxes[k].lower = Vec3(e[0], e[1], e[2]);
    boxes[k].upper = -Vec3(e[3], e[4], e[5]);
    boxes[k].finite = e[6] == 0;
  }
}

inline BoundingBox over_ranks(const BoundingBox& mine, const parallel::Communicator& ranks) {
  BoundingBox box = mine;
  over_ranks(std::span(&box, 1), ranks);
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
