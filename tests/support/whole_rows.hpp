#pragma once
// The rows a set-up in blocks gives a rank under MPI against the whole set-up's
// (test_set_up_in_blocks, test_cards_in_shares): this rank's block of the node order, each row byte for byte the whole
// set-up's at its place (the row as it would travel, every byte set: explicit padding).
#include <gtest/gtest.h>

#include <cstring>

#include "spall/core/communicator.hpp"
#include "spall/discretization/node_store.hpp"

namespace spall::test_support {

inline void expect_whole_rows(const discretization::NodeStore& whole, const discretization::NodeStore& blocks) {
  const parallel::Communicator& ranks = parallel::world();
  EXPECT_EQ(blocks.holds_a_block(), ranks.size() > 1);
  const Index first = parallel::block_begin(whole.size(), ranks.rank(), ranks.size());
  ASSERT_EQ(blocks.size(), parallel::block_begin(whole.size(), ranks.rank() + 1, ranks.size()) - first);
  for (Index r = 0; r < blocks.size(); ++r) {
    const discretization::NodeStore::Row built = blocks.row(r), reference = whole.row(first + r);
    EXPECT_EQ(std::memcmp(&built, &reference, sizeof built), 0) << "node " << blocks.id[r];
  }
}

}  // namespace spall::test_support
