#pragma once
// Builds weakly compressible SPH problems in code: a box of fluid particles on a cell-centred
// lattice, in a rectangular tank whose floor and walls are layers of fixed (SPC'd) boundary
// particles on the same lattice, under gravity g along -z. With fluid.dimension == 2 the problem
// is the x-z section of the 3D one laid in the x-y plane (plane strain, as LS-DYNA's IDIM = 2):
// the vertical is y, every particle at z = 0, masses per unit thickness.
#include <algorithm>
#include <cmath>
#include <memory>
#include <numeric>
#include <random>

#include "spall/model/curve.hpp"
#include "spall/solver/problem.hpp"
#include "spall/sph/fluid.hpp"

namespace spall::test_support {

struct FluidTank {
  Vec3 fluid_size = Vec3(0.1, 0.1, 0.2);  // fluid block [0, size] (x, y, z)
  Vec3 tank_size = Vec3(0.4, 0.1, 0.3);   // inner tank [0, size]; the fluid sits in its -x corner
  Real spacing = 0.01;
  int wall_layers = 3;
  bool side_walls = true;  // walls at y = 0 and y = tank_size.y() (else the y faces are free)
  bool right_wall = true;  // the wall at x = tank_size.x()
  Real gravity = 9.81;
  sph::FluidParameters fluid;  // its material's density is the particles' density
  Real end_time = 0.1;
  // Nonzero: the nodes are stored, and the particles listed, in orders shuffled with this seed
  // (node IDs as unshuffled), as another card order or a rank's share of them would store them.
  unsigned shuffle_seed = 0;
};

// The problem and the curve its gravity load points to.
struct FluidTankProblem {
  std::unique_ptr<model::Curve> gravity_curve;
  solver::Problem problem;
  std::vector<Index> fluid_nodes;  // node indices of the fluid particles
  std::vector<Index> wall_nodes;
  int vertical = 2;                 // the axis gravity acts along (1 in 2D)
  sph::FluidFormulation& formulation() {
    return dynamic_cast<sph::FluidFormulation&>(*problem.formulations.front());
  }
};

inline FluidTankProblem fluid_tank_problem(const FluidTank& t) {
  FluidTankProblem out;
  auto& nodes = out.problem.nodes;
  const Real dp = t.spacing;
  const bool plane = t.fluid.dimension == 2;
  const Real volume = plane ? dp * dp : dp * dp * dp;
  std::vector<Vec3> x;
  std::vector<bool> wall;
  const auto cells = [&](Real length) { return static_cast<int>(std::lround(length / dp)); };
  const int fx = cells(t.fluid_size.x()), fy = plane ? 1 : cells(t.fluid_size.y()),
            fz = cells(t.fluid_size.z());
  const auto at = [&](int i, int j, int k) -> Vec3 {
    return plane ? dp * Vec3(i + 0.5, k + 0.5, 0) : dp * Vec3(i + 0.5, j + 0.5, k + 0.5);
  };
  for (int k = 0; k < fz; ++k)
    for (int j = 0; j < fy; ++j)
      for (int i = 0; i < fx; ++i) {
        x.push_back(at(i, j, k));
        wall.push_back(false);
      }
  // Wall particles fill the lattice cells outside the tank, up to wall_layers deep.
  const int tx = cells(t.tank_size.x()), ty = plane ? 1 : cells(t.tank_size.y()),
            tz = cells(t.tank_size.z());
  const int L = t.wall_layers;
  const bool side_walls = t.side_walls && !plane;
  const int y_first = side_walls ? -L : 0, y_last = side_walls ? ty + L : ty;
  const int x_last = t.right_wall ? tx + L : tx;
  for (int k = -L; k < tz; ++k)
    for (int j = y_first; j < y_last; ++j)
      for (int i = -L; i < x_last; ++i) {
        const bool inside = i >= 0 && i < tx && j >= 0 && j < ty && k >= 0;
        if (inside) continue;
        x.push_back(at(i, j, k));
        wall.push_back(true);
      }
  const Index n = static_cast<Index>(x.size());
  nodes.resize(n);
  out.problem.nodes.part.assign(n, 1);
  std::vector<Index> slot(n), particles(n);  // node p (ID p + 1) is stored at slot[p]
  std::iota(slot.begin(), slot.end(), Index(0));
  std::iota(particles.begin(), particles.end(), Index(0));
  if (t.shuffle_seed != 0) {
    std::mt19937 random(t.shuffle_seed);
    std::shuffle(slot.begin(), slot.end(), random);
    std::shuffle(particles.begin(), particles.end(), random);
  }
  for (Index p = 0; p < n; ++p) {
    const Index i = slot[p];
    nodes.id[i] = p + 1;
    nodes.x0[i] = nodes.x[i] = x[p];
    nodes.mass[i] = t.fluid.material.density * volume;
    if (plane) nodes.fixed[i] = 4;  // plane strain: the particles stay in their plane
    if (wall[p]) {
      nodes.fixed[i] = 7;
      out.problem.nodes.part[i] = 2;
      out.wall_nodes.push_back(i);
    } else {
      out.fluid_nodes.push_back(i);
    }
  }
  out.problem.formulations.push_back(
      std::make_unique<sph::FluidFormulation>(t.fluid, particles, nodes));
  out.gravity_curve = std::make_unique<model::Curve>();
  out.gravity_curve->points = {{0.0, t.gravity}, {1.0, t.gravity}};
  out.vertical = plane ? 1 : 2;
  out.problem.base_accelerations.push_back({out.vertical, out.gravity_curve.get(), 1.0});
  out.problem.controls.end_time = t.end_time;
  out.problem.controls.tssfac = 1.0;
  out.problem.controls.glstat_dt = t.end_time / 100;
  return out;
}

}  // namespace spall::test_support
