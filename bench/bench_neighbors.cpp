// Verlet list build on a cubic lattice: particles per second, and neighbours per particle.
// Search radius 2.4 spacings (cutoff 2.2 + skin 0.2), 56 neighbours in the interior: the usual
// SPH/SPG support of about 60 neighbours.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <vector>

#include "spall/neighbors/verlet_list.hpp"

namespace {

using spall::Real;
using spall::Vec3;

std::vector<Vec3> cubic_lattice(int side, Real dx) {
  std::vector<Vec3> x;
  x.reserve(static_cast<std::size_t>(side) * side * side);
  for (int k = 0; k < side; ++k)
    for (int j = 0; j < side; ++j)
      for (int i = 0; i < side; ++i) x.push_back(dx * Vec3(i, j, k));
  return x;
}

// in_cell_order = 0: the lattice in its own order (x fastest); 1: first put in cell order by
// spatial_order, as the solver keeps its particles.
void BM_VerletBuildLattice(benchmark::State& state) {
  const int side = static_cast<int>(std::lround(std::cbrt(static_cast<double>(state.range(0)))));
  const Real dx = 1e-3, cutoff = 2.2 * dx, skin = 0.2 * dx;
  std::vector<Vec3> x = cubic_lattice(side, dx);
  if (state.range(1) != 0) {
    const std::vector<spall::Index> order = spall::neighbors::spatial_order(x, cutoff + skin);
    std::vector<Vec3> sorted(x.size());
    for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = x[order[k]];
    x.swap(sorted);
  }
  spall::neighbors::VerletList verlet;
  for (auto _ : state) {
    verlet.build(x, cutoff, skin);
    benchmark::DoNotOptimize(verlet.list().neighbors.data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(x.size()));
  state.counters["particles"] = static_cast<double>(x.size());
  state.counters["neighbors_per_particle"] =
      static_cast<double>(verlet.list().neighbors.size()) / static_cast<double>(x.size());
  // What the list keeps: the rows, their offsets and the positions at the build.
  state.counters["bytes_per_particle"] =
      static_cast<double>(sizeof(spall::Index) *
                              (verlet.list().neighbors.size() + verlet.list().offsets.size()) +
                          sizeof(Vec3) * x.size()) /
      static_cast<double>(x.size());
}
BENCHMARK(BM_VerletBuildLattice)
    ->ArgNames({"particles", "in_cell_order"})
    ->ArgsProduct({{100'000, 1'000'000}, {0, 1}})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime();

void BM_SpatialOrderLattice(benchmark::State& state) {
  const int side = static_cast<int>(std::lround(std::cbrt(static_cast<double>(state.range(0)))));
  const Real dx = 1e-3;
  std::vector<Vec3> x = cubic_lattice(side, dx);
  std::reverse(x.begin(), x.end());  // the worst input order for the sort
  for (auto _ : state) {
    benchmark::DoNotOptimize(spall::neighbors::spatial_order(x, 2.4 * dx).data());
  }
  state.SetItemsProcessed(state.iterations() * static_cast<std::int64_t>(x.size()));
}
BENCHMARK(BM_SpatialOrderLattice)->Arg(1'000'000)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
