#pragma once
// What the tests of a formulation's state over several ranks share: the deals they compare (the
// nodes whole on rank 0, in blocks, and in blocks shifted), the internal force on every node
// gathered from the ranks that own them, a restart file in memory, and the comparison of the runs.
#include <gtest/gtest.h>

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/communicator.hpp"
#include "spall/discretization/formulation.hpp"
#include "spall/discretization/node_store.hpp"

namespace spall::test_support {

// Pulls a body along `axis` at the rate given: v = rate x_axis along the axis, at every node.
inline void pull(discretization::NodeStore& nodes, int axis, Real rate) {
  for (Index i = 0; i < nodes.size(); ++i) {
    nodes.v[i] = Vec3::Zero();
    nodes.v[i][axis] = rate * nodes.x[i][axis];
  }
}

// NodeStore::deal's first nodes of each rank, and the count after them.
struct Deals {
  std::vector<Index> whole, blocks, shifted;
};

// n nodes: rank 0 computing every one; each rank an equal block; the blocks past the first each
// moved `shift` nodes on.
inline Deals deals(Index n, Index shift) {
  const parallel::Communicator& ranks = parallel::world();
  Deals d{std::vector<Index>(ranks.size() + 1, n), std::vector<Index>(ranks.size() + 1, n),
          std::vector<Index>(ranks.size() + 1, n)};
  d.whole[0] = d.shifted[0] = 0;
  for (int r = 0; r < ranks.size(); ++r) d.blocks[r] = r * n / ranks.size();
  for (int r = 1; r < ranks.size(); ++r) d.shifted[r] = d.blocks[r] + shift;
  return d;
}

// The internal force on every node of the deck, every rank's (its rows every node or a window).
inline std::vector<Vec3> node_forces(const discretization::NodeStore& nodes) {
  struct NodeForce {
    std::int64_t node;
    double f[3];
  };
  const parallel::Communicator& ranks = parallel::world();
  std::vector<NodeForce> mine;
  for (Index i = 0; i < nodes.size(); ++i)
    if (nodes.owns(i)) mine.push_back({nodes.deck_index(i), {nodes.f[i].x(), nodes.f[i].y(), nodes.f[i].z()}});
  std::vector<Vec3> f(nodes.deck_node_count(), Vec3::Zero());
  for (const NodeForce& r : ranks.all(std::span<const NodeForce>(mine))) f[r.node] = Vec3(r.f[0], r.f[1], r.f[2]);
  return f;
}

// The restart file of the nodes and formulation `f` as the ranks write it (the state completed
// first), every rank's copy of it.
inline std::string restart_file(discretization::NodeStore& nodes, discretization::Formulation& f) {
  const parallel::Communicator& ranks = parallel::world();
  f.complete_state(nodes);
  Archive written = ranks.rank() == 0 ? Archive::for_writing() : Archive::discarding();
  nodes.checkpoint(written);
  f.checkpoint(written, nodes);
  const std::string& mine = written.bytes();
  const std::vector<char> whole = ranks.all(std::span<const char>(mine.data(), mine.size()));
  return {whole.begin(), whole.end()};
}

// Reads restart_file's back into the nodes (dealt already) and `f`, to its end.
inline void read_restart_file(const std::string& file, discretization::NodeStore& nodes,
                              discretization::Formulation& f) {
  Archive archive = Archive::for_reading(file, "checkpoint");
  nodes.checkpoint(archive);
  f.checkpoint(archive, nodes);
  EXPECT_TRUE(archive.at_end());
}

// n nodes, the blocks shifted by `shift`: `forces(begins, then)` (the forces after a run dealt at
// `begins`, then at `then`) dealt in blocks and shifted is, on every node and bit for bit, the run
// of rank 0 alone, whose forces are not all zero (the body is loaded); and so is
// `restarted(begins, read_into, then)`, a run written to a restart file in blocks and read back
// into the deal it was written in or into the shifted one, then shifted.
template <class Forces, class Restarted>
void expect_forces_of_one_rank(Index n, Index shift, Forces&& forces, Restarted&& restarted) {
  const auto [whole, blocks, shifted] = deals(n, shift);
  const std::vector<Vec3> reference = forces(whole, whole);
  const auto differing = [&](const std::vector<Vec3>& f) {
    Index differ = 0;
    for (Index i = 0; i < n; ++i) differ += f[i] != reference[i];
    return differ;
  };
  EXPECT_EQ(differing(forces(blocks, shifted)), 0);
  Index zero = 0;
  for (const Vec3& f : reference) zero += f == Vec3::Zero();
  EXPECT_LT(zero, n / 2) << "the body is not loaded";
  for (const auto& read_into : {blocks, shifted})
    EXPECT_EQ(differing(restarted(blocks, read_into, shifted)), 0)
        << "read into the " << (read_into == blocks ? "deal it was written in" : "new deal");
}

// A body's runs for expect_forces_of_one_rank, each test's own: `make()` builds its problem,
// loaded; `deal(problem, begins)` deals its nodes; `step(problem)` takes a step;
// `formulation(problem)` is what a restart file holds beside the nodes; `check(problem, read)`
// checks what each rank holds after a run, or (`read`) right after a restart file was read.
// The forces after `steps` steps of the body dealt at `begins`, dealt at `then` from the middle on.
template <class Body>
std::vector<Vec3> dealt_forces(const Body& body, int steps, const std::vector<Index>& begins,
                               const std::vector<Index>& then) {
  auto problem = body.make();
  body.deal(problem, begins);
  for (int k = 0; k < steps; ++k) {
    if (k == steps / 2) body.deal(problem, then);
    body.step(problem);
  }
  body.check(problem, false);
  return node_forces(problem.nodes);
}

// The same, written to a restart file in the middle and read back into the body dealt at
// `read_into`, then dealt at `then` for the rest.
template <class Body>
std::vector<Vec3> restarted_forces(const Body& body, int steps, const std::vector<Index>& begins,
                                   const std::vector<Index>& read_into, const std::vector<Index>& then) {
  std::string file;
  {
    auto problem = body.make();
    body.deal(problem, begins);
    for (int k = 0; k < steps / 2; ++k) body.step(problem);
    file = restart_file(problem.nodes, body.formulation(problem));
  }
  auto problem = body.make();
  body.deal(problem, read_into);
  read_restart_file(file, problem.nodes, body.formulation(problem));
  body.check(problem, true);
  body.deal(problem, then);
  for (int k = steps / 2; k < steps; ++k) body.step(problem);
  body.check(problem, false);
  return node_forces(problem.nodes);
}

// expect_forces_of_one_rank for a body's runs of `steps` steps (dealt_forces, restarted_forces).
template <class Body>
void expect_body_forces_of_one_rank(Index n, Index shift, const Body& body, int steps) {
  expect_forces_of_one_rank(
      n, shift, [&](const auto& begins, const auto& then) { return dealt_forces(body, steps, begins, then); },
      [&](const auto& begins, const auto& read_into, const auto& then) {
        return restarted_forces(body, steps, begins, read_into, then);
      });
}

}  // namespace spall::test_support
