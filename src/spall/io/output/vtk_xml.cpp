#include "spall/io/output/vtk_xml.hpp"

#include <bit>
#include <set>
#include <stdexcept>
#include <type_traits>
#include <variant>

#include <fmt/format.h>

#include "spall/io/output/atomic_file.hpp"

namespace spall::io::output::vtk_xml {

// The files declare byte_order="LittleEndian" and the arrays are written straight from memory.
static_assert(std::endian::native == std::endian::little, "VTK writers assume a little-endian host");

std::string escaped(std::string_view text) {
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

namespace {
void check_field(const discretization::Field& field, std::size_t point_count) {
  const auto fail = [&](const std::string& why) {
    throw std::invalid_argument(fmt::format("VTK point field '{}': {}", field.name, why));
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
}  // namespace

void check_point_fields(const std::vector<discretization::Field>& fields, std::size_t point_count) {
  std::set<std::string_view> names;
  for (const auto& field : fields) {
    check_field(field, point_count);
    if (!names.insert(field.name).second) {
      throw std::invalid_argument(fmt::format("VTK point field '{}' given twice", field.name));
    }
  }
}

AppendedArray point_field_array(const discretization::Field& field) {
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

// type="..." Name="..." NumberOfComponents="..." ComponentName0="..." ...
std::string AppendedSection::attributes(const AppendedArray& array) {
  std::string xml = fmt::format(R"(type="{}")", array.type);
  if (!array.name.empty()) xml += fmt::format(R"( Name="{}")", escaped(array.name));
  xml += fmt::format(R"( NumberOfComponents="{}")", array.components);
  if (array.component_names) {
    for (std::size_t i = 0; i < array.component_names->size(); ++i) {
      xml += fmt::format(R"( ComponentName{}="{}")", i, escaped((*array.component_names)[i]));
    }
  }
  return xml;
}

std::string AppendedSection::describe_in_pieces(const AppendedArray& array, std::string_view indent) {
  return fmt::format("{}<PDataArray {}/>\n", indent, attributes(array));
}

std::string AppendedSection::describe(AppendedArray array, std::string_view indent) {
  std::string xml = fmt::format("{}<DataArray {}", indent, attributes(array));
  xml += fmt::format(R"( format="appended" offset="{}"/>)", offset_);
  xml += '\n';
  offset_ += sizeof(std::uint64_t) + array.bytes;
  arrays_.push_back(std::move(array));
  return xml;
}

void AppendedSection::write_file(const std::filesystem::path& path, const std::string& header) const {
  replace_file_atomically(path, [&](std::ostream& out) {
    out << header;
    out << "  <AppendedData encoding=\"raw\">\n   _";  // the data start right after the underscore
    for (const AppendedArray& array : arrays_) {
      const std::uint64_t bytes = array.bytes;
      write_raw(out, std::span<const std::uint64_t>(&bytes, 1));
      array.write_values(out);
    }
    out << "\n  </AppendedData>\n</VTKFile>\n";
  });
}

std::string file_opening(std::string_view type) {
  return fmt::format(
      "<?xml version=\"1.0\"?>\n"
      "<VTKFile type=\"{}\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n",
      type);
}

}  // namespace spall::io::output::vtk_xml
