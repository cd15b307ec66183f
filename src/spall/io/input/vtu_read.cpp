#include "spall/io/input/vtu_read.hpp"

#include <bit>
#include <charconv>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <iterator>
#include <optional>
#include <type_traits>
#include <variant>

#include <fmt/format.h>

#include "spall/core/error.hpp"
#include "spall/io/input/xml_tags.hpp"

namespace spall::io::input {

namespace fs = std::filesystem;

namespace {

static_assert(std::endian::native == std::endian::little, "the VTU reader assumes a little-endian host");

[[noreturn]] void fail(const fs::path& path, const std::string& what) {
  throw InputError(fmt::format("{}: {}", path.string(), what));
}

std::string read_whole_file(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) fail(path, "cannot open the file");
  std::string bytes{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
  if (in.bad()) fail(path, "cannot read the file");
  return bytes;
}

std::string required_attribute(const fs::path& path, const XmlTag& tag, std::string_view key) {
  auto value = xml_attribute(tag, key);
  if (!value) fail(path, fmt::format("<{}> has no {} attribute", tag.name, key));
  return *value;
}

// A non-negative integer attribute, read without the locale.
std::uint64_t count_attribute(const fs::path& path, const XmlTag& tag, std::string_view key) {
  const std::string text = required_attribute(path, tag, key);
  std::uint64_t value = 0;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size())
    fail(path, fmt::format("<{}> {}=\"{}\" is not a non-negative integer", tag.name, key, text));
  return value;
}

// One appended array: its bytes start `offset` past the underscore, after a UInt64 byte count.
struct ArrayDescription {
  std::string name;
  std::string type;
  int components = 1;
  std::vector<std::string> component_names;
  std::uint64_t offset = 0;
};

ArrayDescription describe(const fs::path& path, const XmlTag& tag) {
  ArrayDescription a;
  a.name = xml_attribute(tag, "Name").value_or("");
  a.type = required_attribute(path, tag, "type");
  const std::string label = a.name.empty() ? std::string("the points") : "'" + a.name + "'";
  if (xml_attribute(tag, "format").value_or("") != "appended")
    fail(path, fmt::format("array {} is not in the appended section (only Spall's own raw appended "
                           "VTU is read)", label));
  const std::uint64_t components = count_attribute(path, tag, "NumberOfComponents");
  if (components < 1 || components > 64) fail(path, fmt::format("array {}: {} components", label, components));
  a.components = static_cast<int>(components);
  a.offset = count_attribute(path, tag, "offset");
  for (int i = 0; i < a.components; ++i) {
    if (auto n = xml_attribute(tag, fmt::format("ComponentName{}", i))) a.component_names.push_back(*n);
  }
  if (!a.component_names.empty() && a.component_names.size() != components) a.component_names.clear();
  return a;
}

// The values of an appended array of `count` points, as T, checking the byte count against the
// file's size.
template <typename T>
std::vector<T> array_values(const fs::path& path, std::string_view appended, const ArrayDescription& a,
                            std::uint64_t count) {
  const std::string label = a.name.empty() ? std::string("the points") : "'" + a.name + "'";
  const std::uint64_t expected = count * static_cast<std::uint64_t>(a.components) * sizeof(T);
  std::uint64_t bytes = 0;
  if (a.offset > appended.size() || appended.size() - a.offset < sizeof(bytes))
    fail(path, fmt::format("array {}: offset {} is past the end of the file", label, a.offset));
  std::memcpy(&bytes, appended.data() + a.offset, sizeof(bytes));
  if (bytes != expected)
    fail(path, fmt::format("array {}: {} bytes for {} points of {} components (expected {})", label,
                           bytes, count, a.components, expected));
  if (appended.size() - a.offset - sizeof(bytes) < bytes)
    fail(path, fmt::format("array {}: the file ends inside it", label));
  std::vector<T> values(count * a.components);
  if (bytes > 0) std::memcpy(values.data(), appended.data() + a.offset + sizeof(bytes), bytes);
  return values;
}

}  // namespace

const discretization::Field* VtuSnapshot::field(std::string_view name) const {
  for (const auto& f : fields)
    if (f.name == name) return &f;
  return nullptr;
}

namespace {
// The pieces of a .pvtu, each read as a .vtu, joined: points and fields one piece after another.
VtuSnapshot read_pieces(const fs::path& path) {
  const std::string xml = read_whole_file(path);
  VtuSnapshot joined;
  bool parallel = false;
  int pieces = 0;
  for (const XmlTag& tag : xml_tags(xml)) {
    if (tag.name == "VTKFile") {
      parallel = xml_attribute(tag, "type").value_or("") == "PUnstructuredGrid";
      continue;
    }
    if (tag.name != "Piece") continue;
    const fs::path source = path.parent_path() / required_attribute(path, tag, "Source");
    VtuSnapshot piece = read_vtu(source);
    if (pieces++ == 0) {
      joined = std::move(piece);
      continue;
    }
    if (piece.fields.size() != joined.fields.size())
      fail(source, fmt::format("{} point fields, where the first piece of {} has {}", piece.fields.size(),
                               path.string(), joined.fields.size()));
    joined.points.insert(joined.points.end(), piece.points.begin(), piece.points.end());
    for (std::size_t k = 0; k < piece.fields.size(); ++k) {
      discretization::Field& to = joined.fields[k];
      const discretization::Field& from = piece.fields[k];
      if (from.name != to.name || from.components != to.components || from.values.index() != to.values.index())
        fail(source, fmt::format("point field '{}' is not the first piece's '{}' of {}", from.name, to.name,
                                 path.string()));
      std::visit(
          [&](auto& values) {
            const auto& more = std::get<std::decay_t<decltype(values)>>(from.values);
            values.insert(values.end(), more.begin(), more.end());
          },
          to.values);
    }
  }
  if (!parallel) fail(path, "not a VTK PUnstructuredGrid (.pvtu) file");
  if (pieces == 0) fail(path, "no <Piece Source=...>");
  return joined;
}
}  // namespace

