// Whole-scene throughput of the SPG formulation: the free-free elastic bar, 1 m x 0.2 m x 0.2 m
// meshed with 99 x 19 x 19 hexahedra (100 x 20 x 20 = 40 000 particles), DX 1.6, cubic spline with
// cubical support, 20 steps per iteration, at 1 and 2 OpenMP threads, for ITB 1 (smoothed) and ITB 2
// (unsmoothed). SMSTEP 15: a kernel update (shape functions, integration correction) every 15 steps
// is part of what is measured. Reports node-steps per second (items_per_second), per core, bonds
// per particle and bytes per node held by the node store and the SPG arrays.
#include <benchmark/benchmark.h>

#include <cmath>
#include <omp.h>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "spall/spg/formulation.hpp"
#include "support/spg_block.hpp"

using namespace spall;

namespace {

model::Model bar_model(int itb) {
  test_support::SpgBlock bar;
  bar.size = Vec3(1.0, 0.2, 0.2);
  bar.elements = {99, 19, 19};
  bar.section.itb = itb;
  bar.end_time = 1.0;  // the cycle limit ends each run
  model::Model m = test_support::spg_block_model(bar);
  for (const auto& node : m.nodes)
    m.initial_velocity_nodes.push_back({node.id, Vec3(std::cos(M_PI * node.x.x()), 0, 0), Vec3::Zero(), 0, {}});
  return m;
}

void BM_SpgElasticBar(benchmark::State& state) {
  log::set_quiet(true);
  const int threads = static_cast<int>(state.range(0));
  const int itb = static_cast<int>(state.range(1));
  omp_set_num_threads(threads);
  const model::Model model = bar_model(itb);
  const long long steps = 20;
  solver::Problem problem = solver::build_problem(model);
  problem.controls.end_cycle = steps;
  problem.controls.glstat_dt = 1.0;  // histories are not what is measured
  solver::run(problem, {});          // warm-up: first pages touched
  const auto& spg = dynamic_cast<const spg::SpgFormulation&>(*problem.formulations.front());
  const auto& nodes = problem.nodes;
  const double node_bytes = nodes.id.size() * (sizeof(Id) + 4 * sizeof(Vec3) + sizeof(Real) + 1);
  const double n = spg.particle_count();
  const double bytes = double(spg.memory_bytes()) + node_bytes;
  for (auto _ : state) {
    state.PauseTiming();  // set-up (first neighbour search and shape functions) is not a step
    solver::Problem p = solver::build_problem(model);
    p.controls.end_cycle = steps;
    p.controls.glstat_dt = 1.0;
    state.ResumeTiming();
    benchmark::DoNotOptimize(solver::run(p, {}));
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n * (steps + 1)));
  state.counters["nodes"] = n;
  state.counters["threads"] = threads;
  state.counters["itb"] = itb;
  state.counters["bonds"] = double(spg.parts().front().bonds().entry_count()) / n;
  state.counters["bytes_per_node"] = bytes / n;
  state.counters["node_steps_per_s_per_core"] =
      benchmark::Counter(n * (steps + 1) / threads, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_SpgElasticBar)
    ->Args({1, 1})
    ->Args({2, 1})
    ->Args({1, 2})
    ->Args({2, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
