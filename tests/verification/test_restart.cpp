// Checkpoint and restart (issue 36; core/archive.hpp): a run stopped between two steps and
// continued from its checkpoint over a problem built afresh from the same deck is the run that
// was not stopped, bit for bit. The reference is the uninterrupted run itself: the same program
// on the same data gives the same bits (docs/RELIABILITY.md, determinism), so any difference is
// state the checkpoint forgot. Compared exactly: every node's position and velocity at the end,
// and every energy-history row after the checkpoint (time, dt and each ledger term).
//
// Each scene carries the state of one part of the solver across the checkpoint: plastic strain,
// the neighbour lists and their reference positions, the rigid wall's force (SPH solid Taylor
// bar); density and pressure of a fluid under gravity (SPH fluid tank); bonds broken by plastic
// strain, the kernel updated every SMSTEP steps, the penalty contacts' slip history with friction,
// a free rigid body and finite elements (the mixed SPG / FEM / rigid scene). Also: a checkpoint
// read over another deck, or cut short, is refused with a message.
#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <memory>
#include <optional>

#include "spall/core/archive.hpp"
#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/spg/formulation.hpp"
#include "spall/solver/simulation.hpp"
#include "support/contact_decks.hpp"
#include "support/fluid_tank.hpp"
#include "support/taylor_bar.hpp"

using namespace spall;
using namespace spall::test_support;
using test::DeckFolder;

namespace {

using MakeProblem = std::function<std::shared_ptr<solver::Problem>()>;

// A problem that keeps the model it was built from (curves and sets are read from it).
std::shared_ptr<solver::Problem> problem_of(model::Model m) {
  struct Built {
    model::Model model;
    std::optional<solver::Problem> problem;
  };
  auto built = std::make_shared<Built>();
  built->model = std::move(m);
  built->problem.emplace(solver::build_problem(built->model));
  return {built, &*built->problem};
}

using Rows = std::vector<std::vector<double>>;

solver::Observer recording(Rows& rows) {
  solver::Observer observer;
  observer.on_history = [&rows](const solver::StepInfo& step, const discretization::EnergyLedger& e) {
    std::vector<double> row{step.time, step.dt};
    for (const auto& term : e.terms()) row.push_back(term.value);
    rows.push_back(std::move(row));
  };
  return observer;
}

bool same_bits(const Vec3& a, const Vec3& b) { return std::memcmp(a.data(), b.data(), sizeof(Vec3)) == 0; }

struct Interrupted {
  std::string checkpoint;       // taken after step `at`
  std::shared_ptr<solver::Problem> problem;  // the uninterrupted run's problem at the end
  Rows rows;                    // its energy history
  std::size_t rows_before = 0;  // rows written up to the checkpoint
  long long steps = 0;
};

// The uninterrupted run, with a checkpoint taken after step `at` on the way.
Interrupted run_through(const MakeProblem& make, long long at) {
  Interrupted run;
  run.problem = make();
  const solver::Observer observer = recording(run.rows);
  solver::TimeLoop loop(*run.problem, observer);
  run.steps = loop.run([&](const solver::StepInfo& step) {
                    if (step.step == at) {
                      Archive archive = Archive::for_writing();
                      loop.checkpoint(archive);
                      run.checkpoint = archive.bytes();
                      run.rows_before = run.rows.size();
                    }
                    return true;
                  }).steps;
  return run;
}

void expect_restart_bitwise(const MakeProblem& make, long long at, const char* scene) {
  log::set_quiet(true);
  const Interrupted a = run_through(make, at);
  ASSERT_FALSE(a.checkpoint.empty()) << scene << ": the run ended before step " << at;

  const auto b = make();
  Rows rows;
  const solver::Observer observer = recording(rows);
  solver::TimeLoop loop(*b, observer);
  Archive archive = Archive::for_reading(a.checkpoint, "checkpoint");
  loop.checkpoint(archive);
  EXPECT_TRUE(archive.at_end()) << scene << ": bytes left over";
  const long long steps = loop.run().steps;
  std::printf("%s: %lld steps, checkpoint after step %lld (%zu bytes), %zu history rows after it\n", scene, a.steps,
              at, a.checkpoint.size(), rows.size());

  EXPECT_EQ(steps, a.steps) << scene;
  ASSERT_EQ(b->nodes.size(), a.problem->nodes.size());
  Index differing = 0;
  for (Index i = 0; i < b->nodes.size(); ++i)
    differing += !same_bits(b->nodes.x[i], a.problem->nodes.x[i]) || !same_bits(b->nodes.v[i], a.problem->nodes.v[i]);
  EXPECT_EQ(differing, 0) << scene << ": nodes whose position or velocity differs from the uninterrupted run";
  const Rows expected(a.rows.begin() + static_cast<std::ptrdiff_t>(a.rows_before), a.rows.end());
  ASSERT_FALSE(expected.empty()) << scene;
  EXPECT_EQ(rows, expected) << scene << ": the energy history after the checkpoint";
}

// The Taylor bar of test_sph_taylor_bar at D0/6 to 20 us: Johnson-Cook plasticity, neighbour
// lists rebuilt as the foot spreads, a rigid wall.
TEST(Restart, SphSolidTaylorBarContinuesBitwise) {
  TaylorBar bar;
  bar.particles_across = 6;
  bar.end_time = 20e-6;
  expect_restart_bitwise([&] { return problem_of(taylor_bar_model(bar)); }, 60, "SPH solid");
}

// The same bar as hexahedra (ELFORM 2).
TEST(Restart, FemTaylorBarContinuesBitwise) {
  TaylorBar bar;
  bar.particles_across = 6;
  bar.end_time = 10e-6;
  bar.elform = 2;
  expect_restart_bitwise([&] { return problem_of(taylor_bar_model(bar)); }, 40, "FEM");
}

// A water column collapsing in a tank (test_sph_fluid's small dam break, 3-D slab).
TEST(Restart, SphFluidTankContinuesBitwise) {
  const Real column = 0.1;
  FluidTank tank;
  tank.spacing = column / 8;
  tank.fluid_size = Vec3(column, 2 * tank.spacing, 2 * column);
  tank.tank_size = Vec3(3 * column, 2 * tank.spacing, 2.2 * column);
  tank.fluid.material = sph::FluidMaterial::tait(1000, 10 * std::sqrt(2 * 9.81 * 2 * column), 7, 1e-3);
  tank.fluid.smoothing_length = 1.3 * tank.spacing;
  tank.fluid.viscosity.alpha = 0.1;
  tank.end_time = 0.03;
  expect_restart_bitwise(
      [&] {
        auto t = std::make_shared<FluidTankProblem>(fluid_tank_problem(tank));
        return std::shared_ptr<solver::Problem>(t, &t->problem);
      },
      50, "SPH fluid");
}

// A ball of hexahedra (part 1) dropped onto a plate of SPG particles (part 2) whose bonds break at
// 5 % plastic strain (kernel updated every 5 steps), pushed from below by a free rigid block
// (part 3); both contacts with Coulomb friction.
std::string mixed_deck() {
  const Real end_time = 1.5e-3;
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)}) + "*DATABASE_GLSTAT\n" +
                     row({number(end_time / 100)});
  deck += deformable_part(Body::fem, 1, 1000, 1e8, 0.3);
  deck += hex_ball(1, Vec3(0.002, 0.001, 0.0105), 0.01, 4, 1, 1);
  deck += "*PART\nplate\n" + row({"2", "2", "2"}) + "*SECTION_SOLID_SPG\n" + row({"2", "47", "0"}) +
          row({"1.5", "1.5", "1.5", "0", "1", "", "5"}) + row({"1", "0.05"}) + "*MAT_PLASTIC_KINEMATIC\n" +
          row({"2", "1000.0", "1.0e8", "0.3", "1.0e6", "1.0e6"});
  deck += hex_box(2, Vec3(-0.03, -0.03, -0.01), Vec3(0.06, 0.06, 0.01), {8, 8, 2}, 10001, 10001);
  deck += rigid_part(3, 1000, 1e8, 0.3, false) +
          hex_box(3, Vec3(-0.01, -0.01, -0.0305), Vec3(0.02, 0.02, 0.02), {2, 2, 2}, 20001, 20001);
  for (const char* pair : {"1", "3"})
    deck += std::string("*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n") + row({pair, "2", "3", "3"}) +
            row({"0.3", "0.2", "0.0", "0.0", "20.0"}) + row({});
  deck += "*INITIAL_VELOCITY_GENERATION\n" + row({"1", "2", "0.0", "2.0", "0.0", "-20.0"}) + row({});
  deck += "*INITIAL_VELOCITY_GENERATION\n" + row({"3", "2", "0.0", "0.0", "0.0", "5.0"}) + row({});
  return deck + "*END\n";
}

