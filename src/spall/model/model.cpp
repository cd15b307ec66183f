#include "spall/model/model.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <span>

#include "spall/core/communicator.hpp"

namespace spall::model {

void Model::release_mesh() {
  // swap with empty vectors and maps: clear() keeps a vector's capacity
  std::vector<Node>().swap(nodes);
  std::vector<ElementSph>().swap(sph_elements);
  std::vector<ElementSolid>().swap(solid_elements);
  std::vector<ElementShell>().swap(shell_elements);
  node_sets.clear();
}

namespace {

// Every rank's held cards, in the deck's order, gathered in place: the cards of chunks
// [j ranks, (j + 1) ranks) lie one after the other in the deck's order, rank r's at the r-th, so
// each such round is one MPI_Allgatherv into the whole (the whole and a rank's share held at once,
// not the whole twice).
template <typename Card>
void gather(std::vector<Card>& held, const CardShare& cards, Index count) {
  const parallel::Communicator& ranks = parallel::world();
  const Index chunk = CardShare::chunk, round = chunk * cards.ranks;
  std::vector<Card> whole(count);
  std::vector<Index> offsets(cards.ranks + 1);
  for (Index first = 0, j = 0; first < count; first += round, ++j) {
    const Index length = std::min(round, count - first);
    for (int r = 0; r <= cards.ranks; ++r) offsets[r] = std::min(r * chunk, length);
    const Index mine = std::min(chunk, static_cast<Index>(held.size()) - j * chunk);
    if (mine > 0) std::copy_n(held.begin() + j * chunk, mine, whole.begin() + first + offsets[cards.rank]);
    ranks.share(std::span<Card>(whole.data() + first, length), offsets);
  }
  held.swap(whole);
}

}  // namespace

void Model::gather_cards() {
  if (cards.whole()) return;
  gather(nodes, cards, node_cards);
  gather(sph_elements, cards, sph_cards);
  cards = CardShare{};
}

Model::CardLine Model::card_line(const SourceLocation& where) const {
  for (std::size_t f = 0; f < files.size(); ++f)
    if (files[f] == where.file.str()) return {static_cast<std::int32_t>(f), where.line};
  return {-1, where.line};
}

SourceLocation Model::location(CardLine line) const {
  return {line.file >= 0 ? FileName(files[line.file]) : FileName(), line.line};
}

std::vector<Id> Model::named_nodes() const {
  std::vector<Id> named;
  for (const auto& [id, set] : node_sets) named.insert(named.end(), set.nodes.begin(), set.nodes.end());
  for (const auto& [id, set] : segment_sets)
    for (const auto& segment : set.segments) named.insert(named.end(), segment.begin(), segment.end());
  for (const auto& spc : spcs)
    if (spc.target == Target::node) named.push_back(spc.id);
  for (const auto& motion : prescribed_motions)
    if (motion.target == Target::node) named.push_back(motion.id);
  for (const auto& velocity : initial_velocity_nodes) named.push_back(velocity.nid);
  for (const auto& card : history_nodes)
    if (!card.sets) named.insert(named.end(), card.ids.begin(), card.ids.end());
  std::sort(named.begin(), named.end());
  named.erase(std::unique(named.begin(), named.end()), named.end());
  return named;
}

const Part* Model::find_part(Id id) const {
  for (const auto& part : parts)
    if (part.id == id) return &part;
  return nullptr;
}

const MatRigid* Model::rigid_material(const Part& part) const {
  auto it = materials.find(part.mid);
  return it == materials.end() ? nullptr : std::get_if<MatRigid>(&it->second.params);
}

std::array<Real, 4> Model::shell_thickness(const ElementShell& element) const {
  const auto& section = std::get<SectionShell>(sections.at(find_part(element.pid)->secid));
  std::array<Real, 4> t;
  for (int k = 0; k < 4; ++k) t[k] = element.thickness[k] > 0 ? element.thickness[k] : section.t[k];
  return t;
}

Mat3 Model::axes(Id cid, const SourceLocation& where, const std::string& keyword, const std::string& field) const {
  if (cid == 0) return Mat3::Identity();
  const auto it = coordinate_systems.find(cid);
  if (it == coordinate_systems.end())
    fail_at(where, keyword, fmt::format("{}: coordinate system {} is not defined", field, cid));
  const CoordinateSystem& system = it->second;
  Vec3 axis = system.axis, in_plane = system.in_plane;
  if (system.nodes[0] != 0) {
    Vec3 x[3];
    for (int k = 0; k < 3; ++k) {
      const auto node =
          std::find_if(nodes.begin(), nodes.end(), [&](const Node& n) { return n.id == system.nodes[k]; });
      if (node == nodes.end())
        fail_at(system.where, system.keyword, fmt::format("N{}: node {} is not defined", k + 1, system.nodes[k]));
      x[k] = node->x;
    }
    axis = x[1] - x[0];
    in_plane = x[2] - x[0];
  }
  const Vec3 normal = axis.cross(in_plane);
  if (!(normal.norm() > 1e-12 * axis.norm() * in_plane.norm()))
    fail_at(system.where, system.keyword,
            fmt::format("coordinate system {}: its two vectors are parallel (or zero), so they give no axes", cid));
  // The local axes in order axis_index, +1, +2 (cyclic): a, then (a x w) x a, then a x w.
  Mat3 local;
  local.col(system.axis_index) = axis.normalized();
  local.col((system.axis_index + 2) % 3) = normal.normalized();
  local.col((system.axis_index + 1) % 3) = local.col((system.axis_index + 2) % 3).cross(local.col(system.axis_index));
  return local;
}

void Model::require_global_axes(Id cid, const SourceLocation& where, const std::string& keyword,
                                const std::string& field, bool initial_only) const {
  if (cid == 0) return;
  const Mat3 local = axes(cid, where, keyword, field);
  const CoordinateSystem& system = coordinate_systems.at(cid);
  // Global within 1e-9 of the cosine (an angle of 4.5e-5 rad): the round-off of coordinates written
  // with 7 or more digits, well below any rotation a user means.
  bool global = true;
  for (int d = 0; d < 3; ++d) global = global && local(d, d) >= 1 - 1e-9;
  const std::string named = fmt::format("{}: coordinate system {} ({} at {})", field, cid, system.keyword,
                                        to_string(system.where));
  if (!global)
    fail_at(where, keyword,
            fmt::format("{} has local x axis ({:.6g}, {:.6g}, {:.6g}), not the global one: Spall applies this card "
                        "in global axes only",
                        named, local(0, 0), local(1, 0), local(2, 0)));
  if (system.follows_nodes && !initial_only)
    fail_at(where, keyword,
            fmt::format("{} turns with its nodes during the run (FLAG 1), which Spall cannot follow; give FLAG 0",
                        named));
}

}  // namespace spall::model
