// SPG's shape functions of the bonds over several ranks, run
// as 1, 2 and 3 ranks (docs/SCALING.md §3, "SPG's shape functions by rank"): a rank holds them for
// the rows of the particles it reads alone (its own and their bond partners, one stretch of the
// node order), not for every bond. On an elastic bar of SPG particles stretched along its axis, its
// kernel updated every third step, the rows held are exactly those and fewer than every row where a
// rank owns some nodes but not all, and the internal forces on every node are, bit for bit, those
// of the bar dealt whole to one rank, through a new deal (the rows a rank reads anew come from the
// ranks that computed them) and continued from a restart file (each rank's own rows in pieces) read
// into the deal it was written in or into a new one. The bonds themselves (neighbours, flags, rest
// lengths) and the particles' state are held for the rows and particles read alike. Under MPI the
// set-up searches no bond, builds no row and holds no state: each rank builds its own at the first
// deal, and a support too small for a linear field there stops every rank with the one-process
// run's message.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "spall/solver/problem.hpp"
#include "spall/spg/formulation.hpp"
#include "support/forces_over_ranks.hpp"
#include "support/spg_block.hpp"

namespace spall {
namespace {

constexpr Real dt = 4e-7;  // s, under a third of the particles' stable step (10 mm / 5 000 m/s)

// The bar (test_support::bar_along_z) pulled at v_z = rate z.
solver::Problem bar_problem() {
  test_support::SpgBlock b = test_support::bar_along_z();
  b.section.smstep = 3;
  solver::Problem problem = solver::build_problem(test_support::spg_block_model(b));
  test_support::pull(problem.nodes, 2, 200);  // 1/s
  return problem;
}

discretization::Formulation& formulation(solver::Problem& problem) { return *problem.formulations.at(0); }

const spg::Part& part(solver::Problem& problem) {
  return dynamic_cast<const spg::SpgFormulation&>(formulation(problem)).parts().at(0);
}

void step(solver::Problem& problem) {
  for (Index i = 0; i < problem.nodes.size(); ++i) problem.nodes.f[i] = Vec3::Zero();
  formulation(problem).compute_forces(problem.nodes, dt);
  for (Index i = 0; i < problem.nodes.size(); ++i) problem.nodes.x[i] += dt * problem.nodes.v[i];
}

// Checks the rows whose shape functions a rank holds, and the particles whose state it holds: those
// of its own particles and their bond partners, from the first to the last, and fewer than every
// row where it owns some nodes but not all. Every node is a particle, particle a on node a.
void expect_held_rows(solver::Problem& problem) {
  const parallel::Communicator& ranks = parallel::world();
  const discretization::NodeStore& nodes = problem.nodes;
  const spg::Part& p = part(problem);
  const spg::BondList& bonds = p.bonds();
  ASSERT_EQ(p.particle_count(), nodes.size());
  parallel::Range read, own;
  Index owned = 0;
  for (Index a = 0; a < p.particle_count(); ++a) {
    if (!nodes.owns(a)) continue;
    ++owned;
    own = parallel::hull(own, {a, a + 1});
    read = parallel::hull(read, {a, a + 1});
    for (Index k = bonds.offsets[a]; k < bonds.offsets[a + 1]; ++k)
      read = parallel::hull(read, {bonds.neighbour[k], bonds.neighbour[k] + 1});
  }
  const parallel::Range held = p.held_shape_rows();
  const Index every = bonds.entry_count();
  if (owned == 0 || owned == nodes.size()) return;
  EXPECT_EQ(held.begin, bonds.offsets[read.begin]) << "rank " << ranks.rank();
  EXPECT_EQ(held.end, bonds.offsets[read.end]) << "rank " << ranks.rank();
  EXPECT_LT(held.end - held.begin, every) << "rank " << ranks.rank() << " holds every row";
  // The bonds themselves alike, and their mirrors for the rows of the rank's own particles.
  for (const parallel::Range bond_rows :
       {parallel::Range{bonds.neighbour.held_begin(), bonds.neighbour.held_end()},
        parallel::Range{bonds.broken.held_begin(), bonds.broken.held_end()},
        parallel::Range{bonds.rest_length.held_begin(), bonds.rest_length.held_end()}}) {
    EXPECT_EQ(bond_rows.begin, held.begin) << "rank " << ranks.rank();
    EXPECT_EQ(bond_rows.end, held.end) << "rank " << ranks.rank();
  }
  EXPECT_EQ(bonds.mirror.held_begin(), bonds.offsets[own.begin]) << "rank " << ranks.rank();
  EXPECT_EQ(bonds.mirror.held_end(), bonds.offsets[own.end]) << "rank " << ranks.rank();
  // The particles' state (F, the material point, the spring, the step's scratch) alike.
  EXPECT_EQ(p.held_state().begin, read.begin) << "rank " << ranks.rank();
  EXPECT_EQ(p.held_state().end, read.end) << "rank " << ranks.rank();
}

// The bar's runs (test_support::dealt_forces, restarted_forces): the rows are held from the first
// step on, so none is checked right after a restart file was read.
struct Bar {
  solver::Problem make() const { return bar_problem(); }
  void deal(solver::Problem& problem, const std::vector<Index>& begins) const {
    problem.nodes.deal(begins, parallel::world().rank());
  }
  void step(solver::Problem& problem) const { spall::step(problem); }
  discretization::Formulation& formulation(solver::Problem& problem) const { return spall::formulation(problem); }
  void check(solver::Problem& problem, bool read) const {
    if (!read) expect_held_rows(problem);
  }
};

TEST(SpgOverRanks, ARankHoldsTheShapeFunctionsOfTheRowsItReadsAndForcesAreOneRanks) {
  log::set_quiet(true);
  const Index n = 25 * 4 * 4;
  // The blocks shifted two layers of nodes on; a kernel update every third step of 12.
  test_support::expect_body_forces_of_one_rank(n, 37, Bar{}, 12);
}

TEST(SpgOverRanks, TheSetUpBuildsNoRowUnderMpi) {
  log::set_quiet(true);
  solver::Problem problem = bar_problem();
  const parallel::Communicator& ranks = parallel::world();
  const parallel::Range held = part(problem).held_shape_rows();
  const Index every = part(problem).bonds().entry_count();
  EXPECT_EQ(every > 0, ranks.size() == 1);  // under MPI no bond is searched before the deal either
  EXPECT_EQ(held.end - held.begin, ranks.size() == 1 ? every : 0);
  EXPECT_EQ(part(problem).held_state().size(), ranks.size() == 1 ? part(problem).particle_count() : 0);
  problem.nodes.deal(parallel::block_offsets(problem.nodes.size(), ranks.size()), ranks.rank());
  step(problem);
  expect_held_rows(problem);
}

// DX 1.0 on a regular mesh: the support ends exactly at the neighbours, where the window is 0
// (test_spg_setup's one-process case): every rank stops at the first deal, naming node 1.
TEST(SpgOverRanks, ASupportTooSmallStopsEveryRankWithTheOneProcessMessage) {
  log::set_quiet(true);
  const test_support::SpgBlock b = test_support::support_too_small(6);
  const parallel::Communicator& ranks = parallel::world();
  std::string message;
  try {
    solver::Problem problem = solver::build_problem(test_support::spg_block_model(b));
    problem.nodes.deal(parallel::block_offsets(problem.nodes.size(), ranks.size()), ranks.rank());
    step(problem);
  } catch (const InputError& e) {
    message = e.what();
  }
  EXPECT_NE(message.find("*SECTION_SOLID_SPG"), std::string::npos) << "rank " << ranks.rank() << ": " << message;
  EXPECT_NE(message.find("singular moment matrix"), std::string::npos) << message;
  EXPECT_NE(message.find("node 1 "), std::string::npos) << message;
}

}  // namespace
}  // namespace spall
