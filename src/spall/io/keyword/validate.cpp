// validate(): cross-references between the cards of a model as read. Each failure names the card
// that holds the broken reference, with its file and line.
#include <algorithm>
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <tuple>
#include <utility>
#include <unordered_map>
#include <unordered_set>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/first_failure.hpp"
#include "spall/core/id_deal.hpp"
#include "spall/io/keyword/reader.hpp"

namespace spall::io::keyword {

namespace {

using model::Model;


// A card whose ID an earlier card (at `first`) has, reported at the repeat.
InputError defined_twice(const SourceLocation& repeat, const char* keyword, const char* what, Id id,
                         const SourceLocation& first) {
  return InputError(repeat, keyword,
                    std::string(what) + " " + std::to_string(id) + " is defined twice (first at " + to_string(first) +
                        ")");
}

// The first item whose ID repeats an earlier one, reported at the repeat.
template <class Items, class IdOf>
void require_unique(const Items& items, IdOf id_of, const char* keyword, const char* what) {
  std::unordered_map<Id, const SourceLocation*> seen;
  seen.reserve(items.size());
  for (const auto& item : items) {
    auto [it, inserted] = seen.try_emplace(id_of(item), &item.where);
    if (!inserted) throw defined_twice(item.where, keyword, what, id_of(item), *it->second);
  }
}

// A card's ID with its ordinal and line, sent to the rank of the ID (parallel::rank_of_id) for a
// join over the ranks when each holds a share of the cards (model::CardShare).
struct CardId {
  Id id;
  Index ordinal;
  Model::CardLine line;
};

// The cards' IDs, each to the rank of its ID, and every rank's for this one back, in order of ID and
// then of the deck.
template <class Items, class IdOf>
std::vector<CardId> join_by_id(const Model& model, const Items& items, IdOf id_of) {
  const parallel::Communicator& ranks = parallel::world();
  std::vector<std::vector<CardId>> out(ranks.size());
  for (std::size_t k = 0; k < items.size(); ++k) {
    const Id id = id_of(items[k]);
    out[parallel::rank_of_id(id, ranks.size())].push_back(
        {id, model.cards.ordinal(static_cast<Index>(k)), model.card_line(items[k].where)});
  }
  std::vector<CardId> in = ranks.deliver(out);
  std::sort(in.begin(), in.end(),
            [](const CardId& a, const CardId& b) { return std::tie(a.id, a.ordinal) < std::tie(b.id, b.ordinal); });
  return in;
}

// require_unique over every rank's share of the cards, whose IDs came to their ranks (join_by_id):
// the first card in the deck's order whose ID an earlier card has, found at its ID's rank, stops
// every rank.
void require_unique_over_ranks(const Model& model, const std::vector<CardId>& ids, const char* keyword,
                               const char* what) {
  Index repeat = -1;
  std::optional<InputError> error;
  for (std::size_t k = 1; k < ids.size(); ++k) {
    const bool second = ids[k].id == ids[k - 1].id && (k == 1 || ids[k - 2].id != ids[k].id);
    if (!second || (repeat >= 0 && repeat < ids[k].ordinal)) continue;
    repeat = ids[k].ordinal;
    error = defined_twice(model.location(ids[k].line), keyword, what, ids[k].id, model.location(ids[k - 1].line));
  }
  parallel::throw_first_failure(repeat, error, parallel::world());
}

const model::UnsupportedKeyword* find_unsupported(const Model& model, std::string_view prefix,
                                                  Id id) {
  for (const auto& keyword : model.unsupported)
    if (keyword.id == id && std::string_view(keyword.keyword).starts_with(prefix)) return &keyword;
  return nullptr;
}

class Validator {
 public:
  explicit Validator(const Model& model) : model_(model) {
    if (model.cards.whole()) {
      node_ids_.reserve(model.nodes.size());
      for (const auto& node : model.nodes) node_ids_.push_back(node.id);
      std::sort(node_ids_.begin(), node_ids_.end());
    } else {
      find_named_nodes();
      node_cards_ = join_by_id(model, model.nodes, [](const auto& n) { return n.id; });
      particle_cards_ = join_by_id(model, model.sph_elements, [](const auto& e) { return e.nid; });
    }
    for (const auto& part : model.parts) part_ids_.insert(part.id);
  }

