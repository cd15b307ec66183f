#include "spall/discretization/node_store.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>

#include "spall/core/communicator.hpp"
#include "spall/core/pieces.hpp"
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

// Row i's state from a row that travelled or was checkpointed (the force is not in it).
void set_state(NodeStore& nodes, Index i, const NodeStore::Row& row) {
  nodes.id[i] = row.id;
  nodes.part[i] = row.part;
  nodes.x0[i] = row.x0;
  nodes.x[i] = row.x;
  nodes.v[i] = row.v;
  nodes.mass[i] = row.mass;
  nodes.fixed[i] = row.fixed;
  nodes.active[i] = row.active;
  nodes.body[i] = row.body;
}

// Row i from a row that travelled, computed by `rank` (its force is this rank's own, zero at a
// rebuild).
void set_row(NodeStore& nodes, Index i, const NodeStore::Row& row, int rank) {
  set_state(nodes, i, row);
  nodes.owner[i] = rank;
}

// A node's row in a checkpoint: what travels with it between ranks, and its force.
struct SavedRow {
  NodeStore::Row row;
  Vec3 f;
};
}  // namespace
}  // namespace spall::discretization

namespace spall {
template <>
inline constexpr bool archived_as_bytes<discretization::SavedRow> = true;
}  // namespace spall

namespace spall::discretization {

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

std::pair<Index, Index> NodeStore::places_held() const {
  if (!numbered_) return {std::numeric_limits<Index>::min(), std::numeric_limits<Index>::max()};
  if (size() == 0) return {0, 0};
  const auto [lowest, highest] = std::minmax_element(global.begin(), global.end());
  return {*lowest, *highest + 1};
}

void NodeStore::checkpoint(Archive& a) {
  a.expect_size("nodes", static_cast<std::size_t>(deck_node_count()));
  const parallel::Communicator& ranks = parallel::world();
  if (!a.reading()) {
    // By region each rank's own rows, else rank 0's every row (those are in the deck's order).
    std::vector<std::pair<Index, Index>> rows;  // (place in the deck, row), sorted
    if (by_region()) {
      for (const Index i : owned) rows.emplace_back(deck_index(i), i);
      std::sort(rows.begin(), rows.end());
    }
    const Index count = by_region() ? static_cast<Index>(rows.size()) : ranks.rank() == 0 ? size() : 0;
    const auto row_at = [&](Index k) { return by_region() ? rows[k].second : k; };
    parallel::write_pieces<SavedRow>(
        a, count, [&](Index k) { return SavedRow{row(row_at(k)), f[row_at(k)]}; },
        [&](Index k) { return deck_index(row_at(k)); }, ranks);
    return;
  }
  // Into every node, or into the rows a rank holds (the set-up in blocks built them: hold_block,
  // then dealt), each filled once: the other ranks' rows are read past. A node under another ID or
  // given twice, or one of the rows missing, stops every rank alike.
  std::vector<std::uint8_t> seen(size(), 0);
  Index mismatch = -1;
  const auto [first, end] = places_held();
  parallel::read_pieces<SavedRow>(a, [&](const SavedRow& saved) {
    const Index place = static_cast<Index>(saved.row.global);
    const bool in_deck = place >= 0 && place < deck_node_count();
    const Index i = in_deck ? row_of(place) : -1;
    if (numbered_ && in_deck && i < 0) return;  // another rank's row
    if (i < 0 || seen[i]++ || saved.row.id != id[i]) {
      if (mismatch < 0) mismatch = std::max<Index>(place, 0);
      return;
    }
    set_state(*this, i, saved.row);
    f[i] = saved.f;
  }, first, end, numbered_ ? &ranks : nullptr);
  const auto unseen = std::find(seen.begin(), seen.end(), 0);
  Index missing = unseen == seen.end() ? -1 : deck_index(static_cast<Index>(unseen - seen.begin()));
  parallel::check_read(a, "node", mismatch, missing, numbered_ ? &ranks : nullptr);
}

}  // namespace spall::discretization
