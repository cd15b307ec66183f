#pragma once
// The quantity a bond's failure is judged on (*SECTION_SOLID_SPG IDAM; reference/spg.md §3-5).
// Seed 001 eq. 14 (IDAM 1): bond K-J breaks when the bond average (q_K + q_J) / 2 of the particles'
// effective plastic strain exceeds FS and the bond's stretch exceeds STRETCH. The manual lists
// other quantities under the same rule; Spall reads IDAM 2 and 3 with the same averaging and the
// same stretch test [reconstructed: the manual names the quantity only]:
//   IDAM 2  maximum principal Cauchy stress sigma_1,
//   IDAM 3  maximum (tensorial) shear strain (eps_1 - eps_3) / 2 of the logarithmic strain
//           eps = ln V, V the left stretch of the deformation gradient from the initial
//           configuration (F = V R).
#include "spall/core/types.hpp"

namespace spall::spg {

enum class BondFailure { plastic_strain = 1, principal_stress = 2, shear_strain = 3 };

// sigma_1 of a symmetric stress.
Real max_principal_stress(const Mat3& sigma);

// (eps_1 - eps_3) / 2 with eps_i = ln lambda_i, lambda_i^2 the eigenvalues of b = F F^T.
Real max_shear_strain(const Mat3& F);

}  // namespace spall::spg