  void run() {
    require_termination();
    if (model_.cards.whole())
      require_unique(model_.nodes, [](const auto& n) { return n.id; }, "*NODE", "node");
    else
      require_unique_over_ranks(model_, node_cards_, "*NODE", "node");
    require_unique(model_.parts, [](const auto& p) { return p.id; }, "*PART", "part");
    require_unique(model_.solid_elements, [](const auto& e) { return e.eid; }, "*ELEMENT_SOLID",
                   "element");
    require_unique(model_.shell_elements, [](const auto& e) { return e.eid; }, "*ELEMENT_SHELL",
                   "shell element");
    if (model_.cards.whole())
      require_unique(model_.sph_elements, [](const auto& e) { return e.nid; }, "*ELEMENT_SPH", "particle");
    else
      require_unique_over_ranks(model_, particle_cards_, "*ELEMENT_SPH", "particle");
    check_ids_against_unsupported();
    // Before the particles they generate, so that a missing part is reported at the box.
    for (const auto& box : model_.sph_mesh_boxes)
      require_part(box.ipid, box.where, "*DEFINE_SPH_MESH_BOX", "IPID");
    check_elements();
    check_parts();
    check_materials();
    check_sets();
    check_conditions();
    check_contacts();
    check_controls();
  }

 private:
  void require_termination() const {
    if (model_.termination) return;
    const std::string deck = model_.files.empty() ? std::string("deck") : model_.files.front();
    throw InputError(deck + ": *CONTROL_TERMINATION is missing; its ENDTIM says when the run ends");
  }

  void check_ids_against_unsupported() const {
    for (const auto& [id, section] : model_.sections) {
      const auto* other = find_unsupported(model_, "*SECTION_", id);
      if (other)
        throw InputError(other->where, other->keyword,
                         "section " + std::to_string(id) + " is defined twice (first at " +
                             to_string(std::visit([](const auto& s) { return s.where; }, section)) +
                             ")");
    }
    for (const auto& [id, material] : model_.materials) {
      const auto* other = find_unsupported(model_, "*MAT_", id);
      // A *MAT_ADD_ card has its material's ID by design (refuse_unsupported_physics stops an
      // unread one unless it is skipped).
      if (other && !std::string_view(other->keyword).starts_with("*MAT_ADD_"))
        throw InputError(other->where, other->keyword,
                         "material " + std::to_string(id) + " is defined twice (first at " +
                             to_string(material.where) + ")");
    }
    for (const auto& [id, eos] : model_.eos) {
      const auto* other = find_unsupported(model_, "*EOS_", id);
      if (other)
        throw InputError(other->where, other->keyword,
                         "equation of state " + std::to_string(id) + " is defined twice (first at " +
                             to_string(eos.where) + ")");
    }
  }

  void check_elements() {
    if (!model_.cards.whole()) check_solid_elements_over_ranks();
    for (const auto& element : model_.solid_elements) {
      if (model_.cards.whole()) {
        require_part(element.pid, element.where, "*ELEMENT_SOLID", "element " + std::to_string(element.eid));
        for (int k = 0; k < 8; ++k)
          if (!node_defined(element.n[k])) throw element_without_node(element.eid, k, element.n[k], element.where);
      }
      first_solid_.try_emplace(element.pid, &element.where);
    }
    for (const auto& element : model_.shell_elements) {
      require_part(element.pid, element.where, "*ELEMENT_SHELL", "shell element " + std::to_string(element.eid));
      for (int k = 0; k < 4; ++k)
        if (!node_defined(element.n[k]))
          throw InputError(element.where, "*ELEMENT_SHELL",
                           "shell element " + std::to_string(element.eid) + ": node N" + std::to_string(k + 1) +
                               " = " + std::to_string(element.n[k]) + " is not defined");
      first_shell_.try_emplace(element.pid, &element.where);
    }
    if (!model_.cards.whole()) return check_particles_over_ranks();
    for (const auto& particle : model_.sph_elements) {
      require_part(particle.pid, particle.where, "*ELEMENT_SPH",
                   "particle " + std::to_string(particle.nid));
      if (!node_defined(particle.nid)) throw particle_without_node(particle.nid, particle.where);
      first_sph_.try_emplace(particle.pid, particle.where);
    }
  }

