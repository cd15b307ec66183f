#pragma once
// Geometry of the eight-node trilinear hexahedron in LS-DYNA's node order (also VTK's): N1-N4
// one face, N5-N8 the opposite face in the same order. Natural coordinates of node I:
//   (-,-,-) (+,-,-) (+,+,-) (-,+,-) (-,-,+) (+,-,+) (+,+,+) (-,+,+).
// A degenerate element (a prism or a pyramid: repeated nodes) is the same map with corners that
// coincide.
//
// The map x = sum_I N_I x_I is written in the element's polynomial basis
//   x = a0 + a1 xi + a2 eta + a3 zeta + a4 eta zeta + a5 xi zeta + a6 xi eta + a7 xi eta zeta,
//   a_k = (1/8) sum_I c_kI x_I,  c_kI the value of the basis monomial k at node I,
// whose last four are the hourglass base vectors Gamma_1..4 of Flanagan & Belytschko (1981, IJNME
// 17:679): eta zeta, xi zeta, xi eta, xi eta zeta at the nodes. The exact volume is a cubic in the
// a_k (docs/THEORY.md §10.1):
//   V = 8 [a1, a2, a3] + (8/3) ([a6, a2, a4] + [a5, a4, a3] + [a1, a6, a5]),   [u, v, w] = u . (v x w),
// and b_I = dV/dx_I = integral over the element of grad N_I (FB's uniform gradient): the strain
// rate of the one-point element is D = sym((1/V) sum_I v_I (x) b_I) and its nodal forces are
// f_I = -sigma b_I.
#include <algorithm>
#include <array>
#include <cmath>

#include "spall/core/types.hpp"
#include "spall/fem/lanes.hpp"

