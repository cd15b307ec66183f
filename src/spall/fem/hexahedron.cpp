#include "spall/fem/hexahedron.hpp"

#include <algorithm>
#include <cmath>

namespace spall::fem {

HexCoefficients hex_coefficients(const HexNodes& x) {
  HexCoefficients c;
  auto& a = c.a;
  for (int k = 0; k < 8; ++k) {
    Vec3 s = Vec3::Zero();
    for (int I = 0; I < 8; ++I) s += hex_basis[k][I] * x[I];
    a[k] = Real(0.125) * s;
  }
  return c;
}

// g_k = dV/da_k of the cubic in hexahedron.hpp (dV/da_0 = dV/da_7 = 0), then
// b_I = sum_k (dV/da_k)(da_k/dx_I) = (1/8) sum_k c_kI g_k, and V = (1/3) sum_k a_k . g_k (Euler's
// theorem for a cubic form).
HexGradient hex_gradient(const HexCoefficients& coefficients) {
  const auto& a = coefficients.a;
  constexpr Real third8 = Real(8) / 3;
  Vec3 g[7];
  g[1] = 8 * a[2].cross(a[3]) + third8 * a[6].cross(a[5]);
  g[2] = 8 * a[3].cross(a[1]) + third8 * a[4].cross(a[6]);
  g[3] = 8 * a[1].cross(a[2]) + third8 * a[5].cross(a[4]);
  g[4] = third8 * (a[6].cross(a[2]) + a[3].cross(a[5]));
  g[5] = third8 * (a[4].cross(a[3]) + a[1].cross(a[6]));
  g[6] = third8 * (a[2].cross(a[4]) + a[5].cross(a[1]));
  HexGradient out;
  for (int I = 0; I < 8; ++I) {
    Vec3 b = Vec3::Zero();
    for (int k = 1; k < 7; ++k) b += hex_basis[k][I] * g[k];
    out.b[I] = Real(0.125) * b;
  }
  Real v = 0;
  for (int k = 1; k < 7; ++k) v += a[k].dot(g[k]);
  out.volume = v / 3;
  return out;
}

Real hex_characteristic_length(const HexNodes& x, Real volume) {
  static constexpr int faces[6][4] = {{0, 3, 2, 1}, {4, 5, 6, 7}, {0, 1, 5, 4},
                                      {1, 2, 6, 5}, {2, 3, 7, 6}, {3, 0, 4, 7}};
  Real largest = 0;
  for (const auto& f : faces)
    largest = std::max(largest, (x[f[2]] - x[f[0]]).cross(x[f[3]] - x[f[1]]).squaredNorm());
  return volume / (Real(0.5) * std::sqrt(largest));
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

Real hex_point_gradients(const HexNodes& x, int g, std::array<Vec3, 8>& grad) {
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