  static InputError element_without_node(Id eid, int corner, Id nid, const SourceLocation& where) {
    return InputError(where, "*ELEMENT_SOLID",
                      "element " + std::to_string(eid) + ": node N" + std::to_string(corner + 1) + " = " +
                          std::to_string(nid) + " is not defined");
  }

  // check_elements' solid elements where each rank holds a share of the node cards (the element
  // cards are every rank's; each checks those CardShare would deal it): the part of each at its
  // rank, each corner's node at its ID's rank (which every node card's ID went to), the first
  // failure in the deck's order (an element's part, then its corners N1-N8) stopping every rank.
  void check_solid_elements_over_ranks() {
    const parallel::Communicator& ranks = parallel::world();
    const model::CardShare share{ranks.rank(), ranks.size()};
    std::int64_t position = -1;  // 9 ordinal, + 1 + k for corner k
    std::optional<InputError> error;
    const auto fail = [&](std::int64_t at, const InputError& e) {
      if (position < 0 || at < position) position = at, error = e;
    };
    struct Corner {  // whole words: no padding travels
      Id node, element;
      std::int64_t position;
      Model::CardLine line;
    };
    std::vector<std::vector<Corner>> out(ranks.size());
    const auto& elements = model_.solid_elements;
    for (std::size_t k = 0; k < elements.size(); ++k) {
      if (!share.holds(static_cast<Index>(k))) continue;
      const model::ElementSolid& e = elements[k];
      try {
        require_part(e.pid, e.where, "*ELEMENT_SOLID", "element " + std::to_string(e.eid));
      } catch (const InputError& bad) {
        fail(9 * std::int64_t(k), bad);
      }
      for (int c = 0; c < 8; ++c)
        out[parallel::rank_of_id(e.n[c], ranks.size())].push_back(
            {e.n[c], e.eid, 9 * std::int64_t(k) + 1 + c, model_.card_line(e.where)});
    }
    for (const Corner& c : ranks.deliver(out)) {
      const auto node = std::lower_bound(node_cards_.begin(), node_cards_.end(), c.node,
                                         [](const CardId& card, Id id) { return card.id < id; });
      if (node == node_cards_.end() || node->id != c.node)
        fail(c.position,
             element_without_node(c.element, static_cast<int>((c.position - 1) % 9), c.node, model_.location(c.line)));
    }
    parallel::throw_first_failure(position, error, ranks);
  }

  static InputError particle_without_node(Id nid, const SourceLocation& where) {
    return InputError(where, "*ELEMENT_SPH",
                      "particle " + std::to_string(nid) + ": node " + std::to_string(nid) + " is not defined");
  }