namespace spall::fem {

// c_kI: the basis monomials 1, xi, eta, zeta, eta zeta, xi zeta, xi eta, xi eta zeta at node I.
inline constexpr int hex_basis[8][8] = {
    {1, 1, 1, 1, 1, 1, 1, 1},          {-1, 1, 1, -1, -1, 1, 1, -1},    {-1, -1, 1, 1, -1, -1, 1, 1},
    {-1, -1, -1, -1, 1, 1, 1, 1},      {1, 1, -1, -1, -1, -1, 1, 1},    {1, -1, -1, 1, -1, 1, 1, -1},
    {1, -1, 1, -1, 1, -1, 1, -1},      {-1, 1, -1, 1, 1, -1, 1, -1}};
// The hourglass base vectors Gamma_alpha (alpha = 0..3) are rows 4-7 of hex_basis.
inline constexpr int hourglass_modes = 4;

// Eight vectors per node or per basis monomial: Eigen's (HexVectors), or the lanes' of several
// elements at once (lanes.hpp). The functions below take either.
template <typename V>
using HexArray = std::array<V, 8>;
using HexVectors = HexArray<Vec3>;

namespace detail {
// The nodes in binary order (bit 0: xi = +1, bit 1: eta = +1, bit 2: zeta = +1), and the binary
// index of each basis monomial's variables (xi 1, eta 2, zeta 4; eta zeta 6, xi zeta 5, xi eta 3).
inline constexpr int node_of_binary[8] = {0, 1, 3, 2, 4, 5, 7, 6};
inline constexpr int binary_of_monomial[8] = {0, 1, 2, 4, 6, 5, 3, 7};
}  // namespace detail

// The basis coefficients a_k = (1/8) sum_I c_kI x_I of nodal vectors (a_0, the centroid, included),
// and back, x_I = sum_k c_kI a_k: each by a butterfly of 24 additions per component (the
// transform is a 3D Walsh-Hadamard transform with the nodes in LS-DYNA's order).
template <typename V>
HexArray<V> hex_coefficients(const HexArray<V>& x) {
  using S = typename V::Scalar;
  // After the stage of bit d, slot m holds the sum over the pair with the sign of its variable d
  // where m has bit d: y_m = sum_b x_b prod_{d in m} (+1 if b has bit d, else -1).
  HexArray<V> y;
  for (int b = 0; b < 8; ++b) y[b] = x[detail::node_of_binary[b]];
  for (int d = 1; d < 8; d <<= 1)
    for (int b = 0; b < 8; ++b)
      if (!(b & d)) {
        const V low = y[b], high = y[b | d];
        y[b] = low + high;
        y[b | d] = high - low;
      }
  HexArray<V> a;
  for (int k = 0; k < 8; ++k) a[k] = S(0.125) * y[detail::binary_of_monomial[k]];
  return a;
}

template <typename V>
HexArray<V> hex_nodal(const HexArray<V>& a) {
  // The inverse: x_b = sum_m a_m prod_{d in m} (+1 if b has bit d, else -1), stage by stage.
  HexArray<V> y;
  for (int k = 0; k < 8; ++k) y[detail::binary_of_monomial[k]] = a[k];
  for (int d = 1; d < 8; d <<= 1)
    for (int b = 0; b < 8; ++b)
      if (!(b & d)) {
        const V low = y[b], high = y[b | d];
        y[b] = low - high;
        y[b | d] = low + high;
      }
  HexArray<V> x;
  for (int b = 0; b < 8; ++b) x[detail::node_of_binary[b]] = y[b];
  return x;
}

// g_k = dV/da_k (k = 1..6; g_0 = g_7 = 0) and V, from the basis coefficients of the map. The
// uniform gradient is b_I = (1/8) sum_k c_kI g_k = hex_nodal(g / 8), and
// sum_I u_I (x) b_I = sum_k a_k(u) (x) g_k for any nodal field u.
template <typename V>
struct HexVolumeGradientOf {
  HexArray<V> g;
  typename V::Scalar volume;
};
using HexVolumeGradient = HexVolumeGradientOf<Vec3>;

// g_k = dV/da_k of the cubic above, and V = (1/3) sum_k a_k . g_k (Euler's theorem for a cubic form).
template <typename V>
HexVolumeGradientOf<V> hex_volume_gradient(const HexArray<V>& a) {
  using S = typename V::Scalar;
  const S eight(8), third8(Real(8) / 3);
  HexVolumeGradientOf<V> out;
  auto& g = out.g;
  g[0] = g[7] = zero_vector<V>();
  g[1] = eight * cross(a[2], a[3]) + third8 * cross(a[6], a[5]);
  g[2] = eight * cross(a[3], a[1]) + third8 * cross(a[4], a[6]);
  g[3] = eight * cross(a[1], a[2]) + third8 * cross(a[5], a[4]);
  g[4] = third8 * (cross(a[6], a[2]) + cross(a[3], a[5]));
  g[5] = third8 * (cross(a[4], a[3]) + cross(a[1], a[6]));
  g[6] = third8 * (cross(a[2], a[4]) + cross(a[5], a[1]));
  S v(0);
  for (int k = 1; k < 7; ++k) v = v + dot(a[k], g[k]);
  out.volume = v / S(3);
  return out;
}

// sum_k u_k (x) g_k over k = 1..6: V times the mean gradient of the field whose basis coefficients
// are u.
template <typename V>
LaneMatrix<typename V::Scalar> basis_gradient(const HexArray<V>& u, const HexArray<V>& g) {
  using S = typename V::Scalar;
  LaneMatrix<S> m = LaneMatrix<S>::zero();
  for (int k = 1; k < 7; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m.m[i][j] = m.m[i][j] + S(u[k][i]) * S(g[k][j]);
  return m;
}

// b_I and V of an element (for set-up and tests; the element loop stays in the basis).
struct HexGradient {
  HexVectors b;  // dV/dx_I
  Real volume = 0;
};
HexGradient hex_gradient(const HexVectors& x);

// The characteristic length of the element's stable time step: the smaller of
// - V / (largest face area) (LS-DYNA, Radioss, LULESH; fem-contact.md §2.4), from the basis
//   coefficients: the face zeta = -1 is x = (a0 - a3) + (a1 - a5) xi + (a2 - a4) eta + (a6 - a7) xi eta,
//   whose area by its diagonals (exact for a plane face) is 4 |(a1 - a5) x (a2 - a4)|; the others alike;
// - 2 V / sqrt(lambda_max(S)), S = sum_k g_k g_k^T: the highest frequency of one free element of
//   uniform gradient with lumped masses rho V / 8 is omega^2 = 8 (lambda + 2 mu) lambda_max(G) / rho
//   with G = sum_I b_I b_I^T / V^2 = S / (8 V^2) (exact for nu = 0; docs/THEORY.md §10.2), so that
//   2 / omega = L / c with L = 1 / sqrt(2 lambda_max(G)). Both are the edge of a cube; a distorted
//   element (the corners of a disc meshed as a mapped square) is stiffer than its faces say (0.73
//   of V / A_max there), and the first alone let such a mesh blow up. lambda_max(S) is bounded by
//   S's largest absolute row sum (Gershgorin), exact for a brick.
template <typename V>
typename V::Scalar hex_characteristic_length(const HexArray<V>& a, const HexArray<V>& g,
                                             typename V::Scalar volume) {
  using S = typename V::Scalar;
  using std::abs, std::max, std::min, std::sqrt;
  LaneMatrix<S> stiffness = LaneMatrix<S>::zero();
  for (int k = 1; k < 7; ++k)
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) stiffness.m[i][j] = stiffness.m[i][j] + S(g[k][i]) * S(g[k][j]);
  S stiffest(0);
  for (const auto& row : stiffness.m) stiffest = max(stiffest, abs(row[0]) + abs(row[1]) + abs(row[2]));
  const auto face = [](const V& u, const V& w) {
    const V n = cross(u, w);
    return dot(n, n);
  };
  const S largest = max(max(max(face(a[1] - a[5], a[2] - a[4]), face(a[1] + a[5], a[2] + a[4])),  // zeta = -+1
                            max(face(a[2] - a[6], a[3] - a[5]), face(a[2] + a[6], a[3] + a[5]))),  // xi = -+1
                        max(face(a[1] - a[6], a[3] - a[4]), face(a[1] + a[6], a[3] + a[4])));     // eta = -+1
  return min(volume / (S(4) * sqrt(largest)), S(2) * volume / sqrt(stiffest));
}

// The 2 x 2 x 2 Gauss rule of the fully integrated element (ELFORM 2): the derivatives of the
// shape functions with respect to (xi, eta, zeta) at each point (weights are all 1).
struct HexGaussRule {
  std::array<std::array<Vec3, 8>, 8> dN;  // dN[g][I] = dN_I/d(xi, eta, zeta) at point g
};
const HexGaussRule& hex_gauss_rule();

// grad N_I at Gauss point g of the current element and det J there; det J <= 0 (an inverted
// point) leaves `grad` unset.
Real hex_point_gradients(const HexVectors& x, int g, HexVectors& grad);

}  // namespace spall::fem
