#include "spall/discretization/node_store.hpp"

#include <numeric>

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
  const parallel::Communicator& ranks = parallel::world();
  const std::vector<Index> counts = ranks.each(static_cast<Index>(changes.size()));
  std::vector<Index> offsets(counts.size() + 1, 0);
  std::partial_sum(counts.begin(), counts.end(), offsets.begin() + 1);
  if (offsets.back() == 0) return false;
  std::vector<Change> all(offsets.back());
  std::copy(changes.begin(), changes.end(), all.begin() + offsets[ranks.rank()]);
  ranks.share(std::span(all), offsets);
  for (const Change& c : all) owner[c.node] = static_cast<std::int32_t>(c.rank);
  list_owned();
  ++partition;
  return true;
}

}  // namespace spall::discretization
