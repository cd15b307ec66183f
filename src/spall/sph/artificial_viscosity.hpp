#pragma once
// Monaghan's artificial viscosity (Monaghan 1992, Annu. Rev. Astron. Astrophys. 30:543):
//   Pi_ab = (-alpha c_ab mu_ab + beta mu_ab^2) / rho_ab  when v_ab . x_ab < 0, else 0,
//   mu_ab = h v_ab . x_ab / (r_ab^2 + (eta h)^2).
// Shared by the SPH solid and fluid formulations.
#include "spall/core/types.hpp"

namespace spall::sph {

struct ArtificialViscosity {
  Real alpha = 0.06;  // linear term (LS-DYNA *CONTROL_BULK_VISCOSITY Q2)
  Real beta = 1.5;    // quadratic term (Q1)
  Real eta = 0.1;     // keeps mu_ab finite as r -> 0: r^2 + (eta h)^2
};

}  // namespace spall::sph
