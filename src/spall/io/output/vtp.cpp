#include "spall/io/output/vtp.hpp"

#include <ostream>
#include <span>
#include <stdexcept>

#include <fmt/format.h>

#include "spall/io/output/vtk_xml.hpp"

namespace spall::io::output {

namespace {
void check_triangles(const std::vector<std::array<Index, 3>>& triangles, std::size_t vertex_count) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (Index v : triangles[t]) {
      if (v < 0 || static_cast<std::size_t>(v) >= vertex_count)
        throw std::invalid_argument(
            fmt::format("VTP triangle {} names vertex {} of {}", t, v, vertex_count));
    }
  }
}
}  // namespace

void write_vtp(const std::filesystem::path& path, const std::vector<Vec3>& vertices,
               const std::vector<std::array<Index, 3>>& triangles, const std::vector<discretization::Field>& fields) {
  const std::size_t n = vertices.size(), m = triangles.size();
  vtk_xml::check_point_fields(fields, n);
  check_triangles(triangles, n);

  // VTK's Polys: a flat connectivity list and the end of each polygon in it, both Int64 as in the
  // VTU; the vertices stay Float64.
  std::vector<std::int64_t> connectivity, offsets;
  connectivity.reserve(3 * m);
  offsets.reserve(m);
  for (const auto& t : triangles) {
    for (Index v : t) connectivity.push_back(v);
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
  }
  std::vector<double> coordinates;
  coordinates.reserve(3 * n);
  for (const Vec3& v : vertices) coordinates.insert(coordinates.end(), {v.x(), v.y(), v.z()});

  const auto array = [](std::string name, std::string_view type, int components, const auto& values) {
    const std::span data(values);
    return vtk_xml::AppendedArray{
        .name = std::move(name),
        .type = type,
        .components = components,
        .bytes = data.size_bytes(),
        .write_values = [data](std::ostream& out) { vtk_xml::write_raw(out, data); }};
  };

  vtk_xml::AppendedSection appended;
  std::string header = vtk_xml::file_opening("PolyData") + "  <PolyData>\n";
  header += fmt::format(
      "    <Piece NumberOfPoints=\"{}\" NumberOfVerts=\"0\" NumberOfLines=\"0\" NumberOfStrips=\"0\" "
      "NumberOfPolys=\"{}\">\n",
      n, m);
  header += "      <PointData>\n";
  for (const auto& field : fields)
    header += appended.describe(vtk_xml::point_field_array(field), "        ");
  header += "      </PointData>\n      <Points>\n";
  header += appended.describe(array("", "Float64", 3, coordinates), "        ");
  header += "      </Points>\n      <Polys>\n";
  header += appended.describe(array("connectivity", "Int64", 1, connectivity), "        ");
  header += appended.describe(array("offsets", "Int64", 1, offsets), "        ");
  header +=
      "      </Polys>\n"
      "    </Piece>\n"
      "  </PolyData>\n";
  appended.write_file(path, header);
}

}  // namespace spall::io::output
