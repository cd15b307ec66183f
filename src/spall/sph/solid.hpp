#pragma once
// Updated-Lagrangian SPH for elastic solids (Libersky & Petschek 1990; Gray, Monaghan & Swift
// 2001), the base of seed 000 §3-4:
//   continuity       d rho_a/dt = sum_b m_b (v_a - v_b) . grad_a W_ab
//   velocity grad.   L_a = sum_b (m_b / rho_b) (v_b - v_a) (x) grad_a W_ab
//   Hooke, Jaumann   dS/dt = 2G dev(D) + W S - S W
//   pressure         p = K (rho / rho_0 - 1)
//   momentum         m_a dv_a/dt = sum_b V_a V_b (sigma_a B_a^T + sigma_b B_b^T) grad_a W_ab
//                                  - sum_b m_a m_b Pi_ab grad_a W_ab
//                    (seed 000 eqs. 7-8 in a symmetric form that conserves linear momentum)
//   correction       B_a = (sum_b V_b (x_b - x_a) (x) grad_a W_ab)^-1 (Randles & Libersky 1996),
//                    applied to L and, by duality, to the force; B = I when switched off
//   viscosity        Pi_ab = (-alpha c_ab mu_ab + beta mu_ab^2) / rho_ab when v_ab . x_ab < 0 (Monaghan)
// One SPH formulation owns every SPH part; particles of different parts interact through the
// kernel, with each particle's own material.
#include <vector>

#include "spall/materials/elastic.hpp"
#include "spall/neighbors/verlet_list.hpp"
#include "spall/solver/formulation.hpp"
#include "spall/sph/artificial_viscosity.hpp"

namespace spall::sph {

// One SPH particle as the solver sets it up.
struct ParticleSetup {
  Index node = 0;
  Index material = 0;  // index into the material table
  Real smoothing_length = 0;  // LS-DYNA's h; the kernel support is 2h
};

class SolidFormulation final : public solver::Formulation {
 public:
  SolidFormulation(std::vector<materials::ElasticConstants> materials,
                   const std::vector<ParticleSetup>& particles, ArtificialViscosity viscosity,
                   const solver::NodeStore& nodes);

  const char* name() const override { return "SPH"; }
  void compute_forces(solver::NodeStore& nodes, Real dt) override;
  Real stable_time_step(const solver::NodeStore& nodes) const override;
  Power internal_power(std::span<const Vec3> v) const override;
  void add_fields(std::vector<io::output::PointField>& fields,
                  const solver::NodeStore& nodes) const override;
  Real max_wave_speed() const override;

  Index particle_count() const { return static_cast<Index>(node_.size()); }
  // Bytes held by the formulation's arrays and its neighbour list.
  std::size_t memory_bytes() const;
  const neighbors::NeighborList& neighbor_list() const { return verlet_.list(); }

 private:
  void gather_kinematics(const solver::NodeStore& nodes);
  void compute_rates();
  void update_state(Real dt);
  void compute_pair_forces();

  std::vector<materials::ElasticConstants> materials_;
  ArtificialViscosity viscosity_;

  // Per particle (structure of arrays).
  std::vector<Index> node_;
  std::vector<Index> material_;
  std::vector<Real> mass_;
  std::vector<Real> smoothing_length_;
  std::vector<Real> density_;
  std::vector<Real> pressure_;
  std::vector<Real> sound_speed_;
  std::vector<Mat3> deviatoric_stress_;
  std::vector<Mat3> gradient_correction_matrix_;  // B_a (identity without correction)
  std::vector<Mat3> corrected_stress_;            // sigma_a B_a^T, as the pair force uses it
  // Scratch of the current step.
  std::vector<Vec3> x_, v_;
  std::vector<Real> density_rate_;
  std::vector<Mat3> velocity_gradient_;
  std::vector<Vec3> force_;            // total internal force
  std::vector<Vec3> viscous_force_;    // its artificial-viscosity part

  bool gradient_correction_ = true;
  neighbors::VerletList verlet_;
  Real max_support_ = 0;
  bool list_built_ = false;
};

}  // namespace spall::sph
