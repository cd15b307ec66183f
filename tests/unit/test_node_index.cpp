// The set-up's index from the deck's node IDs to the node store's rows: a table by ID where the IDs
// are dense, a hash map where they are sparse; both answer alike.
#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "spall/discretization/node_index.hpp"

namespace spall::discretization {
namespace {

void expect_rows(const NodeIndex& index, const std::vector<Id>& ids) {
  for (std::size_t k = 0; k < ids.size(); ++k) {
    ASSERT_NE(index.find(ids[k]), nullptr) << "ID " << ids[k];
    EXPECT_EQ(*index.find(ids[k]), static_cast<Index>(k));
    EXPECT_EQ(index.at(ids[k]), static_cast<Index>(k));
  }
}

TEST(NodeIndex, DenseIdsInAnyOrder) {
  const std::vector<Id> ids{7, 3, 5, 4, 9, 8};  // 6 is missing
  NodeIndex index;
  EXPECT_EQ(index.assign(ids), -1);
  expect_rows(index, ids);
  for (Id missing : {Id(6), Id(2), Id(10), Id(-1), Id(1) << 40}) EXPECT_EQ(index.find(missing), nullptr) << missing;
  EXPECT_THROW(index.at(6), std::logic_error);
}

TEST(NodeIndex, SparseIdsUseAHashAndAnswerAlike) {
  const std::vector<Id> ids{1000000000, 1, 2000000000000, 42};
  NodeIndex index;
  EXPECT_EQ(index.assign(ids), -1);
  expect_rows(index, ids);
  for (Id missing : {Id(0), Id(2), Id(1000000001)}) EXPECT_EQ(index.find(missing), nullptr) << missing;
}

TEST(NodeIndex, TheFirstRepeatedIdIsReported) {
  NodeIndex dense, sparse;
  EXPECT_EQ(dense.assign(std::vector<Id>{1, 2, 3, 2, 1}), 3);
  EXPECT_EQ(sparse.assign(std::vector<Id>{1, Id(1) << 50, 3, Id(1) << 50, 1}), 3);
  EXPECT_EQ(NodeIndex().assign({}), -1);
}

TEST(NodeIndex, AssignReplacesTheIds) {
  NodeIndex index;
  index.assign(std::vector<Id>{1, Id(1) << 50});
  const std::vector<Id> ids{10, 11};
  EXPECT_EQ(index.assign(ids), -1);
  expect_rows(index, ids);
  EXPECT_EQ(index.find(1), nullptr);
}

}  // namespace
}  // namespace spall::discretization
