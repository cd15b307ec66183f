// The cost of penalty contact in a workpiece it touches (issue 33: "contact adds at most 30 % to a
// step of the workpiece it touches"): an SPG steel block 40 x 40 x 10 mm of 40 x 40 x 10 hexahedra
// (18 491 particles, all of them slave nodes, as a drilling deck gives the whole workpiece part)
// under a rigid 12 x 12 mm punch (16 segments) that starts 0.05 mm into its top, plunging at
// 1 m/s and turning at 300 rad/s, friction 0.2, soft-constraint penalty (SOFT 1). 20 steps per
// iteration at 1 and 2 threads, with the contact (range 1 = 1) and without it (0: the same bodies,
// no *CONTACT card). Reports particle-steps per second per core of the whole step, the contact
// phase's time per slave node and step, and its share of the step. The two variants' difference
// is more than the contact phase: without contact the punch passes through a block at rest, with
// it the block deforms and its SPG particles update their neighbour lists (internal forces 0.69 s
// against 0.55 s an iteration at 1 thread, session 28).
#include <benchmark/benchmark.h>

#include <omp.h>

#include "spall/core/log.hpp"
#include "spall/solver/simulation.hpp"
#include "support/spg_block.hpp"

using namespace spall;

namespace {

model::Model punch_on_block(bool contact) {
  test_support::SpgBlock block;
  block.size = Vec3(0.04, 0.04, 0.01);
  block.elements = {40, 40, 10};
  block.end_time = 1.0;  // the cycle limit ends each run
  model::Model m = test_support::spg_block_model(block);
  // The punch: part 2, *MAT_RIGID, a 12 x 12 x 4 mm box of 4 x 4 x 1 hexahedra over the middle.
  m.parts.push_back({2, "punch", 2, 2, 0, 0, 0, {}, {}});
  m.sections[2] = model::SectionSolid{2, 1, 0, {}};
  model::Material rigid;
  rigid.id = 2;
  rigid.keyword = "*MAT_RIGID";
  rigid.params = model::MatRigid{7850, 200e9, 0.3};
  m.materials[2] = rigid;
  const Id first = 1000001;
  const auto id = [&](int i, int j, int k) { return first + i + 5 * (j + 5 * k); };
  const Vec3 corner(0.014, 0.014, 0.01 - 5e-5);
  const Vec3 axis(0.02, 0.02, 0);
  for (int k = 0; k <= 1; ++k)
    for (int j = 0; j <= 4; ++j)
      for (int i = 0; i <= 4; ++i) {
        const Vec3 x = corner + Vec3(0.003 * i, 0.003 * j, 0.004 * k);
        m.nodes.push_back({id(i, j, k), x, 0, 0, {}});
        const Vec3 r = x - axis;
        m.initial_velocity_nodes.push_back({id(i, j, k), Vec3(-300 * r.y(), 300 * r.x(), -1), Vec3::Zero(), 0, {}});
      }
  Id eid = 1000001;
  for (int j = 0; j < 4; ++j)
    for (int i = 0; i < 4; ++i)
      m.solid_elements.push_back({eid++, 2,
                                  {id(i, j, 0), id(i + 1, j, 0), id(i + 1, j + 1, 0), id(i, j + 1, 0), id(i, j, 1),
                                   id(i + 1, j, 1), id(i + 1, j + 1, 1), id(i, j + 1, 1)},
                                  {}});
  if (contact) {
    model::Contact c;
    c.kind = model::Contact::Kind::automatic_nodes_to_surface;
    c.keyword = "*CONTACT_AUTOMATIC_NODES_TO_SURFACE";
    c.a = {1, model::ContactSurface::Type::part, {}};
    c.b = {2, model::ContactSurface::Type::part, {}};
    c.fs = c.fd = 0.2;
    c.soft = 1;
    m.contacts.push_back(c);
  }
  return m;
}

void BM_ContactPunchOnSpgBlock(benchmark::State& state) {
  log::set_quiet(true);
  const int threads = static_cast<int>(state.range(0));
  const bool contact = state.range(1) != 0;
  omp_set_num_threads(threads);
  const model::Model model = punch_on_block(contact);
  const long long steps = 20;
  double contact_seconds = 0, step_seconds = 0, touching = 0;
  Index slaves = 0, particles = 0;
  for (auto _ : state) {
    state.PauseTiming();
    solver::Problem p = solver::build_problem(model);
    p.controls.end_cycle = steps;
    p.controls.glstat_dt = 1.0;  // histories are not what is measured
    particles = 0;
    for (Index i = 0; i < p.nodes.size(); ++i) particles += p.nodes.part[i] == 1;
    slaves = contact ? particles : 0;
    state.ResumeTiming();
    solver::TimeLoop loop(p, {});
    benchmark::DoNotOptimize(loop.run());
    contact_seconds += loop.phases()[solver::Phase::contact];
    step_seconds += loop.phases().total();
    if (contact) touching = p.contacts.front().touching();
  }
  const double iterations = static_cast<double>(state.iterations());
  state.SetItemsProcessed(static_cast<int64_t>(iterations * particles * (steps + 1)));
  state.counters["threads"] = threads;
  state.counters["contact"] = contact;
  state.counters["touching"] = touching;
  state.counters["particle_steps_per_s_per_core"] =
      benchmark::Counter(particles * double(steps + 1) / threads, benchmark::Counter::kIsIterationInvariantRate);
  if (contact) {
    state.counters["contact_ns_per_slave_step"] = 1e9 * contact_seconds / (iterations * slaves * (steps + 1));
    state.counters["contact_share_of_step"] = contact_seconds / step_seconds;
  }
}

}  // namespace

BENCHMARK(BM_ContactPunchOnSpgBlock)
    ->Args({1, 0})
    ->Args({1, 1})
    ->Args({2, 0})
    ->Args({2, 1})
    ->Unit(benchmark::kMillisecond)
    ->UseRealTime()
    ->MinTime(2.0);
