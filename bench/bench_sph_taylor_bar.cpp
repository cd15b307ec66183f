// Whole-scene throughput of the elastoplastic SPH solid: the Taylor bar of examples/taylor_bar
// (OFHC copper, Johnson-Cook, rigid wall; tests/support/taylor_bar.hpp) at D0/35, 105 084
// particles, at 1 and 2 OpenMP threads (others by SPALL_BENCH_THREADS: thread_counts.hpp). The
// rod is first run 5 us past impact (set-up, not timed), so that the timed steps see a plastic
// foot on the wall; each iteration then continues it by 20 steps (21 force evaluations; the first
// of each run does not advance the material).
// Reports particle-steps per second (items_per_second) and per core, the mean number of
// neighbours inside the support (|x_a - x_b| < h_a + h_b) and of Verlet-list entries (1.05 (h_a +
// h_b) plus a skin of 10 % of 2.1 x the largest h), and the bytes per particle of the SPH arrays and neighbour list
// (SolidFormulation::memory_bytes()) plus the node store. particle_steps_per_cpu_s divides by the
// processor time of all threads instead of the wall clock (OMP_WAIT_POLICY=passive keeps idle
// threads from spinning it away): per core, and less disturbed by other programs on the machine.
// evaluations_per_rebuild: force evaluations per Verlet-list build during the timed runs.
// passes_per_step: pair passes per force evaluation (the rates pass and the force pass);
// force_pairs_once: 1 when the force pass took each pair once (SolidFormulation::pairs_taken_once),
// 0 when it gathered every row whole.
//
// BM_SphTaylorBarPeerPhysics runs the same rod with the physics of LAMMPS SMD's input
// (bench/peers/lammps_smd_taylor_bar.in, TaylorBar::peer_physics) and its time step, so that
// both codes do the same work per step; step_ns reports the step each variant takes.
//
// The 10^6-particle variant (D0/74, 981 312 particles; about 1 GB, and minutes to run the rod to
// 5 us past impact) runs too, unless SPALL_BENCH_QUICK is set:
//   SPALL_BENCH_QUICK=1 build/release/bin/spall_bench --benchmark_filter=TaylorBar
#include <benchmark/benchmark.h>

#include <ctime>
#include <cstdlib>
#include <map>
#include <memory>
#include <omp.h>

#include "spall/core/log.hpp"
#include "spall/neighbors/verlet_list.hpp"
#include "spall/solver/simulation.hpp"
#include "spall/sph/solid.hpp"
#include "support/taylor_bar.hpp"
#include "thread_counts.hpp"

using namespace spall;

