#pragma once
// Oscillating cantilever plate (Gray, Monaghan & Swift 2001, CMAME 190:6641; the SPHinXsys and
// PySPH set-up of reference/validation.md §2), 2D plane strain (*CONTROL_SPH IDIM 2):
// L = 0.2 m, H = 0.02 m, rho = 1000 kg/m^3, E = 2 MPa, nu = 0.3975, clamped by holding every
// particle of a 0.06 m root (x < 0) with *BOUNDARY_SPC_SET. The free part starts with the first
// cantilever mode shape as velocity,
//   v_y(x) = V_f c0 [M (cos kx - cosh kx) - N (sin kx - sinh kx)] / Q,  kL = 1.875,
// M = sin kL + sinh kL, N = cos kL + cosh kL, Q = 2 (cos kL sinh kL - sin kL cosh kL),
// c0 = sqrt(K / rho), and swings with the thin-plate period T = 2 pi / omega,
//   omega^2 = E H^2 k^4 / (12 rho (1 - nu^2))  ->  T = 0.2540 s.
// The period is read from the tip's vertical displacement: it starts at zero moving up, crosses
// zero going down near T/2 and going up near T.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "spall/solver/simulation.hpp"

namespace spall::test_support {

struct OscillatingPlate {
  int layers = 10;                 // particles across the thickness H
  Real velocity_factor = 0.01;     // V_f
  bool artificial_stress = false;  // Monaghan's, epsilon 0.3, n 4 (Gray et al.)
  Real end_time = 0.3;
};

constexpr Real plate_length = 0.2, plate_thickness = 0.02, plate_clamp = 0.06;
constexpr Real plate_density = 1000, plate_young = 2.0e6, plate_poisson = 0.3975;
constexpr Real plate_mode_kl = 1.875;  // first root of cos kL cosh kL = -1, to four digits

inline Real thin_plate_period() {
  const Real k = plate_mode_kl / plate_length;
  const Real omega2 = plate_young * plate_thickness * plate_thickness * std::pow(k, 4) /
                      (12 * plate_density * (1 - plate_poisson * plate_poisson));
  return 2 * M_PI / std::sqrt(omega2);
}

// The model and the ID of the particle at the middle of the free end.
inline model::Model oscillating_plate_model(const OscillatingPlate& p, Id& tip) {
  const Real dx = plate_thickness / p.layers;
  model::Model m;
  m.parts.push_back({1, "plate", 1, 1, 0, 0, 0, {}, {}});
  model::SectionSph section;
  section.id = 1;
  section.cslh = 1.3;
  m.sections[1] = section;
  model::Material mat;
  mat.id = 1;
  mat.keyword = "*MAT_ELASTIC";
  mat.params = model::MatElastic{plate_density, plate_young, plate_poisson, 0, 0};
  m.materials[1] = mat;
  if (p.artificial_stress) m.sph_artificial_stress = model::SphArtificialStress{};
  model::ControlSph control;
  control.idim = 2;
  m.control_sph = control;
  model::ControlTermination term;
  term.endtim = p.end_time;
  m.termination = term;

  const Real bulk = plate_young / (3 * (1 - 2 * plate_poisson));
  const Real c0 = std::sqrt(bulk / plate_density);
  const Real kl = plate_mode_kl, k = kl / plate_length;
  const Real M = std::sin(kl) + std::sinh(kl), N = std::cos(kl) + std::cosh(kl);
  const Real Q = 2 * (std::cos(kl) * std::sinh(kl) - std::sin(kl) * std::cosh(kl));
  model::NodeSet clamped;
  clamped.id = 1;
  const int nx = static_cast<int>(std::lround((plate_length + plate_clamp) / dx));
  Id id = 1;
  Real best = 1e30;
  for (int j = 0; j < p.layers; ++j)
    for (int i = 0; i < nx; ++i, ++id) {
      const Vec3 x(-plate_clamp + (i + 0.5) * dx, (j + 0.5) * dx - plate_thickness / 2, 0);
      m.nodes.push_back({id, x, 0, 0, {}});
      m.sph_elements.push_back({id, 1, plate_density * dx * dx, {}});  // mass per unit thickness
      if (x.x() < 0) {
        clamped.nodes.push_back(id);
      } else {
        const Real kx = k * x.x();
        model::InitialVelocityNode iv;
        iv.nid = id;
        iv.v =
            Vec3(0,
                 p.velocity_factor * c0 *
                     (M * (std::cos(kx) - std::cosh(kx)) - N * (std::sin(kx) - std::sinh(kx))) / Q,
                 0);
        m.initial_velocity_nodes.push_back(iv);
      }
      const Real distance = std::abs(x.x() - plate_length) + std::abs(x.y());
      if (distance < best) best = distance, tip = id;
    }
  m.node_sets[1] = clamped;
  model::Spc spc;
  spc.target = model::Target::node_set;
  spc.id = 1;
  spc.dof = {true, true, true, false, false, false};
  m.spcs.push_back(spc);
  return m;
}

// Times at which the tip's vertical displacement changes sign, interpolated linearly between
// steps.
inline std::vector<Real> tip_zero_crossings(const OscillatingPlate& p) {
  Id tip = 0;
  const model::Model model = oscillating_plate_model(p, tip);
  solver::Problem problem = solver::build_problem(model);
  Index tip_index = 0;
  while (problem.nodes.id[tip_index] != tip) ++tip_index;
  problem.controls.glstat_dt = 1e-30;  // every step
  std::vector<Real> crossings;
  Real previous_t = 0, previous_u = 0;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo& s, const discretization::EnergyLedger&) {
    const Real u = problem.nodes.x[tip_index].y() - problem.nodes.x0[tip_index].y();
    if (s.step > 0 && previous_u * u < 0)
      crossings.push_back(previous_t + (s.time - previous_t) * previous_u / (previous_u - u));
    previous_t = s.time;
    previous_u = u;
  };
  solver::run(problem, observer);
  return crossings;
}

}  // namespace spall::test_support
