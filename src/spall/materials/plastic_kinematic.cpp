#include "spall/materials/plastic_kinematic.hpp"

#include <stdexcept>

#include "spall/materials/elastic.hpp"
#include "spall/materials/radial_return.hpp"

namespace spall::materials {

Real update_plastic_kinematic(const PlasticKinematic& model, Real shear_modulus, PointState& state,
                              const Mat3& strain_rate, Real dt, Mat3* back_stress) {
  if (back_stress == nullptr && moves_back_stress(model))
    throw std::logic_error("update_plastic_kinematic: kinematic hardening without the point's back stress");
  const Mat3 trial = state.deviatoric_stress + 2 * shear_modulus * dt * deviator(strain_rate);
  const Mat3 relative = back_stress ? Mat3(trial - *back_stress) : trial;
  const Real q = von_mises(relative);
  const Real rate_factor = model.rate.active() ? model.rate.factor(effective_strain_rate(strain_rate)) : Real(1);
  const Real isotropic_modulus = model.beta * model.hardening_modulus;
  const Real kinematic_modulus = (1 - model.beta) * model.hardening_modulus;
  const auto yield = [&](Real dp) {
    return YieldValue{
        rate_factor * (model.yield_stress + isotropic_modulus * (state.plastic_strain + dp)),
        rate_factor * isotropic_modulus};
  };
  if (q <= yield(0).stress) {
    state.deviatoric_stress = trial;
    return 0;
  }
  const Real dp = plastic_strain_increment(q, 3 * shear_modulus + kinematic_modulus, yield);
  const Mat3 direction = relative / q;  // von_mises(direction) = 1
  state.deviatoric_stress = trial - 3 * shear_modulus * dp * direction;
  if (back_stress) *back_stress += kinematic_modulus * dp * direction;
  state.plastic_strain += dp;
  // d(eps^p) = 3/2 dp xi / q
  const Real work = Real(1.5) * dp * state.deviatoric_stress.cwiseProduct(direction).sum();
  if (model.failure_strain > 0 && state.plastic_strain >= model.failure_strain) state.failed = true;
  return work;
}

}  // namespace spall::materials