  // check_elements' particles where each rank holds a share of the cards: the part of each at its
  // rank, the node of each at its node ID's rank (which every node card's ID went to), the first
  // failure in the deck's order (a card's part before its node) stopping every rank; then each
  // part's first particle over the ranks.
  void check_particles_over_ranks() {
    const parallel::Communicator& ranks = parallel::world();
    const auto& particles = model_.sph_elements;
    std::int64_t position = -1;  // 2 ordinal, + 1 for the node
    std::optional<InputError> error;
    for (std::size_t k = 0; k < particles.size() && !error; ++k) {
      try {
        require_part(particles[k].pid, particles[k].where, "*ELEMENT_SPH",
                     "particle " + std::to_string(particles[k].nid));
      } catch (const InputError& e) {
        error = e;
        position = 2 * std::int64_t(model_.cards.ordinal(static_cast<Index>(k)));
      }
    }
    auto node = node_cards_.begin();
    for (const CardId& particle : particle_cards_) {
      while (node != node_cards_.end() && node->id < particle.id) ++node;
      if ((node != node_cards_.end() && node->id == particle.id) ||
          (position >= 0 && position < 2 * std::int64_t(particle.ordinal) + 1))
        continue;
      position = 2 * std::int64_t(particle.ordinal) + 1;
      error = particle_without_node(particle.id, model_.location(particle.line));
    }
    parallel::throw_first_failure(position, error, ranks);

    struct First {
      Index part;  // in model_.parts
      Index ordinal;
      Model::CardLine line;
    };
    std::vector<First> mine;
    for (std::size_t k = 0; k < particles.size(); ++k) {
      const auto part = std::find_if(model_.parts.begin(), model_.parts.end(),
                                     [&](const model::Part& p) { return p.id == particles[k].pid; });
      const Index p = part - model_.parts.begin();
      if (std::none_of(mine.begin(), mine.end(), [&](const First& f) { return f.part == p; }))
        mine.push_back({p, model_.cards.ordinal(static_cast<Index>(k)), model_.card_line(particles[k].where)});
    }
    std::vector<First> every = ranks.all(std::span<const First>(mine));
    std::sort(every.begin(), every.end(),
              [](const First& a, const First& b) { return std::tie(a.part, a.ordinal) < std::tie(b.part, b.ordinal); });
    for (const First& f : every) first_sph_.try_emplace(model_.parts[f.part].id, model_.location(f.line));
  }

  // Where each rank holds a share of the node cards: which of the nodes that the other cards name
  // (sets, constraints, motions, initial velocities), every one on every rank, some rank's cards
  // define; node_ids_ holds those.
  void find_named_nodes() {
    const std::vector<Id> named = model_.named_nodes();
    std::vector<std::int64_t> defined(named.size(), 0);
    for (const auto& node : model_.nodes)
      if (const auto it = std::lower_bound(named.begin(), named.end(), node.id); it != named.end() && *it == node.id)
        defined[it - named.begin()] = 1;
    parallel::world().sum(std::span(defined));
    for (std::size_t k = 0; k < named.size(); ++k)
      if (defined[k] > 0) node_ids_.push_back(named[k]);
  }

  void require_part(Id pid, const SourceLocation& where, const char* keyword,
                    const std::string& who) const {
    if (part_ids_.contains(pid)) return;
    if (const auto* unsupported = find_unsupported(model_, "*PART_", pid))
      throw InputError(where, keyword,
                       who + ": part " + std::to_string(pid) + " is a " + unsupported->keyword +
                           " (" + to_string(unsupported->where) +
                           "), which Spall does not support");
    throw InputError(where, keyword, who + ": part " + std::to_string(pid) + " is not defined");
  }

