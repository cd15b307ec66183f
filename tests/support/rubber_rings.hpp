#pragma once
// Colliding rubber rings (Gray, Monaghan & Swift 2001, CMAME 190:6641; reference/validation.md
// §3, PySPH examples/solid_mech/rings.py): two elastic rings, inner radius 0.03 m, outer 0.04 m,
// centres at x = -0.041 and +0.041 m, each moving towards the other at 0.059 c0,
// c0 = sqrt(K / rho); E = 1e7, nu = 0.3975, rho = 1 (scaled units); 2D plane strain (*CONTROL_SPH
// IDIM 2). Plain SPH (FORM 0) as Gray et al. unless asked otherwise; Monaghan's viscosity with alpha = beta = 1; the
// artificial stress (epsilon 0.3, n 4) on or off. Built in code for the verification tests.
#include <cmath>

#include "spall/model/model.hpp"

namespace spall::test_support {

struct RubberRings {
  Real spacing = 0.002;  // lattice spacing; 5 particles across the ring's wall
  Real end_time = 4e-4;
  bool artificial_stress = true;
  Real cslh = 1.3;
  int form = 0;  // *CONTROL_SPH FORM (Gray et al.: plain SPH)
};

constexpr Real ring_inner_radius = 0.03, ring_outer_radius = 0.04, ring_centre = 0.041;
constexpr Real ring_density = 1.0, ring_young = 1e7, ring_poisson = 0.3975;

// The approach speed of each ring, 0.059 c0 (238 in these units).
inline Real ring_speed() {
  const Real bulk = ring_young / (3 * (1 - 2 * ring_poisson));
  return 0.059 * std::sqrt(bulk / ring_density);
}

// Part 1 is the left ring, part 2 the right one (one section and material).
inline model::Model rubber_rings_model(const RubberRings& r) {
  model::Model m;
  m.parts.push_back({1, "left ring", 1, 1, 0, 0, 0, {}, {}});
  m.parts.push_back({2, "right ring", 1, 1, 0, 0, 0, {}, {}});
  model::SectionSph section;
  section.id = 1;
  section.cslh = r.cslh;
  m.sections[1] = section;
  model::Material mat;
  mat.id = 1;
  mat.keyword = "*MAT_ELASTIC";
  mat.params = model::MatElastic{ring_density, ring_young, ring_poisson, 0, 0};
  m.materials[1] = mat;
  if (r.artificial_stress) m.sph_artificial_stress = model::SphArtificialStress{};  // 0.3, 4
  m.bulk_viscosity.q1 = 1.0;                                                        // beta
  m.bulk_viscosity.q2 = 1.0;                                                        // alpha
  model::ControlSph control;
  control.idim = 2;
  control.form = r.form;
  m.control_sph = control;
  model::ControlTermination term;
  term.endtim = r.end_time;
  m.termination = term;
  const Real dx = r.spacing;
  const int n = static_cast<int>(std::ceil(ring_outer_radius / dx));
  Id id = 1;
  for (int part = 1; part <= 2; ++part) {
    const Real side = part == 1 ? -1 : 1;
    for (int j = -n; j < n; ++j)
      for (int i = -n; i < n; ++i) {
        const Real x = (i + 0.5) * dx, y = (j + 0.5) * dx;
        const Real r2 = x * x + y * y;
        if (r2 < ring_inner_radius * ring_inner_radius ||
            r2 >= ring_outer_radius * ring_outer_radius)
          continue;
        m.nodes.push_back({id, Vec3(x + side * ring_centre, y, 0), 0, 0, {}});
        m.sph_elements.push_back(
            {id, part, ring_density * dx * dx, {}});  // mass per unit thickness
        model::InitialVelocityNode iv;
        iv.nid = id;
        iv.v = Vec3(-side * ring_speed(), 0, 0);
        m.initial_velocity_nodes.push_back(iv);
        ++id;
      }
  }
  return m;
}

}  // namespace spall::test_support