namespace {

constexpr long long steps_per_iteration = 20;

// One rod per resolution and physics, run to 5 us past impact once and then shared by the thread
// counts.
solver::Problem& impacted_rod(int particles_across, bool peer_physics) {
  static std::map<std::pair<int, bool>, std::unique_ptr<solver::Problem>> rods;
  auto& rod = rods[{particles_across, peer_physics}];
  if (!rod) {
    test_support::TaylorBar bar;
    bar.particles_across = particles_across;
    bar.peer_physics = peer_physics;
    bar.end_time = 5e-6;
    rod = std::make_unique<solver::Problem>(solver::build_problem(test_support::taylor_bar_model(bar)));
    rod->controls.glstat_dt = 1.0;  // histories are not what is measured
    solver::run(*rod, {});
    rod->controls.end_time = 1.0;  // from here on the cycle limit ends each run
    rod->controls.end_cycle = steps_per_iteration;
    // LAMMPS' input takes steps of 0.1 h / (c + |v|) (fix smd/adjust_dt 0.1): 10.9 ns at D0/35
    // (its log), where Spall's TSSFAC 0.9 takes 46 ns with this physics. The same step gives the
    // same neighbour-list reuse (a list lasts for a distance, not a number of steps).
    if (peer_physics) {
      const Real lammps_step = 10.9e-9 * 35 / particles_across;
      rod->controls.tssfac = lammps_step / rod->formulations.front()->stable_time_step(rod->nodes);
    }
  }
  return *rod;
}

// Neighbours inside the pair support h_a + h_b, per particle: the pairs the force loops use.
double neighbours_in_support(const solver::Problem& problem, const sph::SolidFormulation& sph) {
  discretization::FieldSet fields(problem.nodes.size());
  sph.write_fields(fields, problem.nodes);
  std::vector<double> h;
  for (auto& field : fields.node_fields())
    if (field.name == "smoothing_length") h = std::get<std::vector<double>>(field.values);
  const auto& x = problem.nodes.x;
  Real h_largest = 0;
  for (double value : h) h_largest = std::max<Real>(h_largest, value);
  neighbors::VerletList pairs;
  pairs.build(x, 2 * h_largest, 0);
  const auto& list = pairs.list();
  long long inside = 0;
  for (Index a = 0; a < problem.nodes.size(); ++a)
    for (Index k = list.offsets[a]; k < list.offsets[a + 1]; ++k) {
      const Index b = list.neighbors[k];
      if ((x[a] - x[b]).norm() < h[a] + h[b]) ++inside;
    }
  return double(inside) / double(sph.particle_count());
}

void run_taylor_bar(benchmark::State& state, bool peer_physics) {
  log::set_quiet(true);
  const int particles_across = static_cast<int>(state.range(0));
  const int threads = static_cast<int>(state.range(1));
  solver::Problem& problem = impacted_rod(particles_across, peer_physics);
  omp_set_num_threads(threads);
  const auto& sph = dynamic_cast<const sph::SolidFormulation&>(*problem.formulations.front());
  const double n = sph.particle_count();
  // Processor time of every thread (std::clock is per process): on a shared, oversubscribed
  // machine the wall clock also counts the time other programs held the cores.
  const long long builds_before = sph.neighbor_list_builds();
  const std::clock_t cpu_start = std::clock();
  for (auto _ : state) benchmark::DoNotOptimize(solver::run(problem, {}));
  const double cpu_seconds = double(std::clock() - cpu_start) / CLOCKS_PER_SEC;
  const long long builds = sph.neighbor_list_builds() - builds_before;
  const auto& nodes = problem.nodes;
  const double node_bytes = nodes.id.size() * (sizeof(Id) + 4 * sizeof(Vec3) + sizeof(Real) + 1);
  const double evaluations = steps_per_iteration + 1;
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * n * evaluations));
  state.counters["particles"] = n;
  // The time step the run has reached (the physical time each of these steps advances).
  state.counters["step_ns"] = 1e9 * problem.controls.tssfac * sph.stable_time_step(problem.nodes);
  state.counters["threads"] = threads;
  state.counters["neighbours_in_support"] = neighbours_in_support(problem, sph);
  state.counters["passes_per_step"] = 2;
  state.counters["force_pairs_once"] = sph.pairs_taken_once();
  state.counters["verlet_entries"] = double(sph.neighbor_list().neighbors.size()) / n;
  // What the list's storage holds (it is kept from build to build while under 1.25x the need).
  state.counters["verlet_capacity"] = double(sph.neighbor_list().neighbors.capacity()) / n;
  // Force evaluations per Verlet rebuild (each evaluation first asks whether the list is still valid).
  state.counters["evaluations_per_rebuild"] = double(state.iterations()) * evaluations / double(builds);
  state.counters["bytes_per_particle"] = (double(sph.memory_bytes()) + node_bytes) / n;
  state.counters["particle_steps_per_s_per_core"] =
      benchmark::Counter(n * evaluations / threads, benchmark::Counter::kIsIterationInvariantRate);
  state.counters["particle_steps_per_cpu_s"] = double(state.iterations()) * n * evaluations / cpu_seconds;
}

void BM_SphTaylorBar(benchmark::State& state) { run_taylor_bar(state, false); }
// The same rod with LAMMPS SMD's physics (TaylorBar::peer_physics): the work per step that
// bench/peers/lammps_smd.sh times.
void BM_SphTaylorBarPeerPhysics(benchmark::State& state) { run_taylor_bar(state, true); }

// D0/35 (105 084 particles) at 1 and 2 threads (or SPALL_BENCH_THREADS).
void rod_of_35_across(benchmark::internal::Benchmark* b) {
  b->ArgNames({"across", "threads"});
  for (int threads : bench::thread_counts()) b->Args({35, threads});
  b->Unit(benchmark::kMillisecond)->UseRealTime()->MinTime(2.0);
}

}  // namespace

BENCHMARK(BM_SphTaylorBar)->Apply(rod_of_35_across);
BENCHMARK(BM_SphTaylorBarPeerPhysics)->Apply(rod_of_35_across);

// The 10^6 variant, unless a quick run is asked for (see the header).
[[maybe_unused]] static const bool million_registered = [] {
  if (std::getenv("SPALL_BENCH_QUICK") != nullptr) return false;
  benchmark::RegisterBenchmark("BM_SphTaylorBar/million", BM_SphTaylorBar)
      ->ArgNames({"across", "threads"})
      ->Apply([](benchmark::internal::Benchmark* b) {
        for (int threads : bench::thread_counts()) b->Args({74, threads});
      })
      ->Unit(benchmark::kMillisecond)
      ->UseRealTime()
      ->MinTime(5.0);
  return true;
}();
