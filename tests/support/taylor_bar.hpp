#pragma once
// The Taylor bar of Wilkins & Guinan 1973 (J. Appl. Phys. 44:1200), test 1: an OFHC copper rod,
// L0 = 23.47 mm, D0 = 7.62 mm, hitting a rigid wall at 210 m/s; Johnson & Cook's (1983) copper
// constants (reference/validation.md §1(b)). SI units. Built in code for the verification test and
// the benchmark; examples/taylor_bar has the same scene as a deck.
#include <cmath>

#include "spall/model/model.hpp"

namespace spall::test_support {

struct TaylorBar {
  Real length = 23.47e-3, diameter = 7.62e-3, speed = 210;
  int particles_across = 10;  // lattice spacing D0 / particles_across
  Real end_time = 80e-6;
  Real cslh = 1.2;
};

inline model::Model taylor_bar_model(const TaylorBar& bar) {
  model::Model m;
  m.parts.push_back({1, "copper rod", 1, 1, 0, 0, {}});
  model::SectionSph section;
  section.id = 1;
  section.cslh = bar.cslh;
  m.sections[1] = section;
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
  m.materials[1] = mat;

  const Real dx = bar.diameter / bar.particles_across;
  const Real radius = bar.diameter / 2;
  const int layers = static_cast<int>(std::lround(bar.length / dx));
  std::vector<Vec3> positions;
  for (int k = 0; k < layers; ++k)
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
    model::InitialVelocityNode iv;
    iv.nid = id;
    iv.v = Vec3(0, 0, -bar.speed);
    m.initial_velocity_nodes.push_back(iv);
    ++id;
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

}  // namespace spall::test_support
