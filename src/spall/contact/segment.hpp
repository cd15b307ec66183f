#pragma once
// A master segment of a contact surface: a triangle, or a quadrilateral taken as the four triangles
// that its edges make with its centre (the centre is the mean of the corners, so a warped face has
// no gap and every corner shares the force of a point near the middle). fem-contact.md §2.7.
#include <array>

#include "spall/core/types.hpp"

namespace spall::contact {

struct Segment {
  std::array<Index, 4> node{};  // counter-clockwise seen from outside; a triangle repeats node[2]
  // The unit of the release depth: V / A of the solid element whose face it is, a shell's thickness.
  Real thickness = 0;
  Real stiffness = 0;  // SOFT 0 penalty stiffness: SLSFAC SFS K A^2 / V (solid), K A / max diagonal (shell)
  Real area = 0;       // at the start, for the viscous friction limit VC A
  // A shell's segment: the contact surface lies `offset` off its mid-surface (half the thickness in
  // the automatic types), on both sides when two_sided (the automatic types), else on the side its
  // normal points to. A solid's face: one-sided, no offset.
  bool two_sided = false;
  Real offset = 0;

  bool triangle() const { return node[3] == node[2]; }
  int corners() const { return triangle() ? 3 : 4; }

  // A point at the signed distance d from the segment's mid-surface (along its normal) is pushed
  // along `sign` times the normal, and touches when `penetration` > 0.
  struct Contact {
    Real sign = 1;
    Real penetration = 0;
  };
  Contact contact_at(Real d) const {
    const Real sign = two_sided && d < 0 ? -1 : 1;
    return {sign, offset - sign * d};
  }
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
