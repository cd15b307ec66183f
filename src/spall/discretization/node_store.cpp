#include "spall/discretization/node_store.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <type_traits>

#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/pieces.hpp"
#include "spall/core/reorder.hpp"

namespace spall::discretization {

namespace {
// Calls visit(array) for each per-row array of a node's state and force.
template <class Visit>
void each_state_array(NodeStore& nodes, Visit&& visit) {
  visit(nodes.id), visit(nodes.part), visit(nodes.x0), visit(nodes.x), visit(nodes.v);
  visit(nodes.f), visit(nodes.mass), visit(nodes.fixed), visit(nodes.active), visit(nodes.body);
}

// Calls visit(array) for each per-row array that goes with a row: the state, its place in the deck
// and its rank.
template <class Visit>
void each_row_array(NodeStore& nodes, Visit&& visit) {
  visit(nodes.global), visit(nodes.owner);
  each_state_array(nodes, visit);
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

// Dealt in blocks: the rows of this rank's own block in its rows (none for an empty block).
void place_owned_rows(NodeStore& nodes) {
  const Index first = nodes.rank_begin[nodes.rank], end = nodes.rank_begin[nodes.rank + 1];
  nodes.owned_begin = first < end ? first - nodes.window_first() : 0;
  nodes.owned_end = first < end ? end - nodes.window_first() : 0;
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
  if (global.empty()) return deck >= window_first_ && deck - window_first_ < size() ? deck - window_first_ : -1;
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
  ++layout;
}

void NodeStore::deal(std::vector<Index> begins, int self) {
  if (block_) {  // the set-up's block of the nodes is this rank's own: the window of them
    if (begins.back() != deck_nodes_ || begins[self + 1] - begins[self] != size() ||
        (size() > 0 && global.front() != begins[self]))
      throw std::logic_error("NodeStore::deal: blocks other than those the set-up built");
    window_first_ = begins[self];
    windowed_ = true;
    numbered_ = false;
    std::vector<Index>().swap(global);
    std::vector<std::pair<Index, Index>>().swap(by_deck_);
    sorted_by_deck_ = 0;
  } else if (windowed_) {  // every rank, its new block empty or not
    const parallel::Range held = parallel::hull(window(), {begins[self], begins[self + 1]});
    hold_window(held.begin, held.end);
  }
  rank_begin = std::move(begins);
  regions = {};
  owned.clear();
  rank = self;
  place_owned_rows(*this);
  std::vector<std::int32_t>().swap(owner);
  block_ = false;
  ++partition;
  ++layout;
}

void NodeStore::hold_window(Index first, Index end) {
  if (by_region() || rank_begin.empty() || numbered_)
    throw std::logic_error("NodeStore::hold_window: the nodes are not dealt in blocks");
  if (!windowed_) deck_nodes_ = size();
  end = std::max(first, end);
  const Index own_first = rank_begin[rank], own_end = rank_begin[rank + 1];
  if (first < 0 || end > deck_nodes_ || (own_first < own_end && (own_first < first || own_end > end)))
    throw std::logic_error("NodeStore::hold_window: a window beyond the nodes or without this rank's own");
  const auto [old_first, old_end] = window();  // every node until a window
  struct Window {
    Index old_first, old_end, first, end;
  };
  const parallel::Communicator& ranks = parallel::world();
  const std::vector<Window> windows = ranks.each(Window{old_first, old_end, first, end});
  // To each other rank, the rows of this rank's own nodes in its new window but not in its old: the
  // stretches of [first, end) ∩ [own_first, own_end) below and above its old window.
  std::vector<std::vector<Row>> out(ranks.size());
  for (int r = 0; r < ranks.size(); ++r) {
    if (r == rank) continue;
    const Window& w = windows[r];
    const Index from = std::max(w.first, own_first), to = std::min(w.end, own_end);
    const auto send = [&](Index begin, Index stop) {
      for (Index place = begin; place < stop; ++place) out[r].push_back(row(place - window_first_));
    };
    send(from, std::min(to, w.old_first));
    send(std::max(from, w.old_end), to);
  }
  const std::vector<Row> in = ranks.deliver(out);
  // The rows held in both windows keep their state and force, the others come in.
  const Index keep_first = std::max(first, old_first), keep_end = std::max(keep_first, std::min(end, old_end));
  if (static_cast<Index>(in.size()) != (end - first) - (keep_end - keep_first))
    throw std::logic_error("NodeStore::hold_window: a node of the new window came from no rank");
  each_state_array(*this, [&](auto& array) {
    std::remove_reference_t<decltype(array)> held(static_cast<std::size_t>(end - first));
    if (keep_first < keep_end)
      std::copy(array.begin() + (keep_first - old_first), array.begin() + (keep_end - old_first),
                held.begin() + (keep_first - first));
    array.swap(held);
  });
  window_first_ = first;
  windowed_ = true;
  for (const Row& arrived : in) {
    const Index i = static_cast<Index>(arrived.global) - first;
    set_state(*this, i, arrived);
    f[i] = Vec3::Zero();
  }
  place_owned_rows(*this);
  ++layout;
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
  ++layout;
}

std::pair<Index, Index> NodeStore::places_held() const {
  if (windowed_) return {window().begin, window().end};
  if (!numbered_) return {std::numeric_limits<Index>::min(), std::numeric_limits<Index>::max()};
  if (size() == 0) return {0, 0};
  const auto [lowest, highest] = std::minmax_element(global.begin(), global.end());
  return {*lowest, *highest + 1};
}

void NodeStore::checkpoint(Archive& a) {
  a.expect_size("nodes", static_cast<std::size_t>(deck_node_count()));
  const parallel::Communicator& ranks = parallel::world();
  if (!a.reading()) {
    // Each rank's own rows where the rows are not every node, or may be stale on rank 0 (by region),
    // else rank 0's every row (those are in the deck's order).
    const bool own_rows = by_region() || !holds_every_node();
    std::vector<std::pair<Index, Index>> rows;  // (place in the deck, row), sorted
    if (own_rows) {
      for (Index k = 0; k < owned_count(); ++k) rows.emplace_back(deck_index(owned_node(k)), owned_node(k));
      std::sort(rows.begin(), rows.end());
    }
    const Index count = own_rows ? static_cast<Index>(rows.size()) : ranks.rank() == 0 ? size() : 0;
    const auto row_at = [&](Index k) { return own_rows ? rows[k].second : k; };
    parallel::write_pieces<SavedRow>(
        a, count, [&](Index k) { return SavedRow{row(row_at(k)), f[row_at(k)]}; },
        [&](Index k) { return deck_index(row_at(k)); }, ranks);
    return;
  }
  // Into every node, or into the rows a rank holds (the set-up in blocks built them: hold_block,
  // then dealt; or a window), each filled once: the other ranks' rows are read past. A node under another ID or
  // given twice, or one of the rows missing, stops every rank alike.
  const bool own_rows = !holds_every_node();  // each rank reads into the rows it holds
  std::vector<std::uint8_t> seen(size(), 0);
  Index mismatch = -1;
  const auto [first, end] = places_held();
  parallel::read_pieces<SavedRow>(a, [&](const SavedRow& saved) {
    const Index place = static_cast<Index>(saved.row.global);
    const bool in_deck = place >= 0 && place < deck_node_count();
    const Index i = in_deck ? row_of(place) : -1;
    if (own_rows && in_deck && i < 0) return;  // another rank's row
    if (i < 0 || seen[i]++ || saved.row.id != id[i]) {
      if (mismatch < 0) mismatch = std::max<Index>(place, 0);
      return;
    }
    set_state(*this, i, saved.row);
    f[i] = saved.f;
  }, first, end, own_rows ? &ranks : nullptr);
  const auto unseen = std::find(seen.begin(), seen.end(), 0);
  Index missing = unseen == seen.end() ? -1 : deck_index(static_cast<Index>(unseen - seen.begin()));
  parallel::check_read(a, "node", mismatch, missing, own_rows ? &ranks : nullptr);
}

}  // namespace spall::discretization
