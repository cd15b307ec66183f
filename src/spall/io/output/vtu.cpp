#include "spall/io/output/vtu.hpp"

#include <algorithm>
#include <array>
#include <ostream>
#include <span>

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

}  // namespace

void write_vtu(const std::filesystem::path& path, const std::vector<Vec3>& points,
               const std::vector<PointField>& fields) {
  const std::size_t n = points.size();
  vtk_xml::check_point_fields(fields, n);

  const std::span<const double> coordinates(n == 0 ? nullptr : points.front().data(), 3 * n);
  // One vertex cell per point: cell i is point i.
  std::array<AppendedArray, 3> cells{{
      {.name = "connectivity",
       .type = "Int64",
       .bytes = n * sizeof(std::int64_t),
       .write_values =
           [n](std::ostream& out) {
             write_sequence<std::int64_t>(out, n, [](std::size_t i) { return std::int64_t(i); });
           }},
      {.name = "offsets",
       .type = "Int64",
       .bytes = n * sizeof(std::int64_t),
       .write_values =
           [n](std::ostream& out) {
             write_sequence<std::int64_t>(out, n, [](std::size_t i) { return std::int64_t(i + 1); });
           }},
      {.name = "types",
       .type = "UInt8",
       .bytes = n * sizeof(std::uint8_t),
       .write_values =
           [n](std::ostream& out) {
             write_sequence<std::uint8_t>(out, n, [](std::size_t) { return vtk_vertex; });
           }},
  }};

  // The XML lists the arrays in VTK's order (PointData, Points, Cells); the appended section
  // holds them in the same order.
  vtk_xml::AppendedSection appended;
  std::string header = vtk_xml::file_opening("UnstructuredGrid") + "  <UnstructuredGrid>\n";
  header += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n);
  header += "      <PointData>\n";
  for (const auto& field : fields)
    header += appended.describe(vtk_xml::point_field_array(field), "        ");
  header += "      </PointData>\n      <Points>\n";
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

void PvdSeries::add(double time, const std::string& relative_file) {
  entries_.emplace_back(time, relative_file);
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
  try {
    replace_file_atomically(path_, [&](std::ostream& out) { out << pvd; });
  } catch (...) {
    entries_.pop_back();  // the series on disk does not list it either
    throw;
  }
}

}  // namespace spall::io::output