  // Sections, materials and EOS of parts that have elements must be ones Spall reads; an unused
  // part may name an unsupported one (it was reported as unsupported already) but not a missing one.
  void check_parts() const {
    for (const auto& part : model_.parts) {
      const bool used =
          first_solid_.contains(part.id) || first_sph_.contains(part.id) || first_shell_.contains(part.id);
      const auto section = model_.sections.find(part.secid);
      if (section == model_.sections.end())
        refuse_reference(part, used, "*SECTION_", "section", part.secid);
      if (!model_.materials.contains(part.mid))
        refuse_reference(part, used, "*MAT_", "material", part.mid);
      if (part.eosid != 0 && !model_.eos.contains(part.eosid))
        refuse_reference(part, used, "*EOS_", "equation of state", part.eosid);
      require_eos_where_needed(part);
      // TMID has the thermal materials' own ID space; a structural material of that number is not one.
      if (part.tmid != 0 && !model_.thermal_materials.contains(part.tmid))
        throw InputError(part.where, "*PART",
                         "part " + std::to_string(part.id) + ": TMID: thermal material " + std::to_string(part.tmid) +
                             " is not defined" +
                             (model_.materials.contains(part.tmid) ? " (material " + std::to_string(part.tmid) +
                                                                         " is a structural one; TMID names a "
                                                                         "*MAT_THERMAL_ card)"
                                                                   : std::string()));
      if (section == model_.sections.end()) continue;
      if (auto it = first_sph_.find(part.id);
          it != first_sph_.end() && !std::holds_alternative<model::SectionSph>(section->second))
        throw InputError(part.where, "*PART",
                         "part " + std::to_string(part.id) + " has *ELEMENT_SPH particles (" +
                             to_string(it->second) + ") but its section " +
                             std::to_string(part.secid) + " is not a *SECTION_SPH");
      if (part.inertia && !model_.rigid_material(part))
        throw InputError(part.inertia->where, "*PART_INERTIA",
                         "part " + std::to_string(part.id) + ": material " + std::to_string(part.mid) +
                             " is not *MAT_RIGID: Spall takes given mass properties for rigid bodies only");
      const bool shell_section = std::holds_alternative<model::SectionShell>(section->second);
      if (auto it = first_shell_.find(part.id); it != first_shell_.end()) {
        if (!shell_section)
          throw InputError(part.where, "*PART",
                           "part " + std::to_string(part.id) + " has *ELEMENT_SHELL elements (" +
                               to_string(*it->second) + ") but its section " + std::to_string(part.secid) +
                               " is not a *SECTION_SHELL");
        if (!model_.rigid_material(part))
          throw InputError(part.where, "*PART",
                           "part " + std::to_string(part.id) + " has *ELEMENT_SHELL elements (" +
                               to_string(*it->second) + ") but material " + std::to_string(part.mid) +
                               " is not *MAT_RIGID: Spall runs shells only as rigid geometry (deformable shells "
                               "are not implemented)");
      }
      if (shell_section && (first_solid_.contains(part.id) || first_sph_.contains(part.id)))
        throw InputError(part.where, "*PART",
                         "part " + std::to_string(part.id) + " has solid elements or particles but its section " +
                             std::to_string(part.secid) + " is a *SECTION_SHELL");
      if (auto it = first_solid_.find(part.id);
          it != first_solid_.end() && std::holds_alternative<model::SectionSph>(section->second))
        throw InputError(part.where, "*PART",
                         "part " + std::to_string(part.id) + " has *ELEMENT_SOLID elements (" +
                             to_string(*it->second) + ") but its section " +
                             std::to_string(part.secid) + " is not a *SECTION_SOLID or *SECTION_SOLID_SPG");
    }
  }

  // *MAT_NULL has no pressure of its own, nor has *MAT_JOHNSON_COOK without E (which LS-DYNA
  // reads for shells only); Spall gives the latter K = E / (3 (1 - 2 PR)) when E is set.
  void require_eos_where_needed(const model::Part& part) const {
    if (part.eosid != 0) return;
    const auto material = model_.materials.find(part.mid);
    if (material == model_.materials.end()) return;
    const auto& params = material->second.params;
    const auto* johnson_cook = std::get_if<model::MatJohnsonCook>(&params);
    std::string why;
    if (std::holds_alternative<model::MatNull>(params))
      why = "*MAT_NULL has no pressure of its own";
    else if (johnson_cook && johnson_cook->e == 0)
      why = "*MAT_JOHNSON_COOK with E = 0 has no bulk modulus";
    else
      return;
    throw InputError(part.where, "*PART",
                     "part " + std::to_string(part.id) + ": material " + std::to_string(part.mid) +
                         " (" + to_string(material->second.where) + ") needs an equation of "
                         "state, but EOSID is 0: " + why);
  }

  // A *MAT_PIECEWISE_LINEAR_PLASTICITY's LCSS must be a *DEFINE_CURVE (yield stress versus
  // effective plastic strain).
  void check_materials() const {
    for (const auto& [id, material] : model_.materials) {
      const auto* piecewise = std::get_if<model::MatPiecewiseLinearPlasticity>(&material.params);
      if (!piecewise || piecewise->lcss == 0 || model_.curves.contains(piecewise->lcss)) continue;
      const std::string lcss = std::to_string(piecewise->lcss);
      if (const auto* table = find_unsupported(model_, "*DEFINE_TABLE", piecewise->lcss))
        throw InputError(material.where, material.keyword,
                         "LCSS: " + lcss + " is a " + table->keyword + " (" + to_string(table->where) +
                             "); tables of curves by strain rate are not read, give a "
                             "*DEFINE_CURVE of yield stress versus plastic strain");
      throw InputError(material.where, material.keyword, undefined("LCSS: curve", piecewise->lcss));
    }
  }

