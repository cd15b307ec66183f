// The solid elements' state over several ranks, run as 1, 2 and 3 ranks (docs/SCALING.md §3, "Solid
// elements by rank"): a rank computes the elements with a node of its block of the node order and
// holds the state of the stretch from the first of them to the last alone (the elements are kept
// in the order of their first nodes), not every element's. On a bar of hexahedra stretched along
// its axis past yield, half of it one-point hexahedra (ELFORM 1, stiffness hourglass control,
// kinematic hardening: state at the point, the back stress and the hourglass forces) and half fully
// integrated (ELFORM 2, eight points an element), the stretch holds every element a rank computes
// and is shorter than the bar, and the internal forces on every node are, bit for bit, those of the
// bar dealt whole to one rank (each node sums its elements in colour order: THEORY §10), through a
// new deal (the state goes to the ranks that compute it now) and continued from a restart file read
// into the deal it was written in or into a new one, right after which a rank holds its stretch
// alone. The same once more with the velocities by reach and the rows a window of the node order
// (the elements alone in a deck, NodeStore::window_by_reads): a rank holds the window from the first
// of its own nodes and its elements' to the last, fewer rows than every node, and the forces are
// still the single rank's, through the new deals (each row current, from the rank that computed it)
// and the restart files (each rank's own rows).
#include <gtest/gtest.h>

#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/log.hpp"
#include "spall/fem/solid_elements.hpp"
#include "spall/solver/problem.hpp"
#include "support/forces_over_ranks.hpp"
#include "support/spg_block.hpp"

