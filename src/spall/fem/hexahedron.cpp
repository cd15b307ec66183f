#include "spall/fem/hexahedron.hpp"

#include <cmath>

namespace spall::fem {

HexGradient hex_gradient(const HexVectors& x) {
  const HexVolumeGradient vg = hex_volume_gradient(hex_coefficients(x));
  HexVectors g8;
  for (int k = 0; k < 8; ++k) g8[k] = Real(0.125) * vg.g[k];
  return {hex_nodal(g8), vg.volume};
}

const HexGaussRule& hex_gauss_rule() {
  static const HexGaussRule rule = [] {
    HexGaussRule r;
    const Real p = 1 / std::sqrt(Real(3));
    for (int g = 0; g < 8; ++g) {
      // The points in the nodes' order, at +-1/sqrt(3).
      const Vec3 s(p * hex_basis[1][g], p * hex_basis[2][g], p * hex_basis[3][g]);
      for (int I = 0; I < 8; ++I) {
        const Vec3 n(hex_basis[1][I], hex_basis[2][I], hex_basis[3][I]);
        const Real fx = 1 + n.x() * s.x(), fy = 1 + n.y() * s.y(), fz = 1 + n.z() * s.z();
        r.dN[g][I] = Real(0.125) * Vec3(n.x() * fy * fz, n.y() * fx * fz, n.z() * fx * fy);
      }
    }
    return r;
  }();
  return rule;
}

Real hex_point_gradients(const HexVectors& x, int g, HexVectors& grad) {
  const auto& dN = hex_gauss_rule().dN[g];
  Mat3 J = Mat3::Zero();  // J_ij = dx_i / dxi_j
  for (int I = 0; I < 8; ++I) J.noalias() += x[I] * dN[I].transpose();
  const Real det = J.determinant();
  if (!(det > 0)) return det;
  const Mat3 inverse_transpose = J.inverse().transpose();
  for (int I = 0; I < 8; ++I) grad[I] = inverse_transpose * dN[I];
  return det;
}

}  // namespace spall::fem
