#include "spall/discretization/field_set.hpp"

#include <fmt/format.h>
#include <stdexcept>

namespace spall::discretization {

int nodes_per_cell(CellShape shape) {
  switch (shape) {
    case CellShape::hexahedron: return 8;
    case CellShape::triangle: return 3;
    default: return 4;
  }
}

Field& FieldSet::node_field(std::string_view name, int components, bool integer,
                            const std::vector<std::string>& component_names) {
  for (auto& field : node_fields_) {
    if (field.name != name) continue;
    const bool field_integer = std::holds_alternative<std::vector<std::int64_t>>(field.values);
    if (field.components != components || field_integer != integer)
      throw std::logic_error(fmt::format("output field '{}' asked for with {} {} components, but it has {} {}", name,
                                         components, integer ? "integer" : "real", field.components,
                                         field_integer ? "integer" : "real"));
    return field;
  }
  Field field{std::string(name), components, {}, component_names};
  const std::size_t size = static_cast<std::size_t>(node_count_) * components;
  if (integer)
    field.values = std::vector<std::int64_t>(size, integer_fill);
  else
    field.values = std::vector<double>(size, real_fill);
  return node_fields_.emplace_back(std::move(field));
}

NodeValues<double> FieldSet::node_real(std::string_view name, int components,
                                       const std::vector<std::string>& component_names) {
  return {std::get<std::vector<double>>(node_field(name, components, false, component_names).values),
          static_cast<std::size_t>(first_) * components};
}

NodeValues<std::int64_t> FieldSet::node_integer(std::string_view name, int components) {
  return {std::get<std::vector<std::int64_t>>(node_field(name, components, true, {}).values),
          static_cast<std::size_t>(first_) * components};
}

CellBlock& FieldSet::add_cell_block(CellShape shape) {
  CellBlock& block = cell_blocks_.emplace_back();
  block.shape = shape;
  return block;
}

}  // namespace spall::discretization
