#pragma once
// Nodal volumes of SPG particles from the solid mesh they are built on (spg.md §6: lumped mass
// M_I = rho_0 V_I). Each corner a of a trilinear hexahedron gets V_a = integral of N_a dV, the
// row sum of the consistent mass matrix divided by rho: V / 8 for a parallelepiped, and the right
// share for a distorted or degenerate (wedge, pyramid: repeated nodes) element, whose repeated
// corners simply add up. 2 x 2 x 2 Gauss points integrate N_a det J exactly (degree at most 3 in
// each local coordinate). LS-DYNA's tetrahedron N1 N2 N3 N4 N4 N4 N4 N4 is the linear tetrahedron
// of its four corners (a quarter each), not the trilinear image of that node list.
#include <array>

#include "spall/core/types.hpp"

namespace spall::spg {

// LS-DYNA node order: N1..N4 the bottom face, N5..N8 the top face above them.
using HexCorners = std::array<Vec3, 8>;

struct HexVolumes {
  std::array<Real, 8> corner{};  // integral of N_a dV per corner
  Real total = 0;
  Real min_jacobian = 0;  // smallest det J at the Gauss points (<= 0: inverted or flat)
};

HexVolumes hex_volumes(const HexCorners& x);

}  // namespace spall::spg
