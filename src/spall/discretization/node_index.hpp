#pragma once
// The deck's node IDs to the node store's rows, for the set-up: every card that names a node finds
// its row here. Decks number their nodes mostly without gaps, so where the IDs are dense the index
// is a table by ID (4 B an ID in their span, against about 33 B a node in a hash map); where they
// are sparse, a hash map.
#include <span>
#include <unordered_map>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::discretization {

class NodeIndex {
 public:
  NodeIndex() = default;
  // ids[k] is row k's ID. Returns the first row whose ID an earlier row has, or -1 when none does
  // (the index then holds the rows before it).
  Index assign(std::span<const Id> ids);

  // The row of the node with this ID, nullptr when no node has it.
  const Index* find(Id id) const {
    if (!dense_) {
      auto it = sparse_.find(id);
      return it == sparse_.end() ? nullptr : &it->second;
    }
    if (id < first_ || id - first_ >= static_cast<Id>(table_.size())) return nullptr;
    const Index& row = table_[static_cast<std::size_t>(id - first_)];
    return row < 0 ? nullptr : &row;
  }
  // The row of a node whose ID was checked before; std::logic_error when there is none.
  Index at(Id id) const;

 private:
  bool dense_ = true;
  Id first_ = 0;              // the smallest ID (dense)
  std::vector<Index> table_;  // by ID - first_, -1 where no node has the ID (dense)
  std::unordered_map<Id, Index> sparse_;
};

}  // namespace spall::discretization
