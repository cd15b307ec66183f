// The output field set (discretization/field_set.hpp, docs/OUTPUT.md "Fields are merged by
// name"): a name two formulations write is one field, the entries nobody wrote hold the documented
// fill values (NaN, -1), a name asked for with other components is a programming error, and cell
// blocks keep their shape and connectivity.
#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include "spall/discretization/field_set.hpp"

namespace spall::discretization {
namespace {

TEST(FieldSet, TwoWritersOfOneNameShareOneFieldAndTheRestIsFilled) {
  FieldSet fields(4);
  fields.node_real("pressure")[0] = 1.5;  // one formulation's node
  fields.node_real("pressure")[2] = -2.0;  // another's
  fields.node_integer("bond_count")[3] = 7;
  ASSERT_EQ(fields.node_fields().size(), 2u);
  const auto& pressure = std::get<std::vector<double>>(fields.node_fields()[0].values);
  EXPECT_EQ(pressure[0], 1.5);
  EXPECT_EQ(pressure[2], -2.0);
  EXPECT_TRUE(std::isnan(pressure[1]) && std::isnan(pressure[3]));
  const auto& bonds = std::get<std::vector<std::int64_t>>(fields.node_fields()[1].values);
  EXPECT_EQ(bonds, (std::vector<std::int64_t>{-1, -1, -1, 7}));
}

TEST(FieldSet, ANameAskedForWithOtherComponentsOrKindIsRefused) {
  FieldSet fields(2);
  fields.node_real("stress", 6, symmetric_tensor_components);
  EXPECT_EQ(fields.node_real("stress", 6).size(), 12u);
  EXPECT_THROW(fields.node_real("stress", 3), std::logic_error);
  EXPECT_THROW(fields.node_integer("stress", 6), std::logic_error);
}

// Under MPI in blocks a rank's set holds its block of the nodes: written by node index as a set of
// every node is, holding the block's entries, the other nodes' values (another rank's) let go.
TEST(FieldSet, AWindowHoldsItsNodesAlone) {
  FieldSet fields(3, 5);  // nodes 3 and 4 of a deck's nodes
  EXPECT_EQ(fields.first_node(), 3);
  EXPECT_EQ(fields.node_count(), 2);
  const auto stress = fields.node_real("stress", 6, symmetric_tensor_components);
  EXPECT_EQ(stress.size(), 12u);
  for (int node = 0; node < 8; ++node)
    for (int c = 0; c < 6; ++c) stress[6 * node + c] = 10 * node + c;
  fields.node_integer("bond_count")[4] = 7;
  fields.node_integer("bond_count")[0] = 9;  // another rank's node
  const auto& held = std::get<std::vector<double>>(fields.node_fields()[0].values);
  ASSERT_EQ(held.size(), 12u);
  for (int c = 0; c < 6; ++c) {
    EXPECT_EQ(held[c], 30 + c);
    EXPECT_EQ(held[6 + c], 40 + c);
  }
  EXPECT_EQ(std::get<std::vector<std::int64_t>>(fields.node_fields()[1].values), (std::vector<std::int64_t>{-1, 7}));
}

TEST(FieldSet, CellBlocksKeepShapeAndConnectivity) {
  FieldSet fields(8);
  CellBlock& block = fields.add_cell_block(CellShape::tetrahedron);
  block.connectivity = {0, 1, 2, 3, 4, 5, 6, 7};
  ASSERT_EQ(fields.cell_blocks().size(), 1u);
  EXPECT_EQ(fields.cell_blocks()[0].shape, CellShape::tetrahedron);
  EXPECT_EQ(fields.cell_blocks()[0].cell_count(), 2u);
  EXPECT_EQ(nodes_per_cell(CellShape::hexahedron), 8);
}

}  // namespace
}  // namespace spall::discretization
