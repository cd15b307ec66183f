#include "spall/fem/hexahedron.hpp"

#include <algorithm>
#include <cmath>

namespace spall::fem {

namespace {

// The nodes in binary order (bit 0: xi = +1, bit 1: eta = +1, bit 2: zeta = +1), and the binary
// index of each basis monomial's variables (xi 1, eta 2, zeta 4; eta zeta 6, xi zeta 5, xi eta 3).
constexpr int node_of_binary[8] = {0, 1, 3, 2, 4, 5, 7, 6};
constexpr int binary_of_monomial[8] = {0, 1, 2, 4, 6, 5, 3, 7};

}  // namespace

HexVectors hex_coefficients(const HexVectors& x) {
  // After the stage of bit d, slot m holds the sum over the pair with the sign of its variable d
  // where m has bit d: y_m = sum_b x_b prod_{d in m} (+1 if b has bit d, else -1).
  HexVectors y;
  for (int b = 0; b < 8; ++b) y[b] = x[node_of_binary[b]];
  for (int d = 1; d < 8; d <<= 1)
    for (int b = 0; b < 8; ++b)
      if (!(b & d)) {
        const Vec3 low = y[b], high = y[b | d];
        y[b] = low + high;
        y[b | d] = high - low;
      }
  HexVectors a;
  for (int k = 0; k < 8; ++k) a[k] = Real(0.125) * y[binary_of_monomial[k]];
  return a;
}

HexVectors hex_nodal(const HexVectors& a) {
  // The inverse: x_b = sum_m a_m prod_{d in m} (+1 if b has bit d, else -1), stage by stage.
  HexVectors y;
  for (int k = 0; k < 8; ++k) y[binary_of_monomial[k]] = a[k];
  for (int d = 1; d < 8; d <<= 1)
    for (int b = 0; b < 8; ++b)
      if (!(b & d)) {
        const Vec3 low = y[b], high = y[b | d];
        y[b] = low - high;
        y[b | d] = low + high;
      }
  HexVectors x;
  for (int b = 0; b < 8; ++b) x[node_of_binary[b]] = y[b];
  return x;
}

// g_k = dV/da_k of the cubic in hexahedron.hpp, and V = (1/3) sum_k a_k . g_k (Euler's theorem
// for a cubic form).
HexVolumeGradient hex_volume_gradient(const HexVectors& a) {
  constexpr Real third8 = Real(8) / 3;
  HexVolumeGradient out;
  auto& g = out.g;
  g[0] = g[7] = Vec3::Zero();
  g[1] = 8 * a[2].cross(a[3]) + third8 * a[6].cross(a[5]);
  g[2] = 8 * a[3].cross(a[1]) + third8 * a[4].cross(a[6]);
  g[3] = 8 * a[1].cross(a[2]) + third8 * a[5].cross(a[4]);
  g[4] = third8 * (a[6].cross(a[2]) + a[3].cross(a[5]));
  g[5] = third8 * (a[4].cross(a[3]) + a[1].cross(a[6]));
  g[6] = third8 * (a[2].cross(a[4]) + a[5].cross(a[1]));
  Real v = 0;
  for (int k = 1; k < 7; ++k) v += a[k].dot(g[k]);
  out.volume = v / 3;
  return out;
}

HexGradient hex_gradient(const HexVectors& x) {
  const HexVolumeGradient vg = hex_volume_gradient(hex_coefficients(x));
  HexVectors g8;
  for (int k = 0; k < 8; ++k) g8[k] = Real(0.125) * vg.g[k];
  return {hex_nodal(g8), vg.volume};
}

Real hex_characteristic_length(const HexVectors& a, const HexVectors& g, Real volume) {
  Mat3 S = Mat3::Zero();
  for (int k = 1; k < 7; ++k) S.noalias() += g[k] * g[k].transpose();
  const Real stiffest = S.cwiseAbs().rowwise().sum().maxCoeff();
  const Real largest = std::max({(a[1] - a[5]).cross(a[2] - a[4]).squaredNorm(),   // zeta = -1
                                 (a[1] + a[5]).cross(a[2] + a[4]).squaredNorm(),   // zeta = +1
                                 (a[2] - a[6]).cross(a[3] - a[5]).squaredNorm(),   // xi = -1
                                 (a[2] + a[6]).cross(a[3] + a[5]).squaredNorm(),   // xi = +1
                                 (a[1] - a[6]).cross(a[3] - a[4]).squaredNorm(),   // eta = -1
                                 (a[1] + a[6]).cross(a[3] + a[4]).squaredNorm()});  // eta = +1
  return std::min(volume / (4 * std::sqrt(largest)), 2 * volume / std::sqrt(stiffest));
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
