// Whole-scene throughput of the solid finite elements: a steel block 1 m x 0.5 m x 0.5 m of
// 60 x 30 x 30 = 54 000 hexahedra with J2 plasticity (*MAT_PLASTIC_KINEMATIC, sigma_y 200 MPa,
// isotropic hardening), set moving with v = 50 cos(pi x) m/s so that it yields within the first
// steps; 20 steps per iteration at 1 and 2 OpenMP threads, for ELFORM 1 (Flanagan-Belytschko
// viscous hourglass control, IHQ 2) and ELFORM 2. Reports element-cycles per second per core
// (issue 32 target: 2e6 for ELFORM 1 with J2 plasticity) and bytes per element held by the
// elements and the node store.
#include <benchmark/benchmark.h>

#include <cmath>
#include <omp.h>

#include "spall/core/log.hpp"
#include "spall/fem/solid_elements.hpp"
#include "spall/solver/simulation.hpp"
#include "support/spg_block.hpp"

using namespace spall;

namespace {

model::Model block_model(int elform) {
  test_support::SpgBlock block;
  block.size = Vec3(1.0, 0.5, 0.5);
  block.elements = {60, 30, 30};
  block.end_time = 1.0;  // the cycle limit ends each run
  block.fem = test_support::FiniteElements{elform, {}};
  model::Model m = test_support::spg_block_model(block);
  m.materials[1].keyword = "*MAT_PLASTIC_KINEMATIC";
  m.materials[1].params = model::MatPlasticKinematic{7850, 200e9, 0.3, 200e6, 2e9, 1.0};
  for (const auto& node : m.nodes)
    m.initial_velocity_nodes.push_back({node.id, Vec3(50 * std::cos(M_PI * node.x.x()), 0, 0), Vec3::Zero(), 0, {}});
  return m;
}

void BM_FemPlasticBlock(benchmark::State& state) {
  log::set_quiet(true);
  const int threads = static_cast<int>(state.range(0));
  const int elform = static_cast<int>(state.range(1));
  omp_set_num_threads(threads);
  const model::Model model = block_model(elform);
  const long long steps = 20;
  solver::Problem problem = solver::build_problem(model);
  problem.controls.end_cycle = steps;
  problem.controls.glstat_dt = 1.0;  // histories are not what is measured
  solver::run(problem, {});          // warm-up: first pages touched
  const auto& fem = dynamic_cast<const fem::SolidElements&>(*problem.formulations.front());
  const auto& nodes = problem.nodes;
  const double node_bytes = nodes.id.size() * (sizeof(Id) + 4 * sizeof(Vec3) + sizeof(Real) + 3 + sizeof(std::int32_t));
  const double n = fem.element_count();
  for (auto _ : state) {
    state.PauseTiming();
    solver::Problem p = solver::build_problem(model);
    p.controls.end_cycle = steps;
    p.controls.glstat_dt = 1.0;
    state.ResumeTiming();
    benchmark::DoNotOptimize(solver::run(p, {}));
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n * (steps + 1)));
  state.counters["elements"] = n;
  state.counters["threads"] = threads;
  state.counters["elform"] = elform;
  state.counters["bytes_per_element"] = (double(fem.memory_bytes()) + node_bytes) / n;
  state.counters["element_cycles_per_s_per_core"] =
      benchmark::Counter(n * (steps + 1) / threads, benchmark::Counter::kIsIterationInvariantRate);
}

}  // namespace

BENCHMARK(BM_FemPlasticBlock)
    ->Args({1, 1})
    ->Args({2, 1})
    ->Args({1, 2})
    ->Args({2, 2})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
