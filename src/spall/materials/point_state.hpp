#pragma once
// What a material point carries from one step to the next.
#include "spall/core/archive.hpp"
#include "spall/core/types.hpp"

namespace spall::materials {

// x^p taken by pow at x = base (base -1: none taken yet), the anchor from which the next steps'
// powers follow by a short series while x stays near it (johnson_cook.cpp).
struct PowerAnchor {
  Real base = -1;
  Real power = 0;
};

struct PointState {
  Mat3 deviatoric_stress = Mat3::Zero();  // S, the deviator of the Cauchy stress
  // The back stress alpha of kinematic hardening (MAT_003 BETA < 1) is not here: only those points
  // keep one, in an array of their formulation (materials::keeps_back_stress), 72 bytes a point
  // that every other point would carry.
  Real plastic_strain = 0;                // effective plastic strain
  Real temperature = 0;                   // MAT_015: starts at TR, rises by adiabatic heating
  Real damage = 0;                        // MAT_015 Johnson-Cook damage D; fails at 1
  PowerAnchor strain_power;               // MAT_015: eps_p^N
  PowerAnchor temperature_power;          // MAT_015: T*^M
  bool failed = false;                    // no deviatoric stress and no tension from now on
};

}  // namespace spall::materials

namespace spall {
template <>
inline constexpr bool archived_as_bytes<materials::PointState> = true;
}  // namespace spall