TEST(Restart, SpgFemContactRigidBodyContinuesBitwise) {
  DeckFolder folder;
  const auto path = folder.write("mixed.k", mixed_deck());
  const MakeProblem make = [&] { return problem_of(io::keyword::read_deck(path)); };
  {  // the scene does what it is here for: bonds break and the plate's kernel is updated
    log::set_quiet(true);
    const auto p = make();
    solver::run(*p, {});
    std::size_t broken = 0;
    for (const auto& f : p->formulations)
      if (const auto* spg = dynamic_cast<const spg::SpgFormulation*>(f.get()))
        for (const auto& part : spg->parts()) broken += part.broken_pairs().size();
    std::printf("mixed scene: %zu broken bonds\n", broken);
    ASSERT_GT(broken, 0u);
  }
  expect_restart_bitwise(make, 47, "SPG + FEM + contact + rigid body");
}

// A checkpoint of one deck read over another, or cut short: a message, not garbage.
TEST(Restart, ForeignOrTruncatedCheckpointIsRefused) {
  log::set_quiet(true);
  TaylorBar bar;
  bar.particles_across = 6;
  bar.end_time = 2e-6;
  const Interrupted a = run_through([&] { return problem_of(taylor_bar_model(bar)); }, 3);
  ASSERT_FALSE(a.checkpoint.empty());

  bar.particles_across = 8;  // another lattice: other particle counts
  auto other = problem_of(taylor_bar_model(bar));
  const solver::Observer quiet;
  solver::TimeLoop loop(*other, quiet);
  Archive archive = Archive::for_reading(a.checkpoint, "runrsf");
  try {
    loop.checkpoint(archive);
    FAIL() << "a checkpoint of another deck was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("runrsf: the checkpoint has"), std::string::npos) << e.what();
  }

  bar.particles_across = 6;
  auto same = problem_of(taylor_bar_model(bar));
  solver::TimeLoop loop2(*same, quiet);
  Archive cut = Archive::for_reading(a.checkpoint.substr(0, a.checkpoint.size() / 2), "runrsf");
  try {
    loop2.checkpoint(cut);
    FAIL() << "half a checkpoint was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("runrsf: the checkpoint ends early"), std::string::npos) << e.what();
  }
}

}  // namespace
