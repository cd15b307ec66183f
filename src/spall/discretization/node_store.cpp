#include "spall/discretization/node_store.hpp"

#include "spall/core/communicator.hpp"

namespace spall::discretization {

bool NodeStore::migrate(std::span<const Index> moving) {
  if (!by_region()) return false;
  struct Change {
    Index node;
    std::int64_t rank;  // 64 bits: no padding travels
  };
  std::vector<Change> changes;
  for (const Index i : moving) {
    if (!owns(i)) continue;
    const int r = regions.rank_of(x[i]);
    if (r != owner[i]) changes.push_back({i, r});
  }
  const std::vector<Change> all = parallel::world().all(std::span<const Change>(changes));
  if (all.empty()) return false;
  for (const Change& c : all) owner[c.node] = static_cast<std::int32_t>(c.rank);
  list_owned();
  ++partition;
  return true;
}

}  // namespace spall::discretization
