#include "spall/io/output/vtu.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <functional>
#include <ostream>
#include <set>
#include <span>
#include <stdexcept>
#include <string_view>
#include <type_traits>

#include <fmt/format.h>

#include "spall/io/output/atomic_file.hpp"

namespace spall::io::output {
namespace {

// The file declares byte_order="LittleEndian" and the arrays are written straight from memory.
static_assert(std::endian::native == std::endian::little, "VTU writer assumes a little-endian host");
static_assert(sizeof(Vec3) == 3 * sizeof(double), "points are written as one contiguous block");

constexpr std::uint8_t vtk_vertex = 1;  // VTKCellType VTK_VERTEX

std::string xml_escaped(std::string_view text) {
  std::string escaped;
  for (const char c : text) {
    switch (c) {
      case '&': escaped += "&amp;"; break;
      case '<': escaped += "&lt;"; break;
      case '>': escaped += "&gt;"; break;
      case '"': escaped += "&quot;"; break;
      default: escaped += c;
    }
  }
  return escaped;
}

template <class T>
void write_raw(std::ostream& out, std::span<const T> values) {
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size_bytes()));
}

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

// One array of the appended section: its XML description and how to write its bytes.
struct AppendedArray {
  std::string name = {};  // empty for the Points array, which VTK does not name
  std::string_view type = {};
  int components = 1;
  const std::vector<std::string>* component_names = nullptr;
  std::uint64_t bytes = 0;
  std::function<void(std::ostream&)> write_values = {};
};

std::string data_array_xml(const AppendedArray& array, std::uint64_t offset) {
  std::string xml = fmt::format(R"(<DataArray type="{}")", array.type);
  if (!array.name.empty()) xml += fmt::format(R"( Name="{}")", xml_escaped(array.name));
  xml += fmt::format(R"( NumberOfComponents="{}")", array.components);
  if (array.component_names) {
    for (std::size_t i = 0; i < array.component_names->size(); ++i) {
      xml += fmt::format(R"( ComponentName{}="{}")", i, xml_escaped((*array.component_names)[i]));
    }
  }
  xml += fmt::format(R"( format="appended" offset="{}"/>)", offset);
  return xml;
}

void check_field(const PointField& field, std::size_t point_count) {
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument(fmt::format("VTU point field '{}': {}", field.name, why));
  };
  if (field.name.empty()) fail("a field needs a name");
  if (field.components < 1) fail("needs at least one component");
  const std::size_t size = std::visit([](const auto& values) { return values.size(); }, field.values);
  const std::size_t expected = point_count * static_cast<std::size_t>(field.components);
  if (size != expected) {
    fail(fmt::format("{} values for {} points of {} components (expected {})", size, point_count,
                     field.components, expected));
  }
  if (!field.component_names.empty() &&
      field.component_names.size() != static_cast<std::size_t>(field.components)) {
    fail(fmt::format("{} component names for {} components", field.component_names.size(),
                     field.components));
  }
}

AppendedArray field_array(const PointField& field) {
  AppendedArray array{.name = field.name, .components = field.components};
  if (!field.component_names.empty()) array.component_names = &field.component_names;
  std::visit(
      [&](const auto& values) {
        using Value = typename std::decay_t<decltype(values)>::value_type;
        array.type = std::is_same_v<Value, double> ? "Float64" : "Int64";
        const std::span<const Value> data(values);
        array.bytes = data.size_bytes();
        array.write_values = [data](std::ostream& out) { write_raw(out, data); };
      },
      field.values);
  return array;
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const std::vector<Vec3>& points,
               const std::vector<PointField>& fields) {
  const std::size_t n = points.size();
  std::set<std::string_view> names;
  for (const auto& field : fields) {
    check_field(field, n);
    // ParaView keeps only one of two arrays with the same name.
    if (!names.insert(field.name).second) {
      throw std::invalid_argument(fmt::format("VTU point field '{}' given twice", field.name));
    }
  }

  std::vector<AppendedArray> point_data;
  for (const auto& field : fields) point_data.push_back(field_array(field));

  const std::span<const double> coordinates(n == 0 ? nullptr : points.front().data(), 3 * n);
  const AppendedArray point_coordinates{
      .type = "Float64",
      .components = 3,
      .bytes = coordinates.size_bytes(),
      .write_values = [coordinates](std::ostream& out) { write_raw(out, coordinates); }};

  // One vertex cell per point: cell i is point i.
  const std::array<AppendedArray, 3> cells{{
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
  // holds them in the same order, each as a UInt64 byte count followed by the values.
  std::vector<const AppendedArray*> appended;
  std::uint64_t offset = 0;
  const auto describe = [&](const AppendedArray& array, std::string_view indent) {
    std::string xml = fmt::format("{}{}\n", indent, data_array_xml(array, offset));
    offset += sizeof(std::uint64_t) + array.bytes;
    appended.push_back(&array);
    return xml;
  };

  std::string header =
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\"LittleEndian\" "
      "header_type=\"UInt64\">\n"
      "  <UnstructuredGrid>\n";
  header += fmt::format("    <Piece NumberOfPoints=\"{}\" NumberOfCells=\"{}\">\n", n, n);
  header += "      <PointData>\n";
  for (const auto& array : point_data) header += describe(array, "        ");
  header += "      </PointData>\n      <Points>\n";
  header += describe(point_coordinates, "        ");
  header += "      </Points>\n      <Cells>\n";
  for (const auto& array : cells) header += describe(array, "        ");
  header +=
      "      </Cells>\n"
      "    </Piece>\n"
      "  </UnstructuredGrid>\n"
      "  <AppendedData encoding=\"raw\">\n"
      "   _";  // the appended data start right after the underscore

  replace_file_atomically(path, [&](std::ostream& out) {
    out << header;
    for (const AppendedArray* array : appended) {
      const std::uint64_t bytes = array->bytes;
      write_raw(out, std::span<const std::uint64_t>(&bytes, 1));
      array->write_values(out);
    }
    out << "\n  </AppendedData>\n</VTKFile>\n";
  });
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
                       xml_escaped(file));
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
