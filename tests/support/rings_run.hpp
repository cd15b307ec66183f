#pragma once
// Runs the colliding rubber rings (rubber_rings.hpp) and checks what Gray, Monaghan & Swift 2001
// show: with the artificial stress the rings bounce apart whole, without it they clump and fuse.
// Shared by test_sph_rubber_rings.cpp and its _slow variant; the bounds are explained there.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "spall/solver/simulation.hpp"
#include "support/rubber_rings.hpp"

namespace spall::test_support {

struct RingsRun {
  Real initial_separation = 0, separation = 0;  // of the rings' centres of mass, along x
  Real opening_speed = 0;         // v_right - v_left of the centres of mass at the end
  Real gap = 0;                   // closest pair of particles of different rings at the end
  Real largest_stretch = 0;       // largest distance of initial nearest neighbours, ever
  Real smallest_distance = 1e30;  // smallest distance of initial nearest neighbours, ever
  Real worst_energy_error = 0;    // |energy ratio - 1|, worst step
  Real worst_momentum = 0;        // |sum m v|, worst step
  Real momentum_scale = 0;        // sum m |v| at the start
};

inline RingsRun run_rubber_rings(const RubberRings& rings) {
  const model::Model model = rubber_rings_model(rings);
  solver::Problem problem = solver::build_problem(model);
  const auto& nodes = problem.nodes;
  const Index n = nodes.size();
  std::vector<int> part(n);
  for (Index i = 0; i < n; ++i) part[i] = problem.nodes.part[i];
  // Initial nearest neighbours on the lattice (4 inside, fewer at the surfaces), each pair once.
  std::vector<std::pair<Index, Index>> pairs;
  for (Index a = 0; a < n; ++a)
    for (Index b = a + 1; b < n; ++b)
      if ((nodes.x0[a] - nodes.x0[b]).norm() < 1.01 * rings.spacing) pairs.emplace_back(a, b);
  RingsRun run;
  Vec3 centre[3] = {}, velocity[3] = {};
  const auto centres = [&] {
    Real mass[3] = {0, 0, 0};
    for (int p = 1; p <= 2; ++p) centre[p] = velocity[p] = Vec3::Zero();
    for (Index i = 0; i < n; ++i) {
      centre[part[i]] += nodes.mass[i] * nodes.x[i];
      velocity[part[i]] += nodes.mass[i] * nodes.v[i];
      mass[part[i]] += nodes.mass[i];
    }
    for (int p = 1; p <= 2; ++p) centre[p] /= mass[p], velocity[p] /= mass[p];
  };
  centres();
  run.initial_separation = centre[2].x() - centre[1].x();
  for (Index i = 0; i < n; ++i) run.momentum_scale += nodes.mass[i] * nodes.v[i].norm();
  problem.controls.glstat_dt = 1e-30;  // every step
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo&, const discretization::EnergyLedger& e) {
    for (const auto& [a, b] : pairs) {
      const Real d = (nodes.x[a] - nodes.x[b]).norm();
      run.largest_stretch = std::max(run.largest_stretch, d);
      run.smallest_distance = std::min(run.smallest_distance, d);
    }
    run.worst_energy_error = std::max(run.worst_energy_error, std::abs(e.ratio() - 1));
    Vec3 momentum = Vec3::Zero();
    for (Index i = 0; i < n; ++i) momentum += nodes.mass[i] * nodes.v[i];
    run.worst_momentum = std::max(run.worst_momentum, momentum.norm());
  };
  solver::run(problem, observer);
  centres();
  run.separation = centre[2].x() - centre[1].x();
  run.opening_speed = velocity[2].x() - velocity[1].x();
  run.gap = 1e30;
  for (Index a = 0; a < n; ++a)
    for (Index b = 0; b < n; ++b)
      if (part[a] == 1 && part[b] == 2)
        run.gap = std::min(run.gap, (nodes.x[a] - nodes.x[b]).norm());
  const Real dx = rings.spacing;
  std::printf(
      "rings dx %g, artificial stress %s: centres %.4f -> %.4f m, opening speed %+.1f (approach "
      "%.1f), gap %.2f dx, neighbour distance %.2f..%.2f dx, energy error %.2e, momentum %.2e of "
      "sum m|v|\n",
      dx, rings.artificial_stress ? "on" : "off", run.initial_separation, run.separation,
      run.opening_speed, 2 * ring_speed(), run.gap / dx, run.smallest_distance / dx,
      run.largest_stretch / dx, run.worst_energy_error, run.worst_momentum / run.momentum_scale);
  return run;
}

// Bounds of an intact ring (the lattice's nearest neighbours stay neighbours).
constexpr Real intact_stretch = 2.5, intact_distance = 0.5;  // in initial spacings

inline void expect_conservation(const RingsRun& run) {
  EXPECT_LT(run.worst_momentum, 1e-12 * run.momentum_scale);
  EXPECT_LT(run.worst_energy_error, 0.01);
}

inline void expect_bounce_apart_whole(const RubberRings& rings, const RingsRun& run) {
  const Real dx = rings.spacing, support = 2 * rings.cslh * dx;
  EXPECT_GT(run.opening_speed, 0) << "the rings should move apart at the end";
  EXPECT_GT(run.separation, run.initial_separation);
  EXPECT_GT(run.gap, support) << "the rings should no longer interact";
  EXPECT_LT(run.largest_stretch, intact_stretch * dx) << "a ring tore";
  EXPECT_GT(run.smallest_distance, intact_distance * dx) << "particles paired up";
  expect_conservation(run);
}

inline void expect_clump_and_fuse(const RubberRings& rings, const RingsRun& run) {
  const Real dx = rings.spacing;
  EXPECT_LT(run.separation, run.initial_separation) << "the rings should still be stuck together";
  EXPECT_GT(run.largest_stretch, intact_stretch * dx) << "the rings should tear";
  EXPECT_LT(run.smallest_distance, intact_distance * dx) << "particles should pair up";
  expect_conservation(run);
}

}  // namespace spall::test_support
