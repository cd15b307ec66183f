#include "spall/materials/material.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Eigenvalues>

#include "spall/materials/elastic.hpp"
#include "spall/materials/radial_return.hpp"

namespace spall::materials {

PointState initial_state(const Material& material) {
  PointState state;
  state.temperature = material.initial_temperature;
  return state;
}

Real eos_pressure(const Material& material, Real density, Real specific_energy) {
  return evaluate_eos(material.eos, material.density, density, specific_energy).pressure;
}

Real update_deviatoric_stress(const Material& material, PointState& state, const Mat3& strain_rate,
                              Real dt, Real density, Real pressure, Mat3* back_stress) {
  Real work = 0;
  if (!state.failed) {
    const Real g = material.shear_modulus;
    struct Visitor {
      PointState& state;
      const Mat3& d;
      Real dt, density, pressure, g;
      Mat3* back_stress;
      Real operator()(const Elastic&) const {
        state.deviatoric_stress += 2 * g * dt * deviator(d);
        return 0;
      }
      Real operator()(const PlasticKinematic& m) const {
        return update_plastic_kinematic(m, g, state, d, dt, back_stress);
      }
      Real operator()(const PiecewiseLinear& m) const {
        return update_piecewise_linear(m, g, state, d, dt);
      }
      Real operator()(const JohnsonCook& m) const {
        return update_johnson_cook(m, g, state, d, dt, density, pressure);
      }
      Real operator()(const Null& m) const {
        state.deviatoric_stress = 2 * m.viscosity * deviator(d);
        return 0;
      }
    };
    work = std::visit(Visitor{state, strain_rate, dt, density, pressure, g, back_stress}, material.strength);
  }
  if (state.failed) {
    state.deviatoric_stress.setZero();
    if (back_stress) back_stress->setZero();
  }
  return work;
}

Real apply_tensile_limit(const Material& material, PointState& state, Real pressure, Mat3* back_stress) {
  switch (material.tensile_limit) {
    case TensileLimit::none:
      break;
    case TensileLimit::pressure_cutoff:
      pressure = std::max(pressure, material.pressure_cutoff);
      break;
    case TensileLimit::principal_stress: {
      if (state.failed) break;
      // A deviator's largest eigenvalue is at most sqrt(2/3) |s| (s_2 = s_3 = -s_1 / 2): the
      // eigen-solve only where that bound reaches -PC.
      const Real bound = std::sqrt(Real(2) / 3 * state.deviatoric_stress.squaredNorm()) - pressure;
      if (bound >= -material.pressure_cutoff &&
          max_principal_stress(state.deviatoric_stress - pressure * Mat3::Identity()) >= -material.pressure_cutoff)
        state.failed = true;
      break;
    }
    case TensileLimit::hydrostatic_tension:
      if (pressure <= material.pressure_cutoff) state.failed = true;
      break;
  }
  if (state.failed) {
    state.deviatoric_stress.setZero();
    if (back_stress) back_stress->setZero();
    pressure = std::max(pressure, Real(0));
  }
  return pressure;
}

namespace {
// sqrt((K_s + 4G/3) / rho) from an EOS evaluation at rho.
Real longitudinal_wave_speed(const Material& material, const EosValue& eos, Real density) {
  const Real bulk = std::max(isentropic_bulk_modulus(eos, density), Real(0));
  return std::sqrt((bulk + Real(4) / 3 * material.shear_modulus) / density);
}
}  // namespace

StressUpdate update_stress(const Material& material, PointState& state, const Mat3& strain_rate,
                           Real dt, Real density, Real specific_energy, Mat3* back_stress) {
  const EosValue eos = evaluate_eos(material.eos, material.density, density, specific_energy);
  const Real work = update_deviatoric_stress(material, state, strain_rate, dt, density, eos.pressure, back_stress);
  return {apply_tensile_limit(material, state, eos.pressure, back_stress), work,
          longitudinal_wave_speed(material, eos, density)};
}

Real advance_point(const Material& material, PointState& state, PointThermo& thermo, const Mat3& L, Real dt,
                   Real density, Mat3* back_stress) {
  const Mat3 D = Real(0.5) * (L + L.transpose());
  const Mat3 sigma_old = state.deviatoric_stress - thermo.pressure * Mat3::Identity();
  state.deviatoric_stress += dt * jaumann_rotation(L, state.deviatoric_stress);
  if (back_stress) *back_stress += dt * jaumann_rotation(L, *back_stress);
  const Real e_predicted = thermo.specific_energy + dt * sigma_old.cwiseProduct(D).sum() / density;
  const StressUpdate update = update_stress(material, state, D, dt, density, e_predicted, back_stress);
  const Mat3 sigma = state.deviatoric_stress - update.pressure * Mat3::Identity();
  thermo.specific_energy += Real(0.5) * dt * (sigma_old + sigma).cwiseProduct(D).sum() / density;
  thermo.pressure = update.pressure;
  thermo.sound_speed = sound_speed(material, density, thermo.specific_energy);
  return update.plastic_work;
}

Real max_principal_stress(const Mat3& sigma) {
  Eigen::SelfAdjointEigenSolver<Mat3> solver;
  solver.computeDirect(sigma, Eigen::EigenvaluesOnly);
  return solver.eigenvalues().maxCoeff();
}

bool keeps_back_stress(const Material& material) {
  const auto* m = std::get_if<PlasticKinematic>(&material.strength);
  return m != nullptr && moves_back_stress(*m);
}

bool erodes_element(const Material& material, const PointState& state) {
  if (const auto* m = std::get_if<PlasticKinematic>(&material.strength))
    return m->failure_strain > 0 && state.plastic_strain >= m->failure_strain;
  if (const auto* m = std::get_if<PiecewiseLinear>(&material.strength))
    return m->failure_strain > 0 && state.plastic_strain >= m->failure_strain;
  if (const auto* m = std::get_if<JohnsonCook>(&material.strength))
    return m->erode_at_failure && m->damage() && state.damage >= 1;
  return false;
}

Real static_yield_stress(const Material& material, const PointState& state) {
  struct Visitor {
    const PointState& state;
    Real operator()(const Elastic&) const { return std::numeric_limits<Real>::infinity(); }
    Real operator()(const Null&) const { return 0; }
    // Isotropic part of the yield radius; the back stress moves the surface, not its size.
    Real operator()(const PlasticKinematic& m) const {
      return m.yield_stress + m.beta * m.hardening_modulus * state.plastic_strain;
    }
    Real operator()(const PiecewiseLinear& m) const { return m.curve.at(state.plastic_strain).stress; }
    Real operator()(const JohnsonCook& m) const {
      return johnson_cook_flow_stress(m, state.plastic_strain, 0, state.temperature);
    }
  };
  return std::visit(Visitor{state}, material.strength);
}

Real sound_speed(const Material& material, Real density, Real specific_energy) {
  return longitudinal_wave_speed(material, evaluate_eos(material.eos, material.density, density, specific_energy),
                                 density);
}

}  // namespace spall::materials
