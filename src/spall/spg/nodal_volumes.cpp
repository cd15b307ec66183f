#include "spall/spg/nodal_volumes.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spall::spg {

namespace {
// Local coordinates of the corners in LS-DYNA order.
constexpr Real corner_xi[8][3] = {{-1, -1, -1}, {1, -1, -1}, {1, 1, -1}, {-1, 1, -1},
                                  {-1, -1, 1},  {1, -1, 1},  {1, 1, 1},  {-1, 1, 1}};

// LS-DYNA's tetrahedron N1 N2 N3 N4 N4 N4 N4 N4: the trilinear map would bend the face N1-N4
// through the apex, so the element is taken as the linear tetrahedron of its four distinct corners,
// each of which gets a quarter of the volume (the row sum of its consistent mass).
HexVolumes tetrahedron_volumes(const HexCorners& x) {
  HexVolumes v;
  const Real volume = (x[1] - x[0]).cross(x[2] - x[0]).dot(x[3] - x[0]) / 6;
  v.total = volume;
  v.min_jacobian = volume;
  for (int a = 0; a < 4; ++a) v.corner[a] = volume / 4;
  return v;
}

bool is_tetrahedron(const HexCorners& x) {
  for (int a = 4; a < 8; ++a)
    if (x[a] != x[3]) return false;
  return x[0] != x[1] && x[0] != x[2] && x[1] != x[2] && x[0] != x[3] && x[1] != x[3] && x[2] != x[3];
}

}  // namespace

HexVolumes hex_volumes(const HexCorners& x) {
  if (is_tetrahedron(x)) return tetrahedron_volumes(x);
  HexVolumes v;
  v.min_jacobian = std::numeric_limits<Real>::infinity();
  const Real g = 1 / std::sqrt(Real(3));
  for (int q = 0; q < 8; ++q) {
    const Real p[3] = {corner_xi[q][0] * g, corner_xi[q][1] * g, corner_xi[q][2] * g};
    Real N[8];
    Mat3 J = Mat3::Zero();  // J_ij = d x_i / d xi_j
    for (int a = 0; a < 8; ++a) {
      const Real s[3] = {1 + corner_xi[a][0] * p[0], 1 + corner_xi[a][1] * p[1], 1 + corner_xi[a][2] * p[2]};
      N[a] = s[0] * s[1] * s[2] / 8;
      const Vec3 dN(corner_xi[a][0] * s[1] * s[2] / 8, corner_xi[a][1] * s[0] * s[2] / 8,
                    corner_xi[a][2] * s[0] * s[1] / 8);
      J.noalias() += x[a] * dN.transpose();
    }
    const Real det = J.determinant();  // Gauss weights are 1
    v.min_jacobian = std::min(v.min_jacobian, det);
    v.total += det;
    for (int a = 0; a < 8; ++a) v.corner[a] += N[a] * det;
  }
  return v;
}

}  // namespace spall::spg