  void refuse_reference(const model::Part& part, bool used, std::string_view prefix,
                        const char* what, Id id) const {
    const auto* unsupported = find_unsupported(model_, prefix, id);
    if (!unsupported)
      throw InputError(part.where, "*PART",
                       "part " + std::to_string(part.id) + ": " + what + " " + std::to_string(id) +
                           " is not defined");
    if (used)
      throw InputError(part.where, "*PART",
                       "part " + std::to_string(part.id) + " uses " + unsupported->keyword + " (" +
                           to_string(unsupported->where) + "), which Spall does not support");
  }

  void check_sets() const {
    for (const auto& [id, set] : model_.node_sets)
      for (Id nid : set.nodes)
        if (!node_defined(nid))
          throw InputError(set.where, "*SET_NODE_LIST",
                           "node set " + std::to_string(id) + ": node " + std::to_string(nid) +
                               " is not defined");
    for (const auto& [id, set] : model_.part_sets)
      for (Id pid : set.parts)
        // A member defined by an unsupported *PART_ keyword was reported as unsupported already.
        if (!part_ids_.contains(pid) && !find_unsupported(model_, "*PART_", pid))
          throw InputError(set.where, "*SET_PART_LIST",
                           "part set " + std::to_string(id) + ": part " + std::to_string(pid) +
                               " is not defined");
    if (!model_.solid_sets.empty()) {
      std::unordered_set<Id> solids;
      for (const auto& element : model_.solid_elements) solids.insert(element.eid);
      for (const auto& [id, set] : model_.solid_sets)
        for (Id eid : set.elements)
          if (!solids.contains(eid))
            throw InputError(set.where, "*SET_SOLID",
                             "solid set " + std::to_string(id) + ": element " + std::to_string(eid) +
                                 " is not defined");
    }
    for (const auto& [id, set] : model_.segment_sets)
      for (const auto& segment : set.segments)
        for (Id nid : segment)
          if (!node_defined(nid))
            throw InputError(set.where, "*SET_SEGMENT",
                             "segment set " + std::to_string(id) + ": node " + std::to_string(nid) +
                                 " is not defined");
  }

  // "<what> <id> is not defined", or, when a keyword Spall does not read defines it (a *SET_NODE_ADD,
  // a *DEFINE_CURVE_FUNCTION), that keyword and where it is. `what` ends with the kind of thing
  // ("node set", "LCID: curve"), which says which keywords could define it: sets of one kind share
  // an ID space, curves share theirs with tables and functions.
  std::string undefined(std::string_view what, Id id) const {
    static constexpr std::pair<std::string_view, std::array<std::string_view, 3>> definers[] = {
        {"node set", {"*SET_NODE"}},
        {"part set", {"*SET_PART"}},
        {"segment set", {"*SET_SEGMENT"}},
        {"curve", {"*DEFINE_CURVE", "*DEFINE_FUNCTION", "*DEFINE_TABLE"}},
    };
    const std::string name = std::string(what) + " " + std::to_string(id);
    for (const auto& [kind, prefixes] : definers) {
      if (!what.ends_with(kind)) continue;
      for (std::string_view prefix : prefixes)
        if (const auto* other = !prefix.empty() ? find_unsupported(model_, prefix, id) : nullptr)
          return name + " is defined by " + other->keyword + " (" + to_string(other->where) +
                 "), which Spall does not read";
    }
    return name + " is not defined";
  }
  void require(bool exists, const SourceLocation& where, const char* keyword, const char* what,
               Id id) const {
    if (!exists) throw InputError(where, keyword, undefined(what, id));
  }
  void require_curve(Id lcid, const SourceLocation& where, const char* keyword,
                     const char* field) const {
    if (!model_.curves.contains(lcid))
      throw InputError(where, keyword, undefined(std::string(field) + ": curve", lcid));
  }
  bool target_exists(model::Target target, Id id) const {
    switch (target) {
      case model::Target::node: return node_defined(id);
      case model::Target::node_set: return model_.node_sets.contains(id);
      case model::Target::part: return part_ids_.contains(id);
      case model::Target::part_set: return model_.part_sets.contains(id);
      case model::Target::all_nodes: return true;
    }
    return false;
  }
  static const char* target_name(model::Target target) {
    switch (target) {
      case model::Target::node: return "node";
      case model::Target::node_set: return "node set";
      case model::Target::part: return "part";
      case model::Target::part_set: return "part set";
      case model::Target::all_nodes: return "all nodes";
    }
    return "";
  }

