#pragma once
// A master segment of a contact surface: a triangle, or a quadrilateral taken as the four triangles
// that its edges make with its centre (the centre is the mean of the corners, so a warped face has
// no gap and every corner shares the force of a point near the middle). fem-contact.md §2.7.
#include <array>

#include "spall/core/types.hpp"

namespace spall::contact {

struct Segment {
  std::array<Index, 4> node{};  // counter-clockwise seen from outside; a triangle repeats node[2]
  Real thickness = 0;  // V / A of the solid element whose face it is: the unit of the release depth
  Real stiffness = 0;  // SOFT 0 penalty stiffness of the segment, SLSFAC SFS K A^2 / V
  Real area = 0;       // at the start, for the viscous friction limit VC A

  bool triangle() const { return node[3] == node[2]; }
  int corners() const { return triangle() ? 3 : 4; }
};

// The point of a segment closest to p, with the normal of the (sub-)triangle it lies on and the
// weights that spread a point force on it to the corners (they sum to 1).
struct SegmentPoint {
  Real distance_squared = 0;
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();  // outward unit normal
  std::array<Real, 4> weight{};
};

// The barycentric weights (on a, b, c) of the point of triangle abc closest to p: by the Voronoi
// region of p (a vertex, an edge or the face), as in Ericson, Real-Time Collision Detection §5.1.5.
std::array<Real, 3> closest_on_triangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c);

// The point of the segment with corners x (x[3] == x[2] for a triangle) closest to p.
SegmentPoint closest_on_segment(const Vec3& p, const std::array<Vec3, 4>& x, bool triangle);

}  // namespace spall::contact