namespace spall {
namespace {

constexpr Real dt = 5e-7;  // s, under a third of the elements' stable step (10 mm / 5 800 m/s)

// The bar (test_support::bar_along_z, as hexahedra) pulled at v_z = rate z: a strain of 2.5e-4 a
// step, past the yield strain 1.75e-3 from the eighth step on.
solver::Problem bar_problem() {
  test_support::SpgBlock b = test_support::bar_along_z();
  b.fem = test_support::FiniteElements{1, model::Hourglass{1, 4, 0.1, 0, 0, {}}};
  model::Model m = test_support::spg_block_model(b);
  model::MatPlasticKinematic steel{7850, 200e9, 0.3, 350e6, 1e9, 0.5};  // BETA 0.5: a back stress
  m.materials[1].keyword = "*MAT_PLASTIC_KINEMATIC";
  m.materials[1].params = steel;
  model::SectionSolid full;
  full.id = 2;
  full.elform = 2;
  m.sections[2] = full;
  m.parts.push_back({2, "fully integrated", 2, 1, 0, 0, 0, {}, {}});
  for (auto& e : m.solid_elements) e.pid = e.eid % 2 ? 1 : 2;  // the deck's order is not the node order
  solver::Problem problem = solver::build_problem(m);
  test_support::pull(problem.nodes, 2, 500);  // 1/s
  return problem;
}

fem::SolidElements& elements(solver::Problem& problem) {
  return dynamic_cast<fem::SolidElements&>(*problem.formulations.at(0));
}

void step(solver::Problem& problem) {
  for (Index i = 0; i < problem.nodes.size(); ++i) problem.nodes.f[i] = Vec3::Zero();
  elements(problem).compute_forces(problem.nodes, dt);
  for (Index i = 0; i < problem.nodes.size(); ++i) problem.nodes.x[i] += dt * problem.nodes.v[i];
}

// Checks the stretch a rank holds of each block: every element it computes (one with a node it
// owns), and not every element where it owns some nodes but not all; and, where the rows are a
// window (`window`), that they are those its elements read and its own, fewer than every node.
// Returns the elements held.
Index expect_held_stretch(solver::Problem& problem, bool window = true) {
  const parallel::Communicator& ranks = parallel::world();
  const fem::SolidElements& fem = elements(problem);
  const discretization::NodeStore& nodes = problem.nodes;
  Index held = 0, owned_nodes = 0;
  for (Index i = 0; i < nodes.size(); ++i) owned_nodes += nodes.owns(i);
  parallel::Range read{nodes.rank_begin[ranks.rank()], nodes.rank_begin[ranks.rank() + 1]};
  for (std::size_t k = 0; k < fem.blocks().size(); ++k) {
    const auto& block = fem.blocks()[k];
    const parallel::Range stretch = fem.held(k);
    Index unheld = 0;
    for (Index e = 0; e < block.size(); ++e) {
      const auto place = [&](int a) { return fem.local_nodes()[block.node[block.nodes_per_element * e + a]]; };
      bool computed = false;
      for (int a = 0; a < block.nodes_per_element; ++a) computed |= nodes.owns(nodes.node_row(place(a)));
      unheld += computed && (e < stretch.begin || e >= stretch.end);
      if (computed)
        for (int a = 0; a < block.nodes_per_element; ++a) read = parallel::hull(read, {place(a), place(a) + 1});
    }
    EXPECT_EQ(unheld, 0) << "rank " << ranks.rank() << " computes elements beyond its stretch of block " << k;
    if (owned_nodes > 0 && owned_nodes < nodes.deck_node_count()) {
      EXPECT_LT(stretch.size(), block.size()) << "rank " << ranks.rank() << " holds every element of block " << k;
    }
    held += stretch.size();
  }
  // Its rows a window of the node order: from the first of its own nodes and its elements' to the
  // last, no more (every node where it computes them all).
  if (window && nodes.window_by_reads && owned_nodes < nodes.deck_node_count()) {
    EXPECT_TRUE(nodes.windowed()) << "rank " << ranks.rank() << " holds no window of the nodes";
    EXPECT_EQ(nodes.window().begin, read.begin) << "rank " << ranks.rank();
    EXPECT_EQ(nodes.window().end, read.end) << "rank " << ranks.rank();
    EXPECT_LT(nodes.size(), nodes.deck_node_count()) << "rank " << ranks.rank() << " holds every node";
  }
  return held;
}

// The bar's runs (test_support::dealt_forces, restarted_forces), `window`: with the velocities by
// reach, the rows a window of the nodes from the elements' first step on, as the time loop deals a
// deck of solid elements alone. Right after a restart file was read into dealt nodes, a rank holds
// the stretch of elements it computes alone (the window comes at the first step).
struct Bar {
  bool window = false;
  solver::Problem make() const { return bar_problem(); }
  void deal(solver::Problem& problem, const std::vector<Index>& begins) const {
    problem.nodes.deal(begins, parallel::world().rank());
    problem.nodes.velocities_by_reach = problem.nodes.window_by_reads = window;
  }
  void step(solver::Problem& problem) const { spall::step(problem); }
  discretization::Formulation& formulation(solver::Problem& problem) const { return elements(problem); }
  void check(solver::Problem& problem, bool read) const {
    const Index held = expect_held_stretch(problem, !read);
    if (read && parallel::world().size() > 1) {
      EXPECT_LT(held, elements(problem).element_count())
          << "rank " << parallel::world().rank() << " read every element's state";
    }
  }
};

TEST(SolidElementsOverRanks, ARankHoldsTheStateOfTheElementsItComputesAndForcesAreOneRanks) {
  log::set_quiet(true);
  const Index n = 25 * 4 * 4;
  // The blocks shifted two layers of nodes on.
  test_support::expect_body_forces_of_one_rank(n, 37, Bar{false}, 12);
}

TEST(SolidElementsOverRanks, AloneARankHoldsTheWindowOfTheNodesItsElementsReadAndForcesAreOneRanks) {
  log::set_quiet(true);
  const Index n = 25 * 4 * 4;
  test_support::expect_body_forces_of_one_rank(n, 37, Bar{true}, 12);
}

}  // namespace
}  // namespace spall