  void check_conditions() const {
    for (const auto& spc : model_.spcs)
      require(target_exists(spc.target, spc.id), spc.where,
              spc.target == model::Target::node ? "*BOUNDARY_SPC_NODE" : "*BOUNDARY_SPC_SET",
              target_name(spc.target), spc.id);
    for (const auto& motion : model_.prescribed_motions) {
      const char* keyword = motion.target == model::Target::node ? "*BOUNDARY_PRESCRIBED_MOTION_NODE"
                            : motion.target == model::Target::node_set
                                ? "*BOUNDARY_PRESCRIBED_MOTION_SET"
                                : "*BOUNDARY_PRESCRIBED_MOTION_RIGID";
      require(target_exists(motion.target, motion.id), motion.where, keyword,
              target_name(motion.target), motion.id);
      require_curve(motion.lcid, motion.where, keyword, "LCID");
    }
    for (const auto& velocity : model_.initial_velocities) {
      if (velocity.nsid != 0)
        require(model_.node_sets.contains(velocity.nsid), velocity.where, "*INITIAL_VELOCITY",
                "node set", velocity.nsid);
      if (velocity.nsidex != 0)
        require(model_.node_sets.contains(velocity.nsidex), velocity.where, "*INITIAL_VELOCITY",
                "node set", velocity.nsidex);
    }
    for (const auto& velocity : model_.initial_velocity_nodes)
      require(node_defined(velocity.nid), velocity.where, "*INITIAL_VELOCITY_NODE", "node",
              velocity.nid);
    for (const auto& generation : model_.initial_velocity_generations) {
      const model::Target target = generation.styp == 1   ? model::Target::part_set
                                   : generation.styp == 2 ? model::Target::part
                                                          : model::Target::node_set;
      require(target_exists(target, generation.id), generation.where,
              "*INITIAL_VELOCITY_GENERATION", target_name(target), generation.id);
    }
    for (const auto& wall : model_.rigid_walls) {
      if (wall.nsid != 0)
        require(model_.node_sets.contains(wall.nsid), wall.where, wall.keyword.c_str(),
                "NSID: node set", wall.nsid);
      if (wall.nsidex != 0)
        require(model_.node_sets.contains(wall.nsidex), wall.where, wall.keyword.c_str(),
                "NSIDEX: node set", wall.nsidex);
    }
    for (const auto& load : model_.body_loads) {
      const char* keyword = load.direction == 0   ? "*LOAD_BODY_X"
                            : load.direction == 1 ? "*LOAD_BODY_Y"
                                                  : "*LOAD_BODY_Z";
      require_curve(load.lcid, load.where, keyword, "LCID");
      if (load.lciddr != 0) require_curve(load.lciddr, load.where, keyword, "LCIDDR");
    }
  }

