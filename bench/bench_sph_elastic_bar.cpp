// Whole-scene throughput of the elastic SPH solid: the free-free bar of examples/elastic_bar at
// a larger size (100 x 20 x 20 = 40 000 particles), 20 steps per iteration, at 1 and 2 OpenMP
// threads. Reports particle-steps per second (items_per_second), per core, the mean length of the
// Verlet rows (neighbours within the support plus the 10 % skin) and the bytes per particle held
// by the node store, the SPH arrays and the neighbour list.
#include <benchmark/benchmark.h>

#include <cmath>
#include <omp.h>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "spall/sph/solid.hpp"
#include "support/sph_block.hpp"

using namespace spall;

namespace {

// The bar of examples/elastic_bar, 1 m x 0.2 m x 0.2 m, in its first longitudinal mode.
model::Model bar_model(Real spacing) {
  test_support::ElasticBlock bar;
  bar.size = Vec3(1.0, 0.2, 0.2);
  bar.spacing = spacing;
  bar.end_time = 1.0;  // the cycle limit ends each run
  model::Model m = test_support::elastic_block_model(bar);
  for (const auto& node : m.nodes)
    m.initial_velocity_nodes.push_back({node.id, Vec3(std::cos(M_PI * node.x.x()), 0, 0), Vec3::Zero(), 0, {}});
  return m;
}

void BM_SphElasticBar(benchmark::State& state) {
  log::set_quiet(true);
  const int threads = static_cast<int>(state.range(0));
  omp_set_num_threads(threads);
  const model::Model model = bar_model(0.01);
  const long long steps = 20;
  solver::Problem problem = solver::build_problem(model);
  problem.controls.end_cycle = steps;
  problem.controls.glstat_dt = 1.0;  // histories are not what is measured
  solver::run(problem, {});          // warm-up: first neighbour build, first pages touched
  const auto& sph = dynamic_cast<const sph::SolidFormulation&>(*problem.formulations.front());
  const auto& nodes = problem.nodes;
  const double node_bytes = nodes.id.size() * (sizeof(Id) + 4 * sizeof(Vec3) + sizeof(Real) + 1);
  const double bytes = double(sph.memory_bytes()) + node_bytes;
  const double n = sph.particle_count();
  for (auto _ : state) {
    state.PauseTiming();  // set-up is not a step
    solver::Problem p = solver::build_problem(model);
    p.controls.end_cycle = steps;
    p.controls.glstat_dt = 1.0;
    state.ResumeTiming();
    benchmark::DoNotOptimize(solver::run(p, {}));
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n * (steps + 1)));
  state.counters["particles"] = n;
  state.counters["threads"] = threads;
  state.counters["neighbours"] = double(sph.neighbor_list().neighbors.size()) / n;
  state.counters["passes_per_step"] = 2;  // the rates pass and the force pass
  state.counters["bytes_per_particle"] = bytes / n;
  state.counters["particle_steps_per_s_per_core"] =
      benchmark::Counter(n * (steps + 1) / threads, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_SphElasticBar)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
