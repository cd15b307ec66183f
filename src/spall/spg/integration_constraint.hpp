#pragma once
// A correction of the nodal gradient operator that makes direct nodal integration pass the patch
// test on irregular particles (THEORY §9.4). With D_JK the gradient of shape function K at
// particle J and V_J the nodal volumes, DNI reproduces a constant stress exactly only if the
// integration constraint sum_J V_J D_JK = 0 holds for every particle K whose support stays inside
// the body (Chen, Wu, Yoon & You 2001); on irregular particles it does not. The correction
// D' = D + C keeps what the operator already has:
//   - rows:    sum_K C_JK = 0 and sum_K C_JK (x) X_K = 0  (momentum, exact constant strain)
//   - columns: sum_J V_J (D_JK + C_JK) = 0 for interior K (the integration constraint)
// with C on the bonds as antisymmetric fluxes, V_J C_JK = c_JK = -c_KJ and
// V_J C_JJ = -sum_L c_JL. Of all such fluxes it takes the smallest (least squares), whose form is
//   c_JL = (lambda_J - lambda_L) + (mu_J + mu_L) (X_L - X_J)
// per gradient component, with lambda (interior particles only) and mu found by preconditioned
// conjugate residuals on the normal equations. The same D' serves the strain and the force (a
// Galerkin, energy-consistent pair). The solve is global and its conditioning worsens with the
// size of the body (smooth multipliers lambda = phi, mu = grad phi / 2 give fluxes of third order
// in the spacing, THEORY §9.4), so its iterations are capped:
// fully at set-up (the patch test), a few warm-started ones at each kernel update.
#include <cstdint>
#include <span>
#include <vector>

#include "spall/core/range_array.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/particle_share.hpp"
#include "spall/discretization/reach_share.hpp"
#include "spall/spg/bonds.hpp"

namespace spall::spg {

// The correction's fluxes, V_J C_JK = c_JK - (a_J + B_J (X_K - X_J)), the least-squares flux less
// the row's moment removal (row_moment_removal), on a usable bond (neither broken nor of an inactive
// particle; zero on the others), from values per particle: alpha_J = lambda_J - a_J and
// beta_J = mu_J - B_J of row J, lambda_K and mu_K of K, X the positions it was computed at. Per
// particle rather than per bond: 120 B a particle against 24 B a bond (some 24 of them).
inline Vec3 correction_flux(const Vec3& alpha_J, const Mat3& beta_J, const Vec3& X_J, const Vec3& lambda_K,
                            const Mat3& mu_K, const Vec3& X_K) {
  return alpha_J - lambda_K + (beta_J + mu_K) * (X_K - X_J);
}

// Under MPI each array holds the particles a rank reads (Part holds them; a checkpoint writes them
// in pieces), every particle's on one process.
struct IntegrationCorrection {
  RangeArray<Vec3> self;  // C_JJ = -sum_K C_JK
  RangeArray<Vec3> alpha;      // alpha_J of correction_flux
  RangeArray<Mat3> beta;       // beta_J
  RangeArray<Vec3> reference;  // X_J
  // The multipliers of the last solve, the start of the next one (the configuration changes little
  // between kernel updates; zero before the first), and lambda_K, mu_K of correction_flux.
  RangeArray<Vec3> lambda;  // component i: the divergence multiplier of gradient component i
  RangeArray<Mat3> mu;      // row i: the first-moment multipliers of gradient component i
  int iterations = 0;
  Real relative_residual = 0;  // of the normal equations, in the preconditioner's norm, the largest component's

  void checkpoint(Archive& a) { a(iterations, relative_residual); }
};

// Computes the correction for the bonds (broken bonds and bonds of inactive particles excluded)
// given the positions X of the reference configuration, the nodal volumes, which particles are
// interior (their integration constraint is imposed), which are active (inactive ones take no
// part), and the defect e_K = sum_J V_J D_JK of the uncorrected operator. At most max_iterations
// conjugate-residual iterations: the rows always keep zero sums and zero first moments (momentum,
// exact constant strain); only the integration constraint carries what the solve left.
// Under MPI (replicated state, docs/SCALING.md) a rank solves for its own particles (`own`, one
// stretch of them: the particles are in node order; `defect` and `interior` of those, `active` of
// those and their bond partners) and brings in the multipliers and preconditioned residual of
// their bond partners (`reach`, planned for the bonds) once an iteration and the partners' values
// of the correction at the end (the rest of the correction and of the multipliers is current on
// its own rank alone; `correction` must hold its own particles and their partners); the dot
// products are exact sums, so the result does not depend on the number of ranks or threads.
void correct_integration(const BondList& bonds, StretchView<Vec3> X, StretchView<Real> volume,
                         StretchView<std::uint8_t> interior, StretchView<std::uint8_t> active,
                         StretchView<Vec3> defect, int max_iterations, parallel::Range own,
                         const discretization::ParticleShare& share, const discretization::ReachShare& reach,
                         IntegrationCorrection& correction);

}  // namespace spall::spg