  // SURFA and SURFB name sets or parts that exist; the field is named, at the contact's card 1.
  void check_contacts() const {
    for (const auto& contact : model_.contacts) {
      check_contact_surface(contact, contact.a, "SURFA");
      if (contact.kind != model::Contact::Kind::automatic_single_surface)
        check_contact_surface(contact, contact.b, "SURFB");
    }
    // *CONTROL_CONTACT IGNORE is the default of every contact's IGNORE (in LS-DYNA's MPP version,
    // "set to 1 in any of three places, initial penetrations are tracked"): harmless without a contact.
    const auto& control = model_.control_contact;
    if (control && control->ignore != 0 && !model_.contacts.empty()) {
      const auto& contact = model_.contacts.front();
      throw InputError(control->where, "*CONTROL_CONTACT",
                       "IGNORE (card 4) = " + std::to_string(control->ignore) + " would make " + contact.keyword +
                           " (" + to_string(contact.where) +
                           ") track initial penetrations, which is not implemented; leave it 0");
    }
  }
  void check_contact_surface(const model::Contact& contact, const model::ContactSurface& surface,
                             const char* field) const {
    using Type = model::ContactSurface::Type;
    const char* keyword = contact.keyword.c_str();
    switch (surface.type) {
      case Type::segment_set:
        return require(model_.segment_sets.contains(surface.id), contact.where, keyword,
                       (std::string(field) + ": segment set").c_str(), surface.id);
      case Type::part_set:
      case Type::exempted_part_set:
        return require(model_.part_sets.contains(surface.id), contact.where, keyword,
                       (std::string(field) + ": part set").c_str(), surface.id);
      case Type::part: return require_part(surface.id, contact.where, keyword, field);
      case Type::node_set:
        return require(model_.node_sets.contains(surface.id), contact.where, keyword,
                       (std::string(field) + ": node set").c_str(), surface.id);
      case Type::all: return;
    }
  }

  void check_controls() const {
    const auto& timestep = model_.timestep;
    if (timestep.lctm != 0) require_curve(timestep.lctm, timestep.where, "*CONTROL_TIMESTEP", "LCTM");
    if (timestep.tssfac < 0)
      require_curve(static_cast<Id>(-timestep.tssfac), timestep.where, "*CONTROL_TIMESTEP",
                    "TSSFAC");
    if (model_.d3plot && model_.d3plot->lcdt != 0)
      require_curve(model_.d3plot->lcdt, model_.d3plot->where, "*DATABASE_BINARY_D3PLOT", "LCDT");
    // Each history file's LCUR.
    const std::pair<const std::optional<model::OutputInterval>&, const char*> histories[] = {
        {model_.glstat, "*DATABASE_GLSTAT"}, {model_.rwforc, "*DATABASE_RWFORC"},
        {model_.rcforc, "*DATABASE_RCFORC"}, {model_.rbdout, "*DATABASE_RBDOUT"},
        {model_.nodout, "*DATABASE_NODOUT"}, {model_.elout, "*DATABASE_ELOUT"},
        {model_.bndout, "*DATABASE_BNDOUT"}, {model_.spcforc, "*DATABASE_SPCFORC"},
        {model_.matsum, "*DATABASE_MATSUM"}};
    for (const auto& [history, keyword] : histories)
      if (history && history->lcdt != 0) require_curve(history->lcdt, history->where, keyword, "LCUR");
  }

  const Model& model_;
  // The deck's node IDs, ascending (8 B a node), or where each rank holds a share of the cards
  // those of the named nodes (find_named_nodes).
  std::vector<Id> node_ids_;
  bool node_defined(Id id) const { return std::binary_search(node_ids_.begin(), node_ids_.end(), id); }
  // Where each rank holds a share of the cards: the node and particle cards whose IDs this rank
  // keeps in the joins by ID (join_by_id).
  std::vector<CardId> node_cards_, particle_cards_;
  std::unordered_set<Id> part_ids_;
  std::unordered_map<Id, const SourceLocation*> first_solid_;  // part -> its first solid element
  std::unordered_map<Id, SourceLocation> first_sph_;           // part -> its first particle
  std::unordered_map<Id, const SourceLocation*> first_shell_;  // part -> its first shell element
};

}  // namespace

void validate(const model::Model& model) { Validator(model).run(); }

}  // namespace spall::io::keyword
