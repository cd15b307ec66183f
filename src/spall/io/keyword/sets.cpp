// *SET_NODE_LIST (+ _GENERATE), *SET_PART_LIST, *SET_SEGMENT, *SET_SOLID, each with an optional _TITLE
// line.
#include "spall/core/memory.hpp"
#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {
// Card 1 of every set: SID DA1..DA4 SOLVER. The attributes DA1..DA4 have no use in Spall.
Card read_set_header(CardCursor& cursor, const KeywordCall& call) {
  if (call.title) cursor.next_text("title");
  return cursor.next(standard_fields, "card 1 (SID DA1 DA2 DA3 DA4 SOLVER)");
}

// The member cards: 8 IDs per line; blank or 0 entries are padding.
std::vector<Id> read_members(CardCursor& cursor) {
  std::vector<Id> members;
  while (!cursor.done()) {
    const Card card = cursor.next(standard_fields, "member card");
    for (int k = 0; k < 8; ++k)
      if (const Id id = card.integer(k, id_field_names[k], 0); id != 0) members.push_back(id);
  }
  return members;
}
}  // namespace

void read_set_node_list(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  const Card header = read_set_header(cursor, call);
  model::NodeSet set;
  set.id = header.required_integer(0, "SID");
  set.where = header.where();
  set.nodes = read_members(cursor);
  insert_unique(model.node_sets, set.id, std::move(set), header, "node set");
}

void read_set_node_list_generate(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  constexpr const char* names[8] = {"B1BEG", "B1END", "B2BEG", "B2END",
                                    "B3BEG", "B3END", "B4BEG", "B4END"};
  const Card header = read_set_header(cursor, call);
  model::NodeSet set;
  set.id = header.required_integer(0, "SID");
  set.where = header.where();
  while (!cursor.done()) {
    const Card card = cursor.next(standard_fields, "range card");
    for (int pair = 0; pair < 4; ++pair) {
      const Id first = card.integer(2 * pair, names[2 * pair], 0);
      const Id last = card.integer(2 * pair + 1, names[2 * pair + 1], 0);
      if (first == 0 && last == 0) continue;
      if (first <= 0 || last < first || last > largest_id)
        card.fail(names[2 * pair], "range " + std::to_string(first) + ".." + std::to_string(last) +
                                       " is not a range of node IDs");
      set.ranges.push_back({first, last, card.line(), names[2 * pair]});
    }
  }
  insert_unique(model.node_sets, set.id, std::move(set), header, "node set");
}

void generate_node_set_ranges(model::Model& model) {
  const auto defined = static_cast<Id>(model.node_card_count());
  for (auto& [id, set] : model.node_sets) {
    for (const model::NodeRange& range : set.ranges) {
      const SourceLocation where{set.where.file, range.line};
      const Id count = range.last - range.first + 1;
      // Every member must be a node of the deck (validate), so a longer range cannot be meant.
      if (count > defined)
        throw InputError(where, "*SET_NODE_LIST_GENERATE",
                         "field " + std::string(range.field) + ": range " + std::to_string(range.first) + ".." +
                             std::to_string(range.last) + " holds " + std::to_string(count) +
                             " node IDs, more than the " + std::to_string(defined) + " nodes the deck defines");
      if (const std::string why = memory::shortfall(double(set.nodes.size() + count), sizeof(Id), "set members");
          !why.empty())
        throw InputError(where, "*SET_NODE_LIST_GENERATE", "field " + std::string(range.field) + ": " + why);
      for (Id nid = range.first; nid <= range.last; ++nid) set.nodes.push_back(nid);
    }
  }
}

void read_set_part_list(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  const Card header = read_set_header(cursor, call);
  model::PartSet set;
  set.id = header.required_integer(0, "SID");
  set.where = header.where();
  set.parts = read_members(cursor);
  insert_unique(model.part_sets, set.id, std::move(set), header, "part set");
}

// Card 1 SID SOLVER (SOLVER, the solver the set is for, has no use in Spall), then 8 element IDs a line.
void read_set_solid(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card header = cursor.next(standard_fields, "card 1 (SID SOLVER)");
  model::SolidSet set;
  set.id = header.required_integer(0, "SID");
  set.where = header.where();
  set.elements = read_members(cursor);
  insert_unique(model.solid_sets, set.id, std::move(set), header, "solid set");
}

// One segment a line: N1 N2 N3 N4 A1 A2 A3 A4. A1..A4 are attributes with no use in Spall.
void read_set_segment(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  constexpr const char* names[4] = {"N1", "N2", "N3", "N4"};
  const Card header = read_set_header(cursor, call);
  model::SegmentSet set;
  set.id = header.required_integer(0, "SID");
  set.where = header.where();
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card = cursor.next(standard_fields, "segment card (N1 N2 N3 N4 A1 A2 A3 A4)");
    std::array<Id, 4> nodes{};
    for (int k = 0; k < 3; ++k) nodes[k] = card.required_integer(k, names[k]);
    // LS-DYNA's triangle: N4 blank or 0, or N4 = N3.
    nodes[3] = card.integer(3, "N4", 0);
    if (nodes[3] == 0) nodes[3] = nodes[2];
    for (int k = 0; k < 4; ++k)
      if (nodes[k] <= 0) card.fail(names[k], quoted(card.text(k)) + " is not a node ID (> 0)");
    for (int k = 1; k < 4; ++k)
      for (int j = 0; j < k; ++j)
        if (nodes[k] == nodes[j] && !(k == 3 && j == 2))
          card.fail(names[k], quoted(card.text(k)) + " repeats " + names[j] +
                                  ": a segment has 3 or 4 different nodes (a triangle repeats N3 as N4, "
                                  "or leaves N4 blank)");
    set.segments.push_back(nodes);
  }
  if (set.segments.empty())
    header.context().fail(header.line(), "segment set " + std::to_string(set.id) + " has no segment");
  insert_unique(model.segment_sets, set.id, std::move(set), header, "segment set");
}

}  // namespace spall::io::keyword
