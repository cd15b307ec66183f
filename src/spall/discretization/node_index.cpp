#include "spall/discretization/node_index.hpp"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace spall::discretization {

Index NodeIndex::assign(std::span<const Id> ids) {
  table_.clear();
  sparse_.clear();
  if (ids.empty()) return -1;
  const auto [low, high] = std::minmax_element(ids.begin(), ids.end());
  // A table while the span of IDs is at most twice the nodes (and a few more): never more than
  // 8 B a node, a quarter of the hash map's.
  const double span = static_cast<double>(*high) - static_cast<double>(*low) + 1;
  dense_ = span <= 2.0 * static_cast<double>(ids.size()) + 1024;
  first_ = *low;
  if (dense_) table_.assign(static_cast<std::size_t>(span), -1);
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const Index row = static_cast<Index>(k);
    if (dense_) {
      Index& slot = table_[static_cast<std::size_t>(ids[k] - first_)];
      if (slot >= 0) return row;
      slot = row;
    } else if (!sparse_.emplace(ids[k], row).second) {
      return row;
    }
  }
  return -1;
}

Index NodeIndex::at(Id id) const {
  const Index* row = find(id);
  if (!row) throw std::logic_error("node " + std::to_string(id) + " is not in the node index");
  return *row;
}

}  // namespace spall::discretization
