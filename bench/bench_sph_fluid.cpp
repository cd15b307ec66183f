// Whole-scene throughput of the SPH fluid: the 3D dam break of examples/dam_break (water column
// L x 1.5L x 2L in a tank 4L long between side walls), cubic spline with h = 1.73 spacings (about
// 170 neighbours inside the support of an interior particle), 20 steps per iteration from rest, at
// 1 and 2 OpenMP threads (SPALL_BENCH_THREADS: thread_counts.hpp). One pair pass per step. Reports:
//   fluid_steps_per_s           fluid particle-steps per second of wall time
//   fluid_steps_per_core_s      the same per second of process CPU time (all threads)
//   neighbours                  mean number of particles inside the support, over fluid particles
//   bytes_per_particle          node store + every fluid array + cell list, per particle (walls
//                               included: they are particles of the same formulation)
// The scene at about 1e5 and about 1e6 water particles (SPALL_BENCH_QUICK=1 leaves the 1e6 one
// out: it takes minutes to set up and run). A free block
// of fluid (no walls) gives the pair pass alone.
#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdlib>
#include <ctime>
#include <omp.h>
#include <string>
#include <vector>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "support/fluid_tank.hpp"
#include "thread_counts.hpp"

using namespace spall;

namespace {

constexpr Real g = 9.81;

// n particles across the column width L = 0.146 m.
test_support::FluidTank dam_break(int n) {
  test_support::FluidTank t;
  const Real L = 0.146;
  t.spacing = L / n;
  t.fluid_size = Vec3(L, 1.5 * L, 2 * L);
  t.tank_size = Vec3(4 * L, 1.5 * L, 2.2 * L);
  t.wall_layers = 4;  // the support 2h = 3.46 spacings
  t.fluid.material = sph::FluidMaterial::tait(1000, 10 * std::sqrt(2 * g * 2 * L), 7, 1e-3);
  t.fluid.smoothing_length = 1.73 * t.spacing;
  t.fluid.viscosity.alpha = 0.1;
  t.fluid.viscosity.beta = 0;
  t.end_time = 1.0;  // the cycle limit ends each run
  return t;
}

void BM_SphFluidDamBreak(benchmark::State& state) {
  log::set_quiet(true);
  const int n = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  omp_set_num_threads(threads);
  const long long steps = 20;
  const auto tank_setup = dam_break(n);
  double fluid = 0, particles = 0, neighbours = 0, bytes = 0, cpu_seconds = 0;
  for (auto _ : state) {
    state.PauseTiming();  // set-up is not a step
    auto tank = test_support::fluid_tank_problem(tank_setup);
    tank.problem.controls.end_cycle = steps;
    tank.problem.controls.glstat_dt = 1.0;  // histories are not what is measured
    state.ResumeTiming();
    const std::clock_t start = std::clock();
    benchmark::DoNotOptimize(solver::run(tank.problem, {}));
    cpu_seconds += double(std::clock() - start) / CLOCKS_PER_SEC;
    state.PauseTiming();
    const auto& sph = tank.formulation();
    fluid = double(tank.fluid_nodes.size());
    particles = sph.particle_count();
    const auto counts = sph.neighbour_counts();
    double sum = 0;
    int counted = 0;
    for (Index a = 0; a < sph.particle_count(); ++a)
      if (tank.problem.nodes.fixed[sph.node_of(a)] != 7) sum += counts[a], ++counted;
    neighbours = sum / counted;
    const auto& nodes = tank.problem.nodes;
    const double node_bytes = nodes.id.size() * (sizeof(Id) + 4 * sizeof(Vec3) + sizeof(Real) + 1);
    bytes = (double(sph.memory_bytes()) + node_bytes) / particles;
    state.ResumeTiming();
  }
  const double fluid_steps = fluid * (steps + 1) * state.iterations();
  state.SetItemsProcessed(static_cast<int64_t>(fluid_steps));
  state.counters["fluid_particles"] = fluid;
  state.counters["particles"] = particles;
  state.counters["threads"] = threads;
  state.counters["neighbours"] = neighbours;
  state.counters["passes_per_step"] = 1;
  state.counters["bytes_per_particle"] = bytes;
  state.counters["fluid_steps_per_s"] =
      benchmark::Counter(fluid_steps / state.iterations(), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fluid_steps_per_core_s"] = fluid_steps / cpu_seconds;
}

// A free cube of n^3 water particles without walls or gravity, in a slow shearing flow: the pair
// pass alone, every particle a fluid particle (h = 1.73 spacings as above).
void BM_SphFluidBlock(benchmark::State& state) {
  log::set_quiet(true);
  const int n = static_cast<int>(state.range(0));
  omp_set_num_threads(static_cast<int>(state.range(1)));
  const long long steps = 20;
  const Real dp = 0.01;
  double neighbours = 0, bytes = 0, cpu_seconds = 0;
  for (auto _ : state) {
    state.PauseTiming();
    solver::Problem problem;
    auto& nodes = problem.nodes;
    nodes.resize(n * n * n);
    problem.nodes.part.assign(n * n * n, 1);
    std::vector<Index> particles(n * n * n);
    for (int k = 0, i = 0; k < n; ++k)
      for (int j = 0; j < n; ++j)
        for (int l = 0; l < n; ++l, ++i) {
          nodes.id[i] = i + 1;
          nodes.x[i] = nodes.x0[i] = dp * Vec3(l + 0.5, j + 0.5, k + 0.5);
          nodes.mass[i] = 1000 * dp * dp * dp;
          nodes.v[i] = Vec3(0.1 * std::sin(7 * nodes.x[i].y()), 0.1 * std::cos(5 * nodes.x[i].z()), 0);
          particles[i] = i;
        }
    sph::FluidParameters fluid;
    fluid.material = sph::FluidMaterial::tait(1000, 20, 7, 1e-3);
    fluid.smoothing_length = 1.73 * dp;
    fluid.viscosity.alpha = 0.1;
    fluid.viscosity.beta = 0;
    problem.formulations.push_back(std::make_unique<sph::FluidFormulation>(fluid, particles, nodes));
    problem.controls.end_time = 1;
    problem.controls.end_cycle = steps;
    problem.controls.tssfac = 1;
    problem.controls.glstat_dt = 1;
    state.ResumeTiming();
    const std::clock_t start = std::clock();
    benchmark::DoNotOptimize(solver::run(problem, {}));
    cpu_seconds += double(std::clock() - start) / CLOCKS_PER_SEC;
    state.PauseTiming();
    const auto& sph = dynamic_cast<const sph::FluidFormulation&>(*problem.formulations.front());
    const auto counts = sph.neighbour_counts();
    double sum = 0;
    for (Index c : counts) sum += c;
    neighbours = sum / counts.size();
    const double node_bytes = nodes.id.size() * (sizeof(Id) + 4 * sizeof(Vec3) + sizeof(Real) + 1);
    bytes = (double(sph.memory_bytes()) + node_bytes) / sph.particle_count();
    state.ResumeTiming();
  }
  const double fluid_steps = double(n) * n * n * (steps + 1) * state.iterations();
  state.SetItemsProcessed(static_cast<int64_t>(fluid_steps));
  state.counters["fluid_particles"] = double(n) * n * n;
  state.counters["threads"] = double(state.range(1));
  state.counters["neighbours"] = neighbours;
  state.counters["passes_per_step"] = 1;
  state.counters["bytes_per_particle"] = bytes;
  state.counters["fluid_steps_per_s"] =
      benchmark::Counter(fluid_steps / state.iterations(), benchmark::Counter::kIsIterationInvariantRate);
  state.counters["fluid_steps_per_core_s"] = fluid_steps / cpu_seconds;
}

void register_benchmarks() {
  for (int threads : bench::thread_counts())
    benchmark::RegisterBenchmark("BM_SphFluidBlock", BM_SphFluidBlock)
        ->Args({46, threads})  // 97 336 particles
        ->Unit(benchmark::kMillisecond)
        ->UseRealTime()
        ->MinTime(2.0);
  // n = 32: 32 x 48 x 64 = 98 304 water particles.
  std::vector<int> sizes = {32};
  // n = 70: 70 x 105 x 140 = 1 029 000 water particles.
  if (std::getenv("SPALL_BENCH_QUICK") == nullptr) sizes.push_back(70);
  for (int n : sizes)
    for (int threads : bench::thread_counts())
      benchmark::RegisterBenchmark("BM_SphFluidDamBreak", BM_SphFluidDamBreak)
          ->Args({n, threads})
          ->Unit(benchmark::kMillisecond)
          ->UseRealTime()
          ->MinTime(2.0);
}

const int registered = (register_benchmarks(), 0);

}  // namespace
