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
#include <array>

#include "spall/core/types.hpp"

namespace spall::fem {

// c_kI: the basis monomials 1, xi, eta, zeta, eta zeta, xi zeta, xi eta, xi eta zeta at node I.
inline constexpr int hex_basis[8][8] = {
    {1, 1, 1, 1, 1, 1, 1, 1},          {-1, 1, 1, -1, -1, 1, 1, -1},    {-1, -1, 1, 1, -1, -1, 1, 1},
    {-1, -1, -1, -1, 1, 1, 1, 1},      {1, 1, -1, -1, -1, -1, 1, 1},    {1, -1, -1, 1, -1, 1, 1, -1},
    {1, -1, 1, -1, 1, -1, 1, -1},      {-1, 1, -1, 1, 1, -1, 1, -1}};
// The hourglass base vectors Gamma_alpha (alpha = 0..3) are rows 4-7 of hex_basis.
inline constexpr int hourglass_modes = 4;

// Eight vectors per node or per basis monomial.
using HexVectors = std::array<Vec3, 8>;

// The basis coefficients a_k = (1/8) sum_I c_kI x_I of nodal vectors (a_0, the centroid, included),
// and back, x_I = sum_k c_kI a_k: each by a butterfly of 24 additions per component (the
// transform is a 3D Walsh-Hadamard transform with the nodes in LS-DYNA's order).
HexVectors hex_coefficients(const HexVectors& x);
HexVectors hex_nodal(const HexVectors& a);

// g_k = dV/da_k (k = 1..6; g_0 = g_7 = 0) and V, from the basis coefficients of the map. The
// uniform gradient is b_I = (1/8) sum_k c_kI g_k = hex_nodal(g / 8), and
// sum_I u_I (x) b_I = sum_k a_k(u) (x) g_k for any nodal field u.
struct HexVolumeGradient {
  HexVectors g;
  Real volume = 0;
};
HexVolumeGradient hex_volume_gradient(const HexVectors& a);

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
Real hex_characteristic_length(const HexVectors& a, const HexVectors& g, Real volume);

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
