#pragma once
// An SPG cantilever under its own weight (a uniform line load q = rho g A), clamped at x = 0 (every
// node of the root face held), brought to rest by *DAMPING_GLOBAL at twice the first bending
// frequency. Beam theory with the shear term (Timoshenko) for a uniformly loaded cantilever:
//   tip deflection = q L^4 / (8 E I) + q L^2 / (2 kappa G A),  kappa = 10 (1 + nu) / (12 + 11 nu)
// (Timoshenko & Gere, Mechanics of Materials; kappa for a rectangle after Cowper 1966), first
// bending frequency omega_1 = 1.875^2 sqrt(E I / (rho A L^4)).
#include <cmath>

#include "spall/solver/simulation.hpp"
#include "support/spg_block.hpp"

namespace spall::test_support {

struct Cantilever {
  Real length = 0.5, width = 0.05, thickness = 0.1;
  int along = 20, across = 2, through = 4;  // elements along x, y (width), z (thickness)
  Real gravity = 1000;                      // m/s^2: 0.4 mm of tip deflection, well linear
  Real periods = 2.5;                       // of the first bending mode
  Real density = 7850, young = 200e9, poisson = 0.3;
  std::optional<FiniteElements> fem;  // the beam as finite elements instead of SPG
};

struct CantileverResult {
  Real tip_deflection = 0;  // mean over the tip face, downwards positive
  Real tip_speed = 0;       // largest at the end: the beam is at rest
  Real bending = 0, shear = 0;
  Real trapezoid_inertia_ratio = 1;  // I of the trapezoidal rule through the thickness over I
  long long steps = 0;
  Real internal_energy = 0, hourglass_energy = 0;  // at the end
};

inline CantileverResult run_cantilever(const Cantilever& c) {
  const Real A = c.width * c.thickness;
  const Real I = c.width * std::pow(c.thickness, 3) / 12;
  const Real G = c.young / (2 * (1 + c.poisson));
  const Real kappa = 10 * (1 + c.poisson) / (12 + 11 * c.poisson);
  const Real q = c.density * c.gravity * A;
  const Real omega1 = 1.875 * 1.875 * std::sqrt(c.young * I / (c.density * A * std::pow(c.length, 4)));
  SpgBlock b;
  b.size = Vec3(c.length, c.width, c.thickness);
  b.elements = {c.along, c.across, c.through};
  b.density = c.density;
  b.young = c.young;
  b.poisson = c.poisson;
  b.end_time = c.periods * 2 * M_PI / omega1;
  b.fem = c.fem;
  model::Model m = spg_block_model(b);
  model::Curve one;
  one.id = 1;
  one.points = {{0.0, 1.0}, {1.0e3, 1.0}};
  m.curves[1] = one;
  model::BodyLoad load;
  load.direction = 2;
  load.lcid = 1;
  load.sf = c.gravity;  // LS-DYNA: a positive LOAD_BODY_Z pulls towards -z
  m.body_loads.push_back(load);
  for (const auto& node : m.nodes)
    if (node.x.x() == 0) {
      model::Spc spc;
      spc.id = node.id;
      spc.dof = {true, true, true, false, false, false};
      m.spcs.push_back(spc);
    }
  model::DampingGlobal damping;
  damping.valdmp = 2 * omega1;
  m.damping_global = damping;
  solver::Problem p = solver::build_problem(m);
  CantileverResult r;
  const solver::RunSummary summary = solver::run(p, {});
  r.steps = summary.steps;
  r.internal_energy = summary.energies.internal();
  r.hourglass_energy = summary.energies.value(discretization::EnergyLedger::hourglass_energy);
  int count = 0;
  for (Index i = 0; i < p.nodes.size(); ++i)
    if (p.nodes.x0[i].x() == c.length) {
      r.tip_deflection -= p.nodes.x[i].z() - p.nodes.x0[i].z();
      r.tip_speed = std::max(r.tip_speed, p.nodes.v[i].norm());
      ++count;
    }
  r.tip_deflection /= count;
  r.bending = q * std::pow(c.length, 4) / (8 * c.young * I);
  r.shear = q * c.length * c.length / (2 * kappa * G * A);
  // Nodal integration samples the thickness at the particle layers with half volumes on the
  // surfaces: the trapezoidal rule, whose second moment of a section of n layers is
  // I (1 + 2 / n^2).
  r.trapezoid_inertia_ratio = 1 + 2.0 / (c.through * c.through);
  return r;
}

}  // namespace spall::test_support
