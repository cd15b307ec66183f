// The node order's axes (docs/SCALING.md §3, "The node order's axes"): the set-up's cells are
// row-major from the box's shortest axis to its longest, so that a block of the order (a rank's
// nodes under MPI) is a slab across a body's length, whose elements and particles read the nodes
// within a cell either side. A bar of 24 x 3 x 3 SPG elements laid along x, along y and along z:
// the nodes within a bond's reach of the first quarter of the node order lie within two slabs of
// cells after it in the order, whatever the axis (with x the fastest axis whatever the shape, the
// first quarter of a bar along x was a row of cells along it, whose neighbours lie a whole layer of
// cells on in the order).
#include <gtest/gtest.h>

#include <algorithm>
#include <array>

#include "spall/core/bounding_box.hpp"
#include "spall/core/log.hpp"
#include "spall/solver/nodes_in_blocks.hpp"
#include "spall/solver/problem.hpp"
#include "support/spg_block.hpp"

namespace spall {
namespace {

TEST(NodeOrder, TheLongestAxisIsTheSlowest) {
  BoundingBox box;
  box.include(Vec3(0, 0, 0));
  box.include(Vec3(0.3, 2, 0.1));
  const solver::NodeOrderAxes axes(box);
  EXPECT_EQ(axes.axis, (std::array<int, 3>{2, 0, 1}));
  EXPECT_EQ(axes(Vec3(1, 2, 3)), Vec3(3, 1, 2));
  BoundingBox cube;
  cube.include(Vec3(0, 0, 0));
  cube.include(Vec3(1, 1, 1));
  EXPECT_EQ(solver::NodeOrderAxes(cube).axis, (std::array<int, 3>{0, 1, 2})) << "ties keep x, y, z";
}

TEST(NodeOrder, TheNodesNearAQuarterOfTheOrderFollowItWithinTwoSlabsOfCells) {
  log::set_quiet(true);
  constexpr Real length = 0.24, width = 0.03, spacing = 0.01;
  for (int along = 0; along < 3; ++along) {
    test_support::SpgBlock b;
    b.size = Vec3::Constant(width);
    b.size[along] = length;
    b.elements = {3, 3, 3};
    b.elements[along] = 24;
    const solver::Problem problem = solver::build_problem(test_support::spg_block_model(b));
    const auto& nodes = problem.nodes;
    const Index n = nodes.size(), quarter = n / 4;
    BoundingBox box;
    for (Index i = 0; i < n; ++i) box.include(nodes.x0[i]);
    const Real cell = solver::node_order_cell(box, n);
    // The last place in the order of a node within 1.6 spacings (a bond) of the first quarter's.
    Index last = quarter - 1;
    for (Index i = 0; i < quarter; ++i)
      for (Index j = quarter; j < n; ++j)
        if ((nodes.x0[j] - nodes.x0[i]).lpNorm<Eigen::Infinity>() < 1.6 * spacing) last = std::max(last, j);
    const Real slab = static_cast<Real>(n) * cell / length;  // the nodes of a slab of cells across the bar
    EXPECT_LE(last - quarter, 2 * slab) << "the bar along axis " << along;
  }
}

}  // namespace
}  // namespace spall