VtuSnapshot read_vtu(const fs::path& path) {
  if (path.extension() == ".pvtu") return read_pieces(path);
  const std::string bytes = read_whole_file(path);
  const std::size_t appended_tag = bytes.find("<AppendedData");
  if (appended_tag == std::string::npos) fail(path, "no <AppendedData> section (not a VTU that Spall wrote)");
  const std::size_t underscore = bytes.find('_', bytes.find('>', appended_tag));
  if (underscore == std::string::npos) fail(path, "<AppendedData> has no '_' before its data");
  const std::string_view header = std::string_view(bytes).substr(0, appended_tag);
  const std::string_view appended = std::string_view(bytes).substr(underscore + 1);

  std::optional<std::uint64_t> point_count;
  std::optional<ArrayDescription> points;
  std::vector<ArrayDescription> point_data;
  std::string_view section;  // the enclosing PointData, Points, Cells, CellData or FieldData
  for (const XmlTag& tag : xml_tags(header)) {
    if (tag.name == "VTKFile") {
      const auto check = [&](std::string_view key, std::string_view wanted) {
        const std::string value = xml_attribute(tag, key).value_or("(none)");
        if (value != wanted)
          fail(path, fmt::format("<VTKFile {}=\"{}\">: only {}=\"{}\" is read", key, value, key, wanted));
      };
      check("type", "UnstructuredGrid");
      check("byte_order", "LittleEndian");
      check("header_type", "UInt64");
      if (xml_attribute(tag, "compressor")) fail(path, "compressed VTU is not read");
    } else if (tag.name == "AppendedData") {
      if (xml_attribute(tag, "encoding").value_or("") != "raw") fail(path, "appended data not raw");
    } else if (tag.name == "Piece") {
      if (point_count) fail(path, "more than one <Piece>");
      point_count = count_attribute(path, tag, "NumberOfPoints");
    } else if (tag.name == "PointData" || tag.name == "Points" || tag.name == "Cells" ||
               tag.name == "CellData" || tag.name == "FieldData") {
      if (!tag.text.ends_with('/')) section = tag.name;
    } else if (tag.name.starts_with('/') && tag.name.substr(1) == section) {
      section = {};
    } else if (tag.name == "DataArray") {
      if (section == "PointData") {
        point_data.push_back(describe(path, tag));
        if (point_data.back().name.empty()) fail(path, "a point field without a Name");
      } else if (section == "Points") {
        points = describe(path, tag);
      }
    }
  }
  if (!point_count) fail(path, "no <Piece NumberOfPoints=...>");
  if (!points) fail(path, "no <Points> array");
  if (points->type != "Float64" || points->components != 3)
    fail(path, fmt::format("points are {} x {} (expected Float64 x 3)", points->type, points->components));

  VtuSnapshot snap;
  const std::uint64_t n = *point_count;
  const auto coordinates = array_values<double>(path, appended, *points, n);
  snap.points.resize(n);
  for (std::uint64_t i = 0; i < n; ++i)
    snap.points[i] = Vec3(coordinates[3 * i], coordinates[3 * i + 1], coordinates[3 * i + 2]);
  for (const auto& a : point_data) {
    if (snap.field(a.name)) fail(path, fmt::format("point field '{}' given twice", a.name));
    discretization::Field field{
        .name = a.name, .components = a.components, .values = {}, .component_names = a.component_names};
    if (a.type == "Float64")
      field.values = array_values<double>(path, appended, a, n);
    else if (a.type == "Int64")
      field.values = array_values<std::int64_t>(path, appended, a, n);
    else
      fail(path, fmt::format("point field '{}' is {} (Spall writes Float64 and Int64)", a.name, a.type));
    snap.fields.push_back(std::move(field));
  }
  return snap;
}

std::vector<SeriesEntry> read_pvd(const fs::path& path) {
  const std::string xml = read_whole_file(path);
  std::vector<SeriesEntry> entries;
  bool collection = false;
  for (const XmlTag& tag : xml_tags(xml)) {
    if (tag.name == "VTKFile") {
      collection = xml_attribute(tag, "type").value_or("") == "Collection";
    } else if (tag.name == "DataSet") {
      SeriesEntry entry;
      const std::string time = required_attribute(path, tag, "timestep");
      const auto [end, error] = std::from_chars(time.data(), time.data() + time.size(), entry.time);
      if (error != std::errc() || end != time.data() + time.size())
        fail(path, fmt::format("<DataSet timestep=\"{}\"> is not a number", time));
      entry.file = required_attribute(path, tag, "file");
      entries.push_back(std::move(entry));
    }
  }
  if (!collection) fail(path, "not a VTK Collection (.pvd) file");
  return entries;
}

}  // namespace spall::io::input
