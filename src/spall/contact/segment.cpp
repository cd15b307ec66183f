#include "spall/contact/segment.hpp"

#include <limits>

namespace spall::contact {

std::array<Real, 3> closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const Real d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return {1, 0, 0};  // vertex a
  const Vec3 bp = p - b;
  const Real d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return {0, 1, 0};  // vertex b
  const Real vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) {  // edge ab
    const Real s = d1 / (d1 - d3);
    return {1 - s, s, 0};
  }
  const Vec3 cp = p - c;
  const Real d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return {0, 0, 1};  // vertex c
  const Real vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) {  // edge ac
    const Real s = d2 / (d2 - d6);
    return {1 - s, 0, s};
  }
  const Real va = d3 * d6 - d5 * d4;
  if (va <= 0 && d4 - d3 >= 0 && d5 - d6 >= 0) {  // edge bc
    const Real s = (d4 - d3) / ((d4 - d3) + (d5 - d6));
    return {0, 1 - s, s};
  }
  const Real denominator = 1 / (va + vb + vc);  // the face: p's projection is inside
  const Real v = vb * denominator, w = vc * denominator;
  return {1 - v - w, v, w};
}

SegmentPoint closest_on_segment(const Vec3& p, const std::array<Vec3, 4>& x, bool triangle) {
  SegmentPoint best;
  best.distance_squared = std::numeric_limits<Real>::infinity();
  if (triangle) {
    const auto w = closest_on_triangle(p, x[0], x[1], x[2]);
    best.point = w[0] * x[0] + w[1] * x[1] + w[2] * x[2];
    best.distance_squared = (p - best.point).squaredNorm();
    best.normal = (x[1] - x[0]).cross(x[2] - x[0]).normalized();
    best.weight = {w[0], w[1], w[2], 0};
    return best;
  }
  const Vec3 centre = Real(0.25) * (x[0] + x[1] + x[2] + x[3]);
  for (int k = 0; k < 4; ++k) {
    const Vec3& a = x[k];
    const Vec3& b = x[(k + 1) % 4];
    const auto w = closest_on_triangle(p, a, b, centre);
    const Vec3 point = w[0] * a + w[1] * b + w[2] * centre;
    const Real d2 = (p - point).squaredNorm();
    if (!(d2 < best.distance_squared)) continue;
    best.distance_squared = d2;
    best.point = point;
    best.normal = (b - a).cross(centre - a).normalized();
    const Real shared = Real(0.25) * w[2];  // the centre's share goes to the four corners alike
    best.weight = {shared, shared, shared, shared};
    best.weight[k] += w[0];
    best.weight[(k + 1) % 4] += w[1];
  }
  return best;
}

}  // namespace spall::contact
