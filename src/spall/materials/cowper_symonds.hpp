#pragma once
// Cowper-Symonds strain-rate scaling of the yield stress (MAT_003 SRC/SRP, MAT_024 C/P):
//   sigma_y(rate) = sigma_y,static [1 + (rate / C)^(1/P)],
// with C = 0 meaning no rate effect (LS-DYNA keyword manual, *MAT_PLASTIC_KINEMATIC).
#include <cmath>

#include "spall/core/types.hpp"

namespace spall::materials {

struct CowperSymonds {
  Real c = 0;
  Real p = 0;

  // Whether the rate scales the yield stress at all (a caller can then skip the rate).
  bool active() const { return c > 0; }
  Real factor(Real strain_rate) const {
    return active() ? 1 + std::pow(strain_rate / c, 1 / p) : Real(1);
  }
};

}  // namespace spall::materials
