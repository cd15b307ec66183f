#pragma once
// Geometry of the four-node linear tetrahedron (LS-DYNA's ELFORM 10, written as a hexahedron
// card N1 N2 N3 N4 N4 N4 N4 N4; VTK's node order): positive volume when N4 lies on the side of
// (N2 - N1) x (N3 - N1). Its gradient is constant, so b_I = dV/dx_I = V grad N_I is exact.
#include <algorithm>
#include <array>
#include <cmath>

#include "spall/core/types.hpp"

namespace spall::fem {

using TetNodes = std::array<Vec3, 4>;

struct TetGradient {
  std::array<Vec3, 4> b;  // dV/dx_I: a third of the area vector of the face opposite node I
  Real volume = 0;
};

inline TetGradient tet_gradient(const TetNodes& x) {
  const Vec3 e1 = x[1] - x[0], e2 = x[2] - x[0], e3 = x[3] - x[0];
  TetGradient out;
  out.b[1] = e2.cross(e3) / 6;
  out.b[2] = e3.cross(e1) / 6;
  out.b[3] = e1.cross(e2) / 6;
  out.b[0] = -(out.b[1] + out.b[2] + out.b[3]);
  out.volume = e1.dot(out.b[1]);
  return out;
}

// The smallest altitude, 3 V / (largest face area) = V / max |b_I| (the characteristic length of
// LS-DYNA's tetrahedra, fem-contact.md §2.4).
inline Real tet_characteristic_length(const TetGradient& g) {
  Real largest = 0;
  for (const Vec3& b : g.b) largest = std::max(largest, b.squaredNorm());
  return g.volume / std::sqrt(largest);
}

}  // namespace spall::fem
