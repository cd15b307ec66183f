#include "spall/solver/field_output.hpp"

#include <variant>

namespace spall::solver {

namespace {
template <typename T>
std::vector<T> gather(const std::vector<T>& node_values, const std::vector<Index>& written, int components) {
  std::vector<T> out;
  out.reserve(written.size() * components);
  for (Index i : written)
    for (int c = 0; c < components; ++c) out.push_back(node_values[i * components + c]);
  return out;
}
}  // namespace

FieldSnapshot snapshot_fields(const Problem& problem) {
  const auto& nodes = problem.nodes;
  discretization::FieldSet set(nodes.size());
  const auto velocity = set.node_real("velocity", 3), displacement = set.node_real("displacement", 3);
  // With density, a particle's volume m / rho: what `spall surface` needs for the colour field.
  const auto mass = set.node_real("mass");
  const auto part_id = set.node_integer("part_id"), node_id = set.node_integer("node_id");
  for (Index i = 0; i < nodes.size(); ++i) {
    for (int d = 0; d < 3; ++d) {
      velocity[3 * i + d] = nodes.v[i][d];
      displacement[3 * i + d] = nodes.x[i][d] - nodes.x0[i][d];
    }
    mass[i] = nodes.mass[i];
    part_id[i] = problem.part_of_node[i];
    node_id[i] = nodes.id[i];
  }
  for (const auto& f : problem.formulations) f->write_fields(set, nodes);
  problem.rigid_bodies.write_fields(set);

  // The nodes with mass, and those of cells: an eroded element's cell is written (flagged) after
  // its nodes lost their mass.
  std::vector<char> in_cell(nodes.size(), 0);
  for (const auto& block : set.cell_blocks())
    for (Index node : block.connectivity) in_cell[node] = 1;
  std::vector<Index> written, point_of_node(nodes.size(), -1);
  for (Index i = 0; i < nodes.size(); ++i)
    if (nodes.mass[i] > 0 || in_cell[i]) {
      point_of_node[i] = static_cast<Index>(written.size());
      written.push_back(i);
    }
  FieldSnapshot snap;
  for (Index i : written) snap.points.push_back(nodes.x[i]);
  for (auto& field : set.node_fields()) {
    std::visit([&](auto& values) { values = gather(values, written, field.components); }, field.values);
    snap.fields.push_back(std::move(field));
  }
  for (const auto& block : set.cell_blocks()) {
    auto& out = snap.cell_blocks.emplace_back(block);
    for (Index& node : out.connectivity) node = point_of_node[node];
  }
  return snap;
}

}  // namespace spall::solver
