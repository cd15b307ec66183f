// The SPH solid's state over several ranks, run as 1, 2 and 3 ranks (docs/SCALING.md §3, "The
// read state in a stretch"): a rank sets up the state of its own particles alone, and holds what
// the rows read of their neighbours (records, h, density, volume, sound speed, stress records and
// forces, and from the first list build the constants: material, initial h, mass and spacing) for
// the stretch of particles from the first its rows read to the last, not for every particle. On a
// bar stretched along its axis, the stretch holds every particle a rank's rows read and is shorter
// than the bar, and the internal forces on every node are, bit for bit, those of the bar dealt
// whole to one rank (the pair sums are taken in one order whatever the deal: THEORY §3). The bar's
// particles alternate between two materials and three masses, their h follows the density, and
// the artificial stress is on, so that every constant a row reads of its neighbours matters. The run
// continued from a restart file (read into the deal it was written in, and into a new one) gives the
// same forces, and right after the read a rank holds its own particles' state alone.
#include <gtest/gtest.h>

#include <variant>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/log.hpp"
#include "spall/solver/problem.hpp"
#include "spall/sph/solid.hpp"
#include "support/forces_over_ranks.hpp"
#include "support/sph_block.hpp"

namespace spall {
namespace {

// The bar (50 x 5 x 5 particles along x) pulled at v_x = rate x.
solver::Problem bar_problem() {
  test_support::ElasticBlock bar;
  model::Model model = test_support::elastic_block_model(bar);
  auto& section = std::get<model::SectionSph>(model.sections[1]);
  section.hmin = 0.2, section.hmax = 2;
  model.parts.push_back({2, "aluminium", 1, 2, 0, 0, 0, {}, {}});
  model::Material aluminium = model.materials[1];
  aluminium.id = 2;
  aluminium.params = model::MatElastic{2700, 70e9, 0.33, 0, 0};
  model.materials[2] = aluminium;
  for (std::size_t k = 0; k < model.sph_elements.size(); ++k) {
    model.sph_elements[k].pid = k % 2 ? 2 : 1;
    model.sph_elements[k].mass *= 1 - 0.05 * static_cast<Real>(k % 3);  // no h above the bar's: rows no longer
  }
  model.sph_artificial_stress = model::SphArtificialStress{};
  solver::Problem problem = solver::build_problem(model);
  test_support::pull(problem.nodes, 0, 100);  // 1/s: a strain of 1e-6 a step
  return problem;
}

sph::SolidFormulation& solid(solver::Problem& problem) {
  return dynamic_cast<sph::SolidFormulation&>(*problem.formulations[0]);
}

void step(solver::Problem& problem) {
  for (Index i = 0; i < problem.nodes.size(); ++i) problem.nodes.f[i] = Vec3::Zero();
  solid(problem).compute_forces(problem.nodes, 1e-8);
}

// Checks the stretch a rank holds: every particle its rows read, and not every particle where it
// owns some but not all.
void expect_held_stretch(solver::Problem& problem) {
  const parallel::Communicator& ranks = parallel::world();
  const sph::SolidFormulation& sph = solid(problem);
  const neighbors::ParticleRange held = sph.read_state_held();
  const auto& list = sph.neighbor_list();
  const auto in_held = [&](Index a) { return a >= held.begin && a < held.end; };
  Index own = 0, unheld = 0;
  for (Index a = 0; a < sph.particle_count(); ++a) {
    if (!problem.nodes.owns(sph.node_of(a))) continue;
    ++own;
    unheld += !in_held(a);
    for (Index k = list.offsets[a]; k < list.offsets[a + 1]; ++k) unheld += !in_held(list.neighbors[k]);
  }
  EXPECT_EQ(unheld, 0) << "rank " << ranks.rank() << " reads particles beyond its stretch";
  if (own > 0 && own < sph.particle_count()) {
    EXPECT_LT(held.end - held.begin, sph.particle_count()) << "rank " << ranks.rank() << " holds every particle";
  }
}

// The bar's runs (test_support::dealt_forces, restarted_forces): four steps, a new deal after two
// (the state and constants travel to the ranks whose rows now read them). Read back from a restart
// file, a rank holds its own particles' state alone before its first step (docs/SCALING.md §3, "The
// list's positions at its build by rank").
struct Bar {
  solver::Problem make() const { return bar_problem(); }
  void deal(solver::Problem& problem, const std::vector<Index>& begins) const {
    problem.nodes.deal(begins, parallel::world().rank());
  }
  void step(solver::Problem& problem) const { spall::step(problem); }
  discretization::Formulation& formulation(solver::Problem& problem) const { return solid(problem); }
  void check(solver::Problem& problem, bool read) const {
    if (!read) return expect_held_stretch(problem);
    const neighbors::ParticleRange held = solid(problem).read_state_held();
    Index own = 0;
    for (Index a = 0; a < solid(problem).particle_count(); ++a) own += problem.nodes.owns(solid(problem).node_of(a));
    EXPECT_EQ(held.end - held.begin, own) << "rank " << parallel::world().rank() << " read more than its own particles' state";
  }
};

TEST(SphSolidOverRanks, ARankHoldsTheStateItsRowsReadAndForcesAreOneRanks) {
  log::set_quiet(true);
  const Index n = 50 * 5 * 5;
  // The blocks shifted within the stretches of a 50-long bar.
  test_support::expect_body_forces_of_one_rank(n, 10, Bar{}, 4);
}

}  // namespace
}  // namespace spall
