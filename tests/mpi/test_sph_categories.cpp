// The SPH solid's colour-field categorization (seed 000 §4) over several ranks, run as 1, 2 and 3
// ranks: each rank categorizes its own particles, with the surface and layer flags of the other
// ranks' particles its rows read brought in. On a cube at rest the outer layer of particles is
// surface and the next one inner layer (test_sph_colour_field calibrates this on one process);
// the nodes are dealt out at many different points of their order, so that some inner-layer
// particles find their only surface neighbours on another rank: every rank must still categorize
// every particle as one process does.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/log.hpp"
#include "spall/solver/problem.hpp"
#include "spall/sph/solid.hpp"
#include "support/sph_block.hpp"

namespace spall {
namespace {

constexpr int across = 8;
constexpr Real spacing = 0.01;

// Lattice depth of a particle of the cube: 0 on the outer layer.
int depth_in_cube(const Vec3& x) {
  int depth = across;
  for (int d = 0; d < 3; ++d) {
    const int i = static_cast<int>(std::floor(x[d] / spacing));
    depth = std::min({depth, i, across - 1 - i});
  }
  return depth;
}

// The categories after one force pass at rest, with the nodes dealt out at `begins`, and the count
// over the ranks of the particles whose category, on the rank that computes it, differs from the
// cube's layers.
std::int64_t wrong_categories(const std::vector<Index>& begins) {
  test_support::ElasticBlock block;
  block.size = Vec3::Constant(across * spacing);
  block.spacing = spacing;
  model::Model model = test_support::elastic_block_model(block);
  model.sph_colour_fields.push_back(model::SphColourField{});
  solver::Problem problem = solver::build_problem(model);
  problem.nodes.deal(begins, parallel::world().rank());
  auto& sph = dynamic_cast<sph::SolidFormulation&>(*problem.formulations[0]);
  sph.compute_forces(problem.nodes, 0);
  std::int64_t wrong = 0;
  for (Index a = 0; a < sph.particle_count(); ++a) {
    if (!problem.nodes.owns(sph.node_of(a))) continue;
    const int depth = depth_in_cube(problem.nodes.x[sph.node_of(a)]);
    const sph::Category expected =
        depth == 0 ? sph::Category::surface : depth == 1 ? sph::Category::inner_layer : sph::Category::interior;
    wrong += sph.categories()[a] != expected;
  }
  parallel::world().sum({&wrong, 1});
  return wrong;
}

TEST(SphCategoriesOverRanks, EveryDealCategorizesAsOneProcess) {
  log::set_quiet(true);
  const parallel::Communicator& ranks = parallel::world();
  const Index n = across * across * across;
  // Rank r's block begins at r s (the last rank takes the rest), for s from an eighth of the
  // nodes to a whole rank's share, in steps prime to the cells' 16 nodes.
  for (Index s = n / 8; s * (ranks.size() - 1) < n; s += 11) {
    std::vector<Index> begins(ranks.size() + 1, n);
    for (int r = 0; r < ranks.size(); ++r) begins[r] = std::min(n, r * s);
    EXPECT_EQ(wrong_categories(begins), 0) << "blocks of " << s << " nodes";
    if (ranks.size() == 1) break;
  }
}

}  // namespace
}  // namespace spall
