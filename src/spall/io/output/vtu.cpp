#include "spall/io/output/vtu.hpp"

#include <algorithm>
#include <array>
#include <ostream>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include <fmt/format.h>

#include "spall/io/output/atomic_file.hpp"
#include "spall/io/output/vtk_xml.hpp"

namespace spall::io::output {
namespace {

using vtk_xml::AppendedArray;
using vtk_xml::write_raw;

static_assert(sizeof(Vec3) == 3 * sizeof(double), "points are written as one contiguous block");

constexpr std::uint8_t vtk_vertex = 1;  // VTKCellType VTK_VERTEX

// The cell arrays follow from the point count alone; writing them in chunks avoids three
// temporary arrays as long as the particle arrays.
template <class T, class ValueAt>
void write_sequence(std::ostream& out, std::size_t count, ValueAt value_at) {
  std::array<T, 4096> chunk;
  for (std::size_t begin = 0; begin < count; begin += chunk.size()) {
    const std::size_t n = std::min(chunk.size(), count - begin);
    for (std::size_t i = 0; i < n; ++i) chunk[i] = value_at(begin + i);
    write_raw(out, std::span<const T>(chunk.data(), n));
  }
}

// The cell fields of the blocks as arrays over all cells (the vertex cells first, then each
// block's cells in order), filled where a cell does not have the field.
std::vector<discretization::Field> merged_cell_fields(std::size_t vertex_cells,
                                                      const std::vector<discretization::CellBlock>& blocks) {
  std::size_t total = vertex_cells;
  for (const auto& block : blocks) total += block.cell_count();
  std::vector<discretization::Field> merged;
  std::size_t first = vertex_cells;
  for (const auto& block : blocks) {
    vtk_xml::check_point_fields(block.fields, block.cell_count());
    for (const auto& field : block.fields) {
      auto it = std::find_if(merged.begin(), merged.end(), [&](const auto& m) { return m.name == field.name; });
      if (it == merged.end()) {
        discretization::Field m{field.name, field.components, {}, field.component_names};
        std::visit(
            [&](const auto& values) {
              using Value = typename std::decay_t<decltype(values)>::value_type;
              const Value fill = std::is_same_v<Value, double> ? Value(discretization::real_fill)
                                                               : Value(discretization::integer_fill);
              m.values = std::vector<Value>(total * field.components, fill);
            },
            field.values);
        merged.push_back(std::move(m));
        it = merged.end() - 1;
      }
      if (it->components != field.components || it->values.index() != field.values.index())
        throw std::invalid_argument(fmt::format("VTK cell field '{}': blocks disagree on its components", field.name));
      std::visit(
          [&](auto& target) {
            const auto& source = std::get<std::decay_t<decltype(target)>>(field.values);
            std::copy(source.begin(), source.end(), target.begin() + first * field.components);
          },
          it->values);
    }
    first += block.cell_count();
  }
  return merged;
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const std::vector<Vec3>& points,
               const std::vector<discretization::Field>& fields,
               const std::vector<discretization::CellBlock>& cell_blocks) {
  const std::size_t n = points.size();
  vtk_xml::check_point_fields(fields, n);
  // Every point is a vertex cell (cell i is point i), then the blocks' cells.
  std::size_t cell_count = n, connectivity_size = n;
  for (const auto& block : cell_blocks) {
    if (block.connectivity.size() % discretization::nodes_per_cell(block.shape) != 0)
      throw std::invalid_argument("VTK cell block: connectivity is not a whole number of cells");
    for (Index node : block.connectivity)
      if (node < 0 || static_cast<std::size_t>(node) >= n)
        throw std::invalid_argument(fmt::format("VTK cell block: node {} is not one of the {} points", node, n));
    cell_count += block.cell_count();
    connectivity_size += block.connectivity.size();
  }
  const std::vector<discretization::Field> cell_fields = merged_cell_fields(n, cell_blocks);

  const std::span<const double> coordinates(n == 0 ? nullptr : points.front().data(), 3 * n);
  // The vertex cells' arrays follow from the point count alone and are written in chunks; the
  // blocks' arrays from their connectivity.
  const auto* blocks = &cell_blocks;
  std::array<AppendedArray, 3> cells{{
      {.name = "connectivity",
       .type = "Int64",
       .bytes = connectivity_size * sizeof(std::int64_t),
       .write_values =
           [n, blocks](std::ostream& out) {
             write_sequence<std::int64_t>(out, n, [](std::size_t i) { return std::int64_t(i); });
             for (const auto& block : *blocks)
               write_sequence<std::int64_t>(out, block.connectivity.size(),
                                            [&](std::size_t i) { return std::int64_t(block.connectivity[i]); });
           }},
      {.name = "offsets",
       .type = "Int64",
       .bytes = cell_count * sizeof(std::int64_t),
       .write_values =
           [n, blocks](std::ostream& out) {
             write_sequence<std::int64_t>(out, n, [](std::size_t i) { return std::int64_t(i + 1); });
             std::int64_t end = static_cast<std::int64_t>(n);
             for (const auto& block : *blocks) {
               const int per_cell = discretization::nodes_per_cell(block.shape);
               write_sequence<std::int64_t>(out, block.cell_count(),
                                            [&](std::size_t i) { return end + per_cell * std::int64_t(i + 1); });
               end += static_cast<std::int64_t>(block.connectivity.size());
             }
           }},
      {.name = "types",
       .type = "UInt8",
       .bytes = cell_count * sizeof(std::uint8_t),
       .write_values =
           [n, blocks](std::ostream& out) {
             write_sequence<std::uint8_t>(out, n, [](std::size_t) { return vtk_vertex; });
             for (const auto& block : *blocks) {
               const auto type = static_cast<std::uint8_t>(block.shape);
               write_sequence<std::uint8_t>(out, block.cell_count(), [type](std::size_t) { return type; });
             }
           }},
  }};

  // The XML lists the arrays in VTK's order (PointData, CellData, Points, Cells); the appended
  // section holds them in the same order.
  vtk_xml::AppendedSection appended;
  std::string header = vtk_xml::file_opening("UnstructuredGrid") + "  <UnstructuredGrid>\n";
  header += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, cell_count);
  header += "      <PointData>\n";
  for (const auto& field : fields)
    header += appended.describe(vtk_xml::point_field_array(field), "        ");
  header += "      </PointData>\n";
  if (!cell_fields.empty()) {
    header += "      <CellData>\n";
    for (const auto& field : cell_fields)
      header += appended.describe(vtk_xml::point_field_array(field), "        ");
    header += "      </CellData>\n";
  }
  header += "      <Points>\n";
  header += appended.describe(
      {.type = "Float64",
       .components = 3,
       .bytes = coordinates.size_bytes(),
       .write_values = [coordinates](std::ostream& out) { write_raw(out, coordinates); }},
      "        ");
  header += "      </Points>\n      <Cells>\n";
  for (auto& array : cells) header += appended.describe(std::move(array), "        ");
  header +=
      "      </Cells>\n"
      "    </Piece>\n"
      "  </UnstructuredGrid>\n";
  appended.write_file(path, header);
}

void write_pvtu(const std::filesystem::path& path, const std::vector<std::string>& pieces,
                const std::vector<discretization::Field>& fields,
                const std::vector<discretization::CellBlock>& cell_blocks) {
  using vtk_xml::AppendedSection;
  std::string xml = vtk_xml::file_opening("PUnstructuredGrid") + "  <PUnstructuredGrid GhostLevel=\"0\">\n";
  xml += "    <PPointData>\n";
  for (const auto& field : fields)
    xml += AppendedSection::describe_in_pieces(vtk_xml::point_field_array(field), "      ");
  xml += "    </PPointData>\n";
  const std::vector<discretization::Field> cell_fields = merged_cell_fields(0, cell_blocks);
  if (!cell_fields.empty()) {
    xml += "    <PCellData>\n";
    for (const auto& field : cell_fields)
      xml += AppendedSection::describe_in_pieces(vtk_xml::point_field_array(field), "      ");
    xml += "    </PCellData>\n";
  }
  xml += "    <PPoints>\n";
  xml += AppendedSection::describe_in_pieces({.type = "Float64", .components = 3}, "      ");
  xml += "    </PPoints>\n";
  for (const auto& piece : pieces) xml += fmt::format("    <Piece Source=\"{}\"/>\n", vtk_xml::escaped(piece));
  xml += "  </PUnstructuredGrid>\n</VTKFile>\n";
  replace_file_atomically(path, [&](std::ostream& out) { out << xml; });
}

void PvdSeries::add(double time, const std::string& relative_file) {
  entries_.emplace_back(time, relative_file);
  try {
    write();
  } catch (...) {
    entries_.pop_back();  // the series on disk does not list it either
    throw;
  }
}

void PvdSeries::restore(Entries entries) {
  entries_ = std::move(entries);
  write();
}

void PvdSeries::write() const {
  std::string pvd =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"Collection\" version=\"1.0\" byte_order=\"LittleEndian\">\n"
      "  <Collection>\n";
  for (const auto& [entry_time, file] : entries_) {
    // Full precision, so that two output times never print alike; fmt ignores the C locale.
    pvd += fmt::format("    <DataSet timestep=\"{:.17g}\" part=\"0\" file=\"{}\"/>\n", entry_time,
                       vtk_xml::escaped(file));
  }
  pvd += "  </Collection>\n</VTKFile>\n";
  replace_file_atomically(path_, [&](std::ostream& out) { out << pvd; });
}

}  // namespace spall::io::output
