#include "spall/solver/field_output.hpp"

#include <bit>
#include <span>
#include <type_traits>
#include <variant>

#include "spall/core/communicator.hpp"

namespace spall::solver {

namespace {
// The values of the entities `written` of a field of the entities [first, first + values / components),
// zero for those outside it.
template <typename T>
std::vector<T> gather(const std::vector<T>& values, Index first, std::span<const Index> written, int components) {
  const auto held = values.size() / components;
  std::vector<T> out;
  out.reserve(written.size() * components);
  for (Index i : written) {
    const auto k = static_cast<std::size_t>(i - first);
    for (int c = 0; c < components; ++c) out.push_back(k < held ? values[k * components + c] : T{});
  }
  return out;
}

// The cells `cells` of `block`, their nodes numbered as points (point_of_node), with their fields.
discretization::CellBlock piece_of(const discretization::CellBlock& block, const std::vector<Index>& cells,
                                   const std::vector<Index>& point_of_node) {
  discretization::CellBlock piece{.shape = block.shape, .connectivity = {}, .fields = {}};
  const int per_cell = discretization::nodes_per_cell(block.shape);
  piece.connectivity.reserve(cells.size() * per_cell);
  for (Index c : cells)
    for (int k = 0; k < per_cell; ++k)
      piece.connectivity.push_back(point_of_node[block.connectivity[c * per_cell + k]]);
  for (const auto& field : block.fields) {
    auto& out = piece.fields.emplace_back(discretization::Field{
        .name = field.name, .components = field.components, .values = {}, .component_names = field.component_names});
    std::visit([&](const auto& values) { out.values = gather(values, 0, cells, field.components); }, field.values);
  }
  return piece;
}

// Under MPI in blocks, the fields of the nodes of this piece's cells that another rank computes, as
// that rank wrote them: a formulation writes the fields of its own nodes alone from current state
// (Formulation::complete_for_output), and a rank's set holds its own nodes alone. Each rank asks
// the nodes' ranks by their places in the deck and gets back a record of every component of every
// field (integers by their bits).
struct BorrowedFields {
  std::vector<Index> places;  // in `written`
  std::vector<double> records;
  Index record = 0;
  // The records put in place of the values at `places` of the fields gathered for `written`.
  void put(std::vector<discretization::Field>& fields) const {
    for (std::size_t k = 0; k < places.size(); ++k) {
      Index at = 0;
      for (auto& field : fields)
        std::visit([&](auto& values) {
          using T = typename std::remove_reference_t<decltype(values)>::value_type;
          for (int c = 0; c < field.components; ++c)
            values[places[k] * field.components + c] = std::bit_cast<T>(records[k * record + at++]);
        }, field.values);
    }
  }
};

BorrowedFields borrowed_fields(const discretization::FieldSet& set, const discretization::NodeStore& nodes,
                               std::span<const Index> written) {
  const parallel::Communicator& ranks = parallel::world();
  const int size = ranks.size();
  std::vector<std::vector<Index>> borrowed(size);  // places in `written`, by the rank that computes them
  for (std::size_t k = 0; k < written.size(); ++k)
    if (!nodes.owns(written[k])) borrowed[nodes.rank_of(written[k])].push_back(static_cast<Index>(k));
  BorrowedFields found;
  std::vector<Index> ask, ask_offsets(size + 1, 0);
  for (int r = 0; r < size; ++r) {
    for (const Index k : borrowed[r]) {
      ask.push_back(nodes.deck_index(written[k]));
      found.places.push_back(k);
    }
    ask_offsets[r + 1] = static_cast<Index>(ask.size());
  }
  const std::vector<Index> asked_offsets = ranks.offsets_in(ask_offsets);
  std::vector<Index> asked(asked_offsets[size]);
  ranks.exchange(std::span<const Index>(ask), ask_offsets, std::span(asked), asked_offsets);
  Index record = 0;
  for (const auto& field : set.node_fields()) record += field.components;
  found.record = record;
  found.records.resize(ask.size() * record);
  std::vector<double> answer(asked.size() * record);
  for (std::size_t k = 0; k < asked.size(); ++k) {
    const Index row = nodes.row_of(asked[k]) - set.first_node();
    Index at = 0;
    for (const auto& field : set.node_fields())
      std::visit([&](const auto& values) {
        for (int c = 0; c < field.components; ++c)
          answer[k * record + at++] = std::bit_cast<double>(values[row * field.components + c]);
      }, field.values);
  }
  if (record > 0)  // every rank writes the same fields
    ranks.exchange_records(std::as_bytes(std::span(answer)), record * sizeof(double), asked_offsets,
                           std::as_writable_bytes(std::span(found.records)), ask_offsets);
  return found;
}
}  // namespace

FieldSnapshot snapshot_fields(const Problem& problem) {
  const auto& nodes = problem.nodes;
  // Under MPI in blocks a rank's node fields hold the nodes it computes (one stretch of the node
  // order): the other nodes of its cells come from their ranks.
  const bool in_blocks = parallel::world().size() > 1 && !nodes.by_region();
  discretization::FieldSet set = in_blocks ? discretization::FieldSet(nodes.owned_begin, nodes.owned_end)
                                           : discretization::FieldSet(nodes.size());
  const auto velocity = set.node_real("velocity", 3), displacement = set.node_real("displacement", 3);
  // With density, a particle's volume m / rho: what `spall surface` needs for the colour field.
  const auto mass = set.node_real("mass");
  const auto part_id = set.node_integer("part_id"), node_id = set.node_integer("node_id");
  for (Index i = set.first_node(); i < set.first_node() + set.node_count(); ++i) {
    for (int d = 0; d < 3; ++d) {
      velocity[3 * i + d] = nodes.v[i][d];
      displacement[3 * i + d] = nodes.x[i][d] - nodes.x0[i][d];
    }
    mass[i] = nodes.mass[i];
    part_id[i] = nodes.part[i];
    node_id[i] = nodes.id[i];
  }
  for (const auto& f : problem.formulations) f->write_fields(set, nodes);
  problem.rigid_bodies.write_fields(set);

  // The piece's cells, and its nodes: those with mass and those of its cells (an eroded element's
  // cell is written, flagged, after its nodes lost their mass).
  std::vector<std::vector<Index>> piece_cells;  // of each block
  std::vector<char> in_cell(nodes.size(), 0);
  for (const auto& block : set.cell_blocks()) {
    auto& cells = piece_cells.emplace_back();
    const int per_cell = discretization::nodes_per_cell(block.shape);
    for (Index c = 0; c < static_cast<Index>(block.cell_count()); ++c) {
      if (!nodes.owns(block.connectivity[c * per_cell])) continue;
      cells.push_back(c);
      for (int k = 0; k < per_cell; ++k) in_cell[block.connectivity[c * per_cell + k]] = 1;
    }
  }
  std::vector<Index> written, point_of_node(nodes.size(), -1);
  for (Index i = 0; i < nodes.size(); ++i)
    if ((nodes.mass[i] > 0 && nodes.owns(i)) || in_cell[i]) {
      point_of_node[i] = static_cast<Index>(written.size());
      written.push_back(i);
    }
  FieldSnapshot snap;
  snap.points.reserve(written.size());
  for (Index i : written) snap.points.push_back(nodes.x[i]);
  // Written in increasing order, every node of a set of every node is the identity: no copy of
  // every field then.
  const bool every_node = written.size() == static_cast<std::size_t>(nodes.size()) && set.node_count() == nodes.size();
  const BorrowedFields borrowed = in_blocks ? borrowed_fields(set, nodes, written) : BorrowedFields{};
  for (auto& field : set.node_fields()) {
    if (!every_node)  // in place: the set's values of one field at a time let go
      std::visit([&](auto& values) { values = gather(values, set.first_node(), written, field.components); },
                 field.values);
    snap.fields.push_back(std::move(field));
  }
  borrowed.put(snap.fields);
  for (std::size_t b = 0; b < set.cell_blocks().size(); ++b)
    snap.cell_blocks.push_back(piece_of(set.cell_blocks()[b], piece_cells[b], point_of_node));
  return snap;
}

}  // namespace spall::solver
