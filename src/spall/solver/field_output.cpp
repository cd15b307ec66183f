#include "spall/solver/field_output.hpp"

#include <variant>

namespace spall::solver {

namespace {
template <typename T>
std::vector<T> gather(const std::vector<T>& node_values, const std::vector<Index>& active, int components) {
  std::vector<T> out;
  out.reserve(active.size() * components);
  for (Index i : active)
    for (int c = 0; c < components; ++c) out.push_back(node_values[i * components + c]);
  return out;
}
}  // namespace

FieldSnapshot snapshot_fields(const Problem& problem) {
  const auto& nodes = problem.nodes;
  std::vector<Index> active;
  for (Index i = 0; i < nodes.size(); ++i)
    if (nodes.mass[i] > 0) active.push_back(i);

  FieldSnapshot snap;
  std::vector<double> velocity, displacement;
  std::vector<std::int64_t> part_id, node_id;
  for (Index i : active) {
    snap.points.push_back(nodes.x[i]);
    for (int d = 0; d < 3; ++d) {
      velocity.push_back(nodes.v[i][d]);
      displacement.push_back(nodes.x[i][d] - nodes.x0[i][d]);
    }
    part_id.push_back(problem.part_of_node[i]);
    node_id.push_back(nodes.id[i]);
  }
  snap.fields.push_back({"velocity", 3, std::move(velocity)});
  snap.fields.push_back({"displacement", 3, std::move(displacement)});
  std::vector<io::output::PointField> node_fields;
  for (const auto& f : problem.formulations) f->add_fields(node_fields, nodes);
  for (auto& field : node_fields) {
    std::visit([&](auto& values) { values = gather(values, active, field.components); }, field.values);
    snap.fields.push_back(std::move(field));
  }
  snap.fields.push_back({"part_id", 1, std::move(part_id)});
  snap.fields.push_back({"node_id", 1, std::move(node_id)});
  return snap;
}

}  // namespace spall::solver
