#include "spall/discretization/node_store.hpp"

#include <numeric>
#include <stdexcept>

#include "spall/core/communicator.hpp"

namespace spall::discretization {

namespace {
template <typename T>
void take(std::vector<T>& values, std::span<const Index> kept) {
  std::vector<T> out(kept.size());
  for (std::size_t k = 0; k < kept.size(); ++k) out[k] = values[kept[k]];
  values.swap(out);
}
}  // namespace

Index NodeStore::row_of(Index deck) const {
  if (global.empty()) return deck >= 0 && deck < size() ? deck : -1;
  const auto sorted_end = by_deck_.begin() + static_cast<std::ptrdiff_t>(sorted_by_deck_);
  const auto at = std::lower_bound(by_deck_.begin(), sorted_end, std::pair<Index, Index>{deck, -1});
  if (at != sorted_end && at->first == deck) return at->second;
  for (auto added = sorted_end; added != by_deck_.end(); ++added)
    if (added->first == deck) return added->second;
  return -1;
}

void NodeStore::index_by_deck() {
  by_deck_.resize(global.size());
  for (Index i = 0; i < size(); ++i) by_deck_[i] = {global[i], i};
  std::sort(by_deck_.begin(), by_deck_.end());
  sorted_by_deck_ = by_deck_.size();
}

Index NodeStore::add(const Row& row, int by) {
  if (global.empty()) {
    deck_nodes_ = size();
    global.resize(size());
    std::iota(global.begin(), global.end(), Index(0));
    index_by_deck();
  }
  const Index i = size();
  global.push_back(static_cast<Index>(row.global));
  id.push_back(row.id);
  part.push_back(row.part);
  x0.push_back(row.x0);
  x.push_back(row.x);
  v.push_back(row.v);
  f.push_back(Vec3::Zero());
  mass.push_back(row.mass);
  fixed.push_back(row.fixed);
  active.push_back(row.active);
  body.push_back(row.body);
  owner.push_back(by);
  by_deck_.emplace_back(global.back(), i);
  owned_end = size();
  return i;
}

void NodeStore::keep(std::span<const Index> kept) {
  if (!by_region()) throw std::logic_error("NodeStore::keep: rows of a rank's own need the nodes dealt by region");
  if (global.empty()) {
    deck_nodes_ = size();
    global.resize(size());
    std::iota(global.begin(), global.end(), Index(0));
  }
  take(global, kept);
  take(id, kept);
  take(part, kept);
  take(x0, kept);
  take(x, kept);
  take(v, kept);
  take(f, kept);
  take(mass, kept);
  take(fixed, kept);
  take(active, kept);
  take(body, kept);
  take(owner, kept);
  owned_end = size();
  list_owned();
  index_by_deck();
  ++partition;
}

void NodeStore::gather_on_first_rank() {
  const parallel::Communicator& ranks = parallel::world();
  struct Owned {
    Row row;
    std::int64_t rank;
  };
  std::vector<std::vector<Owned>> out(ranks.size());
  for (const Index i : owned) out[0].push_back({row(i), rank});
  const std::vector<Owned> all = ranks.deliver(out);
  ++partition;
  if (rank != 0) return;
  const Index n = global.empty() ? size() : deck_nodes_;
  if (static_cast<Index>(all.size()) != n)
    throw std::logic_error("NodeStore::gather_on_first_rank: the ranks' own nodes are not every node once");
  resize(n);
  owner.assign(n, 0);
  global.clear();
  by_deck_.clear();
  sorted_by_deck_ = 0;
  std::vector<std::uint8_t> seen(n, 0);
  for (const Owned& o : all) {
    const Index i = static_cast<Index>(o.row.global);
    if (i < 0 || i >= n || seen[i]++)
      throw std::logic_error("NodeStore::gather_on_first_rank: the ranks' own nodes are not every node once");
    id[i] = o.row.id;
    part[i] = o.row.part;
    x0[i] = o.row.x0;
    x[i] = o.row.x;
    v[i] = o.row.v;
    mass[i] = o.row.mass;
    fixed[i] = o.row.fixed;
    active[i] = o.row.active;
    body[i] = o.row.body;
    owner[i] = static_cast<std::int32_t>(o.rank);
  }
  list_owned();
}

}  // namespace spall::discretization
