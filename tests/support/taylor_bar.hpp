#pragma once
// The Taylor bar of Wilkins & Guinan 1973 (J. Appl. Phys. 44:1200), test 1: an OFHC copper rod,
// L0 = 23.47 mm, D0 = 7.62 mm, hitting a rigid wall at 210 m/s; Johnson & Cook's (1983) copper
// constants (reference/validation.md §1(b)). SI units. Built in code for the verification test and
// the benchmark; examples/taylor_bar has the same scene as a deck. As SPH particles on a lattice,
// or (elform 1 or 2) as hexahedra: a square grid mapped onto the disc, extruded.
#include <cmath>
#include <cstdio>

#include "spall/model/model.hpp"
#include "spall/solver/simulation.hpp"

namespace spall::test_support {

struct TaylorBar {
  Real length = 23.47e-3, diameter = 7.62e-3, speed = 210;
  int particles_across = 10;  // lattice spacing D0 / particles_across
  Real end_time = 80e-6;
  Real cslh = 1.2;
  // The physics of bench/peers/lammps_smd_taylor_bar.in (LAMMPS SMD's smd/ulsph), for a speed
  // comparison that does the same work per pair and particle: plain SPH (*CONTROL_SPH FORM 0, no
  // gradient correction), J2 plasticity with linear hardening (*MAT_PLASTIC_KINEMATIC: G 46 GPa,
  // K = rho c0^2 with c0 3940 m/s, yield 90 MPa, hardening modulus 0.3 GPa) in place of
  // Johnson-Cook, and the plain step h / (c + |v|) that LAMMPS' smd/adjust_dt scales
  // (*SPALL_SPH_TIMESTEP RULE 1, which needs no row sums of the gradient operator). Not the
  // Wilkins & Guinan test: the verification test leaves it off.
  bool peer_physics = false;
  int elform = 0;  // 0: SPH particles; 1 or 2: solid finite elements of that ELFORM
};

// The rod as hexahedra: n x n elements across (a square grid mapped onto the disc by
// (u, v) -> R (u sqrt(1 - v^2 / 2), v sqrt(1 - u^2 / 2))), layers of about the same height.
inline void add_rod_hexahedra(model::Model& m, const TaylorBar& bar) {
  const int n = bar.particles_across;
  const int layers = static_cast<int>(std::lround(bar.length / (bar.diameter / n)));
  const Real radius = bar.diameter / 2;
  const auto id = [&](int i, int j, int k) { return Id(1 + i + (n + 1) * (j + (n + 1) * k)); };
  for (int k = 0; k <= layers; ++k)
    for (int j = 0; j <= n; ++j)
      for (int i = 0; i <= n; ++i) {
        const Real u = 2.0 * i / n - 1, v = 2.0 * j / n - 1;
        const Vec3 x(radius * u * std::sqrt(1 - v * v / 2), radius * v * std::sqrt(1 - u * u / 2),
                     bar.length * k / layers);
        m.nodes.push_back({id(i, j, k), x, 0, 0, {}});
      }
  Id eid = 1;
  for (int k = 0; k < layers; ++k)
    for (int j = 0; j < n; ++j)
      for (int i = 0; i < n; ++i)
        m.solid_elements.push_back({eid++, 1,
                                    {id(i, j, k), id(i + 1, j, k), id(i + 1, j + 1, k), id(i, j + 1, k),
                                     id(i, j, k + 1), id(i + 1, j, k + 1), id(i + 1, j + 1, k + 1), id(i, j + 1, k + 1)},
                                    {}});
}

inline model::Model taylor_bar_model(const TaylorBar& bar) {
  model::Model m;
  m.parts.push_back({1, "copper rod", 1, 1, 0, 0, 0, {}, {}});
  if (bar.elform != 0) {
    m.sections[1] = model::SectionSolid{1, bar.elform, 0, {}};
  } else {
    model::SectionSph section;
    section.id = 1;
    section.cslh = bar.cslh;
    m.sections[1] = section;
  }
  model::MatJohnsonCook jc;
  jc.ro = 8960;
  jc.e = 124e9;
  jc.pr = 0.34;
  jc.g = jc.e / (2 * (1 + jc.pr));
  jc.a = 90e6;
  jc.b = 292e6;
  jc.n = 0.31;
  jc.c = 0.025;
  jc.m = 1.09;
  jc.tm = 1356;
  jc.tr = 298;
  jc.epso = 1;
  jc.cp = 383;
  jc.pc = -1.0e9;  // tension limited at 1 GPa, about copper's spall strength; not reached here
  jc.spall = 1;
  model::Material mat;
  mat.id = 1;
  mat.keyword = "*MAT_JOHNSON_COOK";
  mat.params = jc;
  if (bar.peer_physics) {
    const Real G = 46e9, K = jc.ro * 3940.0 * 3940.0, hardening = 0.3e9;
    model::MatPlasticKinematic pk;
    pk.ro = jc.ro;
    pk.e = 9 * K * G / (3 * K + G);
    pk.pr = (3 * K - 2 * G) / (2 * (3 * K + G));
    pk.sigy = 90e6;
    pk.etan = pk.e * hardening / (pk.e + hardening);  // hardening = E Etan / (E - Etan)
    pk.beta = 1;                                      // isotropic
    mat.keyword = "*MAT_PLASTIC_KINEMATIC";
    mat.params = pk;
    model::ControlSph control;
    control.form = 0;
    m.control_sph = control;
    model::SphTimestep step;
    step.rule = 1;
    m.sph_timestep = step;
  }
  m.materials[1] = mat;

  const Real dx = bar.diameter / bar.particles_across;
  const Real radius = bar.diameter / 2;
  const int layers = static_cast<int>(std::lround(bar.length / dx));
  std::vector<Vec3> positions;
  if (bar.elform != 0) add_rod_hexahedra(m, bar);
  for (int k = 0; k < layers && bar.elform == 0; ++k)
    for (int j = 0; j < bar.particles_across; ++j)
      for (int i = 0; i < bar.particles_across; ++i) {
        const Real x = (i + 0.5) * dx - radius, y = (j + 0.5) * dx - radius;
        if (x * x + y * y < radius * radius) positions.emplace_back(x, y, (k + 0.5) * bar.length / layers);
      }
  // Equal masses that add up to the rod's mass.
  const Real mass = jc.ro * M_PI * radius * radius * bar.length / static_cast<Real>(positions.size());
  Id id = 1;
  for (const Vec3& x : positions) {
    m.nodes.push_back({id, x, 0, 0, {}});
    m.sph_elements.push_back({id, 1, mass, {}});
    ++id;
  }
  for (const auto& node : m.nodes) {
    model::InitialVelocityNode iv;
    iv.nid = node.id;
    iv.v = Vec3(0, 0, -bar.speed);
    m.initial_velocity_nodes.push_back(iv);
  }
  model::RigidWallPlanar wall;  // z = 0, normal +z, frictionless
  wall.tail = Vec3::Zero();
  wall.head = Vec3(0, 0, 1);
  wall.keyword = "*RIGIDWALL_PLANAR";
  m.rigid_walls.push_back(wall);
  model::ControlTermination term;
  term.endtim = bar.end_time;
  m.termination = term;
  return m;
}

struct TaylorShape {
  Real length_ratio = 0, radius_ratio = 0;  // L/L0 and R/R0
};

// Length from the wall to the far end, and the largest radius (the foot's: the mushroom is widest
// there); each particle stands for a cell of one spacing, so half a spacing is added beyond the
// centres (dx = 0 for elements, whose nodes are on the surface).
inline std::pair<Real, Real> rod_extent(const discretization::NodeStore& nodes, Real dx) {
  Real length = 0, radius = 0;
  for (Index i = 0; i < nodes.size(); ++i) {
    length = std::max(length, nodes.x[i].z() + dx / 2);
    radius = std::max(radius, nodes.x[i].head<2>().norm() + dx / 2);
  }
  return {length, radius};
}

// Runs the bar and returns its final shape. The ratios divide by the same measure of the rod before
// impact (the lattice's own length and radius: a square lattice cut to a circle overshoots D0/2 by
// up to half a cell). Prints the shape and energy every 10 us.
inline TaylorShape run_taylor_bar(const TaylorBar& bar) {
  const model::Model model = taylor_bar_model(bar);
  solver::Problem problem = solver::build_problem(model);
  const Real dx = bar.elform != 0 ? 0 : bar.diameter / bar.particles_across;
  const auto [length0, radius0] = rod_extent(problem.nodes, dx);
  solver::Observer observer;
  problem.controls.glstat_dt = 10e-6;
  observer.on_history = [&](const solver::StepInfo& step, const discretization::EnergyLedger& e) {
    const auto [length, radius] = rod_extent(problem.nodes, dx);
    std::printf("t %.1f us: L/L0 %.4f  R/R0 %.4f  KE %.4g J  ratio %.4f\n", step.time * 1e6,
                length / length0, radius / radius0, e.kinetic(), e.ratio());
  };
  const auto summary = solver::run(problem, observer);
  std::printf("%lld steps\n", summary.steps);
  const auto [length, radius] = rod_extent(problem.nodes, dx);
  const TaylorShape shape{length / length0, radius / radius0};
  std::printf("Taylor bar %s D0/%d: L/L0 %.4f (measured 0.630, %+.1f %%), R/R0 %.4f (measured 2.204, %+.1f %%)\n",
              bar.elform == 0 ? "SPH" : bar.elform == 1 ? "ELFORM 1" : "ELFORM 2", bar.particles_across,
              shape.length_ratio, 100 * (shape.length_ratio / 0.630 - 1),
              shape.radius_ratio, 100 * (shape.radius_ratio / 2.204 - 1));
  return shape;
}

}  // namespace spall::test_support
