#include "spall/discretization/node_store.hpp"

#include <numeric>
#include <stdexcept>

#include "spall/core/communicator.hpp"
#include "spall/core/reorder.hpp"

namespace spall::discretization {

namespace {
// Calls visit(array) for each per-row array that goes with a row: the state, its place in the deck
// and its rank.
template <class Visit>
void each_row_array(NodeStore& nodes, Visit&& visit) {
  visit(nodes.global), visit(nodes.id), visit(nodes.part), visit(nodes.x0), visit(nodes.x), visit(nodes.v);
  visit(nodes.f), visit(nodes.mass), visit(nodes.fixed), visit(nodes.active), visit(nodes.body), visit(nodes.owner);
}

// Row i from a row that travelled (its force is this rank's own, zero at a rebuild).
void set_row(NodeStore& nodes, Index i, const NodeStore::Row& row, int rank) {
  nodes.id[i] = row.id;
  nodes.part[i] = row.part;
  nodes.x0[i] = row.x0;
  nodes.x[i] = row.x;
  nodes.v[i] = row.v;
  nodes.mass[i] = row.mass;
  nodes.fixed[i] = row.fixed;
  nodes.active[i] = row.active;
  nodes.body[i] = row.body;
  nodes.owner[i] = rank;
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

void NodeStore::number_rows() {
  if (numbered_) return;
  numbered_ = true;
  deck_nodes_ = size();
  global.resize(size());
  std::iota(global.begin(), global.end(), Index(0));
  index_by_deck();
}

void NodeStore::hold_block(Index first, Index every) {
  deck_nodes_ = every;
  numbered_ = block_ = true;
  global.resize(size());
  std::iota(global.begin(), global.end(), first);
  index_by_deck();
}

Index NodeStore::add(const Row& row, int by) {
  number_rows();
  const Index i = size();
  each_row_array(*this, [](auto& array) { array.emplace_back(); });
  set_row(*this, i, row, by);
  global[i] = static_cast<Index>(row.global);
  f[i] = Vec3::Zero();
  by_deck_.emplace_back(global[i], i);
  owned_end = size();
  return i;
}

void NodeStore::reserve(Index rows) {
  each_row_array(*this, [&](auto& array) { array.reserve(rows); });
  by_deck_.reserve(rows);
}

void NodeStore::keep(std::span<const Index> kept) {
  if (!by_region()) throw std::logic_error("NodeStore::keep: rows of a rank's own need the nodes dealt by region");
  number_rows();
  each_row_array(*this, [&](auto& array) { reorder(array, kept); });
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
  numbered_ = false;
  by_deck_.clear();
  sorted_by_deck_ = 0;
  std::vector<std::uint8_t> seen(n, 0);
  for (const Owned& o : all) {
    const Index i = static_cast<Index>(o.row.global);
    if (i < 0 || i >= n || seen[i]++)
      throw std::logic_error("NodeStore::gather_on_first_rank: the ranks' own nodes are not every node once");
    set_row(*this, i, o.row, static_cast<int>(o.rank));
  }
  list_owned();
}

}  // namespace spall::discretization
