#pragma once
// A material as the solvers use it, and the update of one material point per step: the strength
// model gives the deviatoric stress, the equation of state the pressure, the tensile limit caps
// tension. Pure functions of their arguments, with no solver dependencies, so that the SPH solid
// and the SPG formulation call the same code per particle or integration point.
//
// A step for one point (advance_point does all four; the SPH solid does them apart, because its
// energy equation uses the stress its pair forces passed on, docs/THEORY.md §3):
//   1. rotate state.deviatoric_stress and the back stress by its objective rate over dt
//      (Jaumann: + dt (W S - S W));
//   2. {p, w} = update_stress(material, state, D, dt, rho, e)   (D = sym(grad v) of the step);
//   3. Cauchy stress sigma = state.deviatoric_stress - p I;
//   4. integrate its energy equation de/dt = sigma : D / rho (e per unit mass; the plastic work w
//      is part of it), and take sound_speed(material, rho, e) for the time step.
// initial_state() and Material::initial_specific_energy give the start of the run.
#include <variant>
#include <vector>

#include "spall/materials/eos.hpp"
#include "spall/materials/johnson_cook.hpp"
#include "spall/materials/piecewise_linear.hpp"
#include "spall/materials/plastic_kinematic.hpp"
#include "spall/materials/point_state.hpp"

namespace spall::materials {

// *MAT_ELASTIC: Hooke's law for the deviator, S += 2G dt dev(D).
struct Elastic {};

// *MAT_NULL: no strength. With a viscosity MU > 0 the deviator is the viscous stress
// S = 2 MU dev(D) of the step (replacing, not adding to, the previous one).
struct Null {
  Real viscosity = 0;
};

using Strength = std::variant<Elastic, PlasticKinematic, PiecewiseLinear, JohnsonCook, Null>;

// How tension is limited (LS-DYNA: MAT_NULL PC; MAT_015 SPALL and PC).
enum class TensileLimit {
  none,
  pressure_cutoff,     // p >= PC (MAT_NULL; MAT_015 SPALL 1)
  principal_stress,    // MAT_015 SPALL 2: the point spalls when sigma_max >= -PC
  hydrostatic_tension  // MAT_015 SPALL 3: the point spalls when p <= PC
};

struct Material {
  Real density = 0;        // rho0, the reference density (RO)
  Real shear_modulus = 0;  // G (0 for MAT_NULL)
  Strength strength = Elastic{};
  EquationOfState eos = LinearBulk{};
  TensileLimit tensile_limit = TensileLimit::none;
  Real pressure_cutoff = 0;          // PC, <= 0
  Real initial_specific_energy = 0;  // e0 = E0 / rho0 from the EOS card
  Real initial_temperature = 0;      // MAT_015: TR
};

// The state of a point at the start of the run: no stress, TR for MAT_015.
PointState initial_state(const Material& material);

struct StressUpdate {
  Real pressure = 0;      // p, compression positive, after the tensile limit
  Real plastic_work = 0;  // sigma : d(eps^p) of the step, per unit current volume
  Real sound_speed = 0;   // sound_speed(material, rho, e) at the update's rho and e, from its EOS call
};

// One step of a material point, in this order: the EOS pressure at the new density and energy;
// the deviatoric update (elastic predictor, return mapping, hardening, heating and damage, which
// uses that pressure); then the tensile limit and failure (a failed point keeps no deviatoric
// stress and no tension: S = 0, p >= 0).
// `back_stress` (here and below): the point's back stress where keeps_back_stress(material), else
// null.
StressUpdate update_stress(const Material& material, PointState& state, const Mat3& strain_rate,
                           Real dt, Real density, Real specific_energy, Mat3* back_stress = nullptr);

// The state of a point besides its PointState: what the energy equation and the time step carry.
struct PointThermo {
  Real specific_energy = 0;  // e, per unit mass
  Real pressure = 0;         // p after the tensile limit
  Real sound_speed = 0;      // sound_speed(material, rho, e) at the step's end
};

// Steps 1-4 above over dt for a point with velocity gradient L (at the middle of the step) and
// density rho at the step's end: the Jaumann rotation by W = skew(L) (jaumann_rotation, the SPH
// solid's too), update_stress with D = sym(L), and the energy equation by the trapezoidal rule in
// the stress (the old stress predicting the energy the EOS sees). The one point update of SPG
// particles and finite elements' integration points. Returns the plastic work of the step per
// unit volume.
Real advance_point(const Material& material, PointState& state, PointThermo& thermo, const Mat3& L, Real dt,
                   Real density, Mat3* back_stress = nullptr);

// The three parts of update_stress, for callers and tests that need them apart.
Real eos_pressure(const Material& material, Real density, Real specific_energy);
// Returns the plastic work per unit volume. `pressure` is used by the Johnson-Cook damage only.
Real update_deviatoric_stress(const Material& material, PointState& state, const Mat3& strain_rate,
                              Real dt, Real density, Real pressure, Mat3* back_stress = nullptr);
// Returns the pressure to use; may mark the point failed (spall) and then clears its deviator.
Real apply_tensile_limit(const Material& material, PointState& state, Real pressure, Mat3* back_stress = nullptr);

// Whether the material's points keep a back stress (MAT_003 with BETA < 1): their formulation
// holds one a point and passes it to the updates above.
bool keeps_back_stress(const Material& material);
// Point i's back stress in a formulation's array of them, null where the array is empty (no
// material of the formulation keeps one).
template <typename Array>
Mat3* kept_back_stress(Array& back_stress, Index i) {
  return back_stress.empty() ? nullptr : &back_stress[i];
}

// Whether the point failed in a way that deletes a finite element (LS-DYNA): the plastic strain
// reached *MAT_003 FS or *MAT_024 FAIL, or the Johnson-Cook damage reached 1 with EROD 0. (Spall
// and particles keep their points: a failed point carries no deviator and no tension.)
bool erodes_element(const Material& material, const PointState& state);

// sigma_1, the largest eigenvalue of a symmetric stress.
Real max_principal_stress(const Mat3& sigma);

// The yield stress at the point's plastic strain and temperature without the strain-rate term
// (the quasi-static flow stress a residual stress is compared with); infinity for materials
// without yield (*MAT_ELASTIC), 0 for *MAT_NULL.
Real static_yield_stress(const Material& material, const PointState& state);

// sqrt((K_s + 4G/3) / rho), K_s the isentropic bulk modulus of the EOS at (rho, e) (never below
// 0): the longitudinal wave speed that bounds the explicit time step.
Real sound_speed(const Material& material, Real density, Real specific_energy);

}  // namespace spall::materials
