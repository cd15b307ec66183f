#pragma once
// Reproducing-kernel (RK) shape functions with a linear basis at one evaluation point x
// (Chen, Pan, Wu & Liu 1996; spg.md §2.1):
//   Psi_I(x) = b(x)^T H(x - x_I) phi_I(x - x_I),   M(x) b(x) = H(0),
//   M(x) = sum_I H(x - x_I) H(x - x_I)^T phi_I(x - x_I),   H(y) = [1, y_x / s_x, y_y / s_y, y_z / s_z],
// (the basis scaled per direction by s, the evaluation point's support sizes, so that the pivot
// ratio measures the particles' arrangement, not the window's aspect ratio; the functions do not
// depend on s) and the gradient from differentiating b through M b_,j = -M_,j b:
//   Psi_I,j = b_,j^T H phi + b^T H_,j phi + b^T H phi_,j.
// Sum_I Psi_I = 1 and sum_I Psi_I x_I = x hold to round-off, and so do their gradients.
#include <span>

#include "spall/core/types.hpp"
#include "spall/spg/kernel_function.hpp"

namespace spall::spg {

// One particle I seen from the evaluation point: y = x - x_I, its support sizes a_I, and the map
// applied to y before the window is evaluated (identity, or F_I^-1 for a window that deforms with
// the material), so that phi_I = phi(map y; a_I).
struct KernelSample {
  Vec3 y = Vec3::Zero();
  Vec3 support = Vec3::Ones();
  Mat3 map = Mat3::Identity();
};

// Below this ratio of the smallest to the largest pivot of the scaled moment matrix, the particles
// in the support do not determine a linear field well (fewer than four, nearly all in one plane):
// healthy rows have 0.02 and more, and rows left between 1e-8 and this by bond failure blew up
// under the friction drill (THEORY §9.8).
inline constexpr Real min_moment_rcond = 1e-3;

// Fills psi[k] = Psi_k(x) and grad[k] = grad Psi_k(x) for every sample. Returns the pivot ratio
// of the scaled moment matrix (a reciprocal-condition indicator); below min_moment_rcond the outputs are not
// meaningful (see shepard_shape_functions). `scale` is s in the basis.
Real rk_shape_functions(KernelShape shape, std::span<const KernelSample> samples, const Vec3& scale,
                        std::span<Real> psi, std::span<Vec3> grad);

// The zeroth-order (Shepard) functions Psi_I = phi_I / sum phi and their gradients: a partition of
// unity without linear reproduction, for an evaluation point whose supports no longer hold a
// linear field (a particle left with too few bonds after bond failure). Returns false when no
// window reaches x at all.
bool shepard_shape_functions(KernelShape shape, std::span<const KernelSample> samples,
                             std::span<Real> psi, std::span<Vec3> grad);

}  // namespace spall::spg
