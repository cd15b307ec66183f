#include "spall/solver/nodes_in_blocks.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <fmt/format.h>
#include <optional>
#include <span>
#include <tuple>
#include <utility>

#include "spall/core/bounding_box.hpp"
#include "spall/core/first_failure.hpp"
#include "spall/core/id_deal.hpp"
#include "spall/core/sort_into_blocks.hpp"
#include "spall/neighbors/cell_list.hpp"
#include "spall/solver/set_up_messages.hpp"

namespace spall::solver {

namespace {

constexpr Real max_coordinate = 1e100;

// f(card, ordinal) for each card of `cards` this rank sets up from: its share, or where the model
// holds every card, the share that CardShare{rank, ranks} would give it.
template <class Card, class F>
void for_each_own_card(const model::Model& model, const std::vector<Card>& cards, const parallel::Communicator& ranks,
                       F&& f) {
  const model::CardShare share = model.cards.whole() ? model::CardShare{ranks.rank(), ranks.size()} : model.cards;
  const bool whole = model.cards.whole();
  for (std::size_t k = 0; k < cards.size(); ++k) {
    const Index ordinal = whole ? static_cast<Index>(k) : share.ordinal(static_cast<Index>(k));
    if (!whole || share.holds(ordinal)) f(cards[k], ordinal);
  }
}

// answer(q) for each question, asked of rank rank_of(q), which answers it: the answers in the
// questions' order (collective). Questions and answers of whole 8-byte words.
template <class Answer, class Question, class RankOf, class Reply>
std::vector<Answer> ask(const std::vector<Question>& questions, RankOf&& rank_of, Reply&& answer,
                        const parallel::Communicator& ranks) {
  struct Asked {
    Question question;
    std::int64_t from, slot;
  };
  struct Answered {
    std::int64_t slot;
    Answer answer;
  };
  static_assert(sizeof(Asked) == sizeof(Question) + 16 && sizeof(Answered) == sizeof(Answer) + 8,
                "records of whole words: no padding travels");
  std::vector<std::vector<Asked>> out(ranks.size());
  for (std::size_t k = 0; k < questions.size(); ++k)
    out[rank_of(questions[k])].push_back({questions[k], ranks.rank(), static_cast<std::int64_t>(k)});
  std::vector<std::vector<Answered>> back(ranks.size());
  for (const Asked& a : ranks.deliver(out)) back[a.from].push_back({a.slot, answer(a.question)});
  std::vector<Answer> answers(questions.size());
  for (const Answered& a : ranks.deliver(back)) answers[a.slot] = a.answer;
  return answers;
}

}  // namespace

void check_node_position(const model::Node& node) {
  // Squared distances (and the box's volume) of such coordinates would overflow a double.
  if (!(node.x.cwiseAbs().maxCoeff() <= max_coordinate))
    fail_at(node.where, "*NODE",
            fmt::format("node {} at ({:.6g}, {:.6g}, {:.6g}): coordinates beyond +-{:g} are not supported", node.id,
                        node.x.x(), node.x.y(), node.x.z(), max_coordinate));
}

Real node_order_cell(const BoundingBox& box, Index count) {
  if (count == 0) return 0;
  const Real volume = std::max((box.upper - box.lower).prod(), Real(0));
  return volume > 0 ? std::cbrt(16 * volume / count) : std::max((box.upper - box.lower).maxCoeff(), Real(1));
}

NodeOrderAxes::NodeOrderAxes(const BoundingBox& box) {
  const Vec3 extent = box.upper - box.lower;
  std::stable_sort(axis.begin(), axis.end(), [&](int a, int b) { return extent[a] < extent[b]; });
}

BoundingBox NodeOrderAxes::operator()(const BoundingBox& box) const {
  BoundingBox binned = box;
  binned.lower = (*this)(box.lower);
  binned.upper = (*this)(box.upper);
  return binned;
}

NodesInBlocks::NodesInBlocks(const model::Model& model, discretization::NodeStore& nodes,
                             const parallel::Communicator& ranks)
    : model_(model), ranks_(ranks), deck_nodes_(model.node_card_count()) {
  // A node card as it travels: its cell's key, its ordinal (the two its place in the order comes
  // from) and what the rows need.
  struct NodeCard {
    neighbors::CellKey key;
    Index ordinal;
    Id id;
    Vec3 x;
    int tc;
    model::Model::CardLine line;
  };
  std::vector<NodeCard> cards;
  std::optional<InputError> error;
  Index failed = -1;
  BoundingBox box;
  for_each_own_card(model, model.nodes, ranks, [&](const model::Node& node, Index ordinal) {
    if (!error) {
      try {
        check_node_position(node);
      } catch (const InputError& e) {
        error = e;
        failed = ordinal;
      }
    }
    box.include(node.x);
    cards.push_back({0, ordinal, node.id, node.x, node.tc, model.card_line(node.where)});
  });
  parallel::throw_first_failure(failed, error, ranks);

  // The box of every node (exact: a minimum), its cells, and each card's cell as the whole set-up's
  // spatial order bins it (neighbors::spatial_order).
  std::array<double, 6> extremes{box.lower.x(),  box.lower.y(),  box.lower.z(),
                                 -box.upper.x(), -box.upper.y(), -box.upper.z()};
  ranks.minimum(extremes);
  box.lower = Vec3(extremes[0], extremes[1], extremes[2]);
  box.upper = -Vec3(extremes[3], extremes[4], extremes[5]);
  if (!cards.empty()) {
    const NodeOrderAxes axes(box);
    std::vector<Vec3> x(cards.size());
    for (std::size_t k = 0; k < cards.size(); ++k) x[k] = axes(cards[k].x);
    const BoundingBox binned = axes(box);
    neighbors::CellList cells;
    cells.build(x, node_order_cell(box, deck_nodes_), {}, &binned);
    for (Index c = 0; c < cells.cell_count(); ++c)
      for (Index k = cells.cell_start(c); k < cells.cell_start(c + 1); ++k)
        cards[cells.order()[k]].key = cells.cell_key(c);
  }
  cards = parallel::sort_into_blocks(
      std::move(cards), [](const NodeCard& c) { return std::pair(c.key, c.ordinal); }, ranks);

  first_row_ = parallel::block_begin(deck_nodes_, ranks.rank(), ranks.size());
  nodes.resize(static_cast<Index>(cards.size()));
  std::vector<std::vector<Entry>> out(ranks.size());
  for (std::size_t r = 0; r < cards.size(); ++r) {
    const NodeCard& card = cards[r];
    nodes.id[r] = card.id;
    nodes.x0[r] = card.x;
    nodes.x[r] = card.x;
    nodes.fixed[r] = model::constraint_axes(card.tc);
    out[parallel::rank_of_id(card.id, ranks.size())].push_back(
        {card.id, first_row_ + static_cast<Index>(r), card.line});
  }
  nodes.hold_block(first_row_, deck_nodes_);
  std::vector<NodeCard>().swap(cards);

  // Each node card's ID and place at the rank of its ID: there a node given twice is found, the
  // first place in the node order whose ID an earlier place has (as the whole set-up's index).
  directory_ = ranks.deliver(out);
  std::sort(directory_.begin(), directory_.end(),
            [](const Entry& a, const Entry& b) { return std::tie(a.id, a.place) < std::tie(b.id, b.place); });
  Index twice = -1;
  for (std::size_t k = 1; k < directory_.size(); ++k)
    if (directory_[k].id == directory_[k - 1].id && (twice < 0 || directory_[k].place < twice)) {
      twice = directory_[k].place;
      error = InputError(model.location(directory_[k].line), "*NODE",
                         set_up_message::node_defined_twice(directory_[k].id));
    }
  parallel::throw_first_failure(twice, error, ranks);
}

std::vector<std::pair<Id, Index>> NodesInBlocks::places_of(std::vector<Id> ids) const {
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  std::vector<std::pair<Id, Index>> found;
  for (const Id id : ids) {
    if (parallel::rank_of_id(id, ranks_.size()) != ranks_.rank()) continue;
    const auto it = std::lower_bound(directory_.begin(), directory_.end(), id,
                                     [](const Entry& e, Id value) { return e.id < value; });
    if (it != directory_.end() && it->id == id) found.emplace_back(id, it->place);
  }
  found = ranks_.all(std::span<const std::pair<Id, Index>>(found));
  std::sort(found.begin(), found.end());
  return found;
}

std::vector<sph::ParticleCard> NodesInBlocks::particles() {
  // A particle card as it travels: first to the rank of its node's ID, then to the rank whose
  // block holds that node's place.
  struct ParticleCard {
    Id nid;
    Id pid;
    Real mass;
    Index ordinal;
    model::Model::CardLine line;
    Index place;
  };
  std::vector<std::vector<ParticleCard>> out(ranks_.size());
  for_each_own_card(model_, model_.sph_elements, ranks_, [&](const model::ElementSph& e, Index ordinal) {
    out[parallel::rank_of_id(e.nid, ranks_.size())].push_back(
        {e.nid, e.pid, e.mass, ordinal, model_.card_line(e.where), -1});
  });
  std::vector<ParticleCard> cards = ranks_.deliver(out);
  std::sort(cards.begin(), cards.end(), [](const ParticleCard& a, const ParticleCard& b) {
    return std::tie(a.nid, a.ordinal) < std::tie(b.nid, b.ordinal);
  });
  // The first card in the deck's order on a node no card gives, or on a node an earlier card's
  // particle sits on (as the whole set-up finds them, card after card).
  Index failed = -1;
  std::optional<InputError> error;
  const auto fail = [&](const ParticleCard& card, const std::string& why) {
    if (failed >= 0 && failed < card.ordinal) return;
    failed = card.ordinal;
    error = InputError(model_.location(card.line), "*ELEMENT_SPH", why);
  };
  for (std::size_t k = 0; k < cards.size(); ++k) {
    ParticleCard& card = cards[k];
    const auto node = std::lower_bound(directory_.begin(), directory_.end(), card.nid,
                                       [](const Entry& e, Id value) { return e.id < value; });
    if (node == directory_.end() || node->id != card.nid)
      fail(card, set_up_message::no_such_node(card.nid));
    else if (k > 0 && cards[k - 1].nid == card.nid)
      fail(card, set_up_message::node_with_two_particles(card.nid));
    else
      card.place = node->place;
  }
  parallel::throw_first_failure(failed, error, ranks_);

  const std::vector<Index> blocks = parallel::block_offsets(deck_nodes_, ranks_.size());
  for (auto& o : out) o.clear();
  for (const ParticleCard& card : cards) {
    out[parallel::rank_of_place(blocks, card.place)].push_back(card);
  }
  std::vector<ParticleCard>().swap(cards);
  cards = ranks_.deliver(out);
  std::sort(cards.begin(), cards.end(),
            [](const ParticleCard& a, const ParticleCard& b) { return a.ordinal < b.ordinal; });
  particles_.clear();
  particles_.reserve(cards.size());
  std::vector<sph::ParticleCard> particles;
  particles.reserve(cards.size());
  for (const ParticleCard& card : cards) {
    particles_.push_back({card.nid, card.pid, card.mass, model_.location(card.line)});
    particles.push_back({&particles_.back(), card.place - first_row_, card.ordinal});
  }
  return particles;
}

std::vector<spg::ElementCorners> NodesInBlocks::solid_elements(const discretization::NodeStore& nodes) const {
  // The element cards are every rank's (model::CardShare deals the node and particle cards alone):
  // each rank takes those that CardShare{rank, ranks} would deal it.
  std::vector<spg::ElementCorners> elements;
  const model::CardShare share{ranks_.rank(), ranks_.size()};
  for (std::size_t k = 0; k < model_.solid_elements.size(); ++k)
    if (share.holds(static_cast<Index>(k)))
      elements.push_back({&model_.solid_elements[k], static_cast<Index>(k), {}, {}});
  // The corners' nodes' places, each ID asked once of the rank of the ID (-1: no card gives it).
  std::vector<Id> ids;
  for (const auto& e : elements) ids.insert(ids.end(), e.card->n.begin(), e.card->n.end());
  std::sort(ids.begin(), ids.end());
  ids.erase(std::unique(ids.begin(), ids.end()), ids.end());
  const std::vector<std::int64_t> place_of_id = ask<std::int64_t>(
      ids, [&](Id id) { return parallel::rank_of_id(id, ranks_.size()); },
      [&](Id id) {
        const auto node = std::lower_bound(directory_.begin(), directory_.end(), id,
                                           [](const Entry& e, Id value) { return e.id < value; });
        return std::int64_t(node != directory_.end() && node->id == id ? node->place : -1);
      },
      ranks_);
  std::vector<std::int64_t> places;
  for (auto& e : elements)
    for (int a = 0; a < 8; ++a) {
      const auto id = std::lower_bound(ids.begin(), ids.end(), e.card->n[a]);
      e.place[a] = static_cast<Index>(place_of_id[id - ids.begin()]);
      if (e.place[a] >= 0) places.push_back(e.place[a]);
    }
  // Their positions, each place asked once of the rank whose block holds it.
  std::sort(places.begin(), places.end());
  places.erase(std::unique(places.begin(), places.end()), places.end());
  const std::vector<Index> blocks = parallel::block_offsets(deck_nodes_, ranks_.size());
  const std::vector<Vec3> x = ask<Vec3>(
      places, [&](std::int64_t place) { return parallel::rank_of_place(blocks, place); },
      [&](std::int64_t place) { return nodes.x0[place - first_row_]; }, ranks_);
  for (auto& e : elements)
    for (int a = 0; a < 8; ++a)
      if (e.place[a] >= 0)
        e.x[a] = x[std::lower_bound(places.begin(), places.end(), std::int64_t(e.place[a])) - places.begin()];
  return elements;
}

}  // namespace spall::solver
