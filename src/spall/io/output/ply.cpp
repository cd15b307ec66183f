#include "spall/io/output/ply.hpp"

#include <bit>
#include <cstdint>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>

#include "spall/io/output/atomic_file.hpp"

namespace spall::io::output {

static_assert(std::endian::native == std::endian::little, "the PLY writer assumes a little-endian host");

void write_ply(const std::filesystem::path& path, const std::vector<Vec3>& vertices,
               const std::vector<std::array<Index, 3>>& triangles) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    for (Index v : triangles[t]) {
      if (v < 0 || static_cast<std::size_t>(v) >= vertices.size())
        throw std::invalid_argument(fmt::format("PLY triangle {} names vertex {} of {}", t, v, vertices.size()));
    }
  }
  // Single-precision vertices: what every PLY reader understands.
  const std::string header = fmt::format(
      "ply\n"
      "format binary_little_endian 1.0\n"
      "comment written by Spall (spall surface)\n"
      "element vertex {}\n"
      "property float x\n"
      "property float y\n"
      "property float z\n"
      "element face {}\n"
      "property list uchar int vertex_indices\n"
      "end_header\n",
      vertices.size(), triangles.size());
  replace_file_atomically(path, [&](std::ostream& out) {
    out << header;
    for (const Vec3& v : vertices) {
      const float xyz[3] = {float(v.x()), float(v.y()), float(v.z())};
      out.write(reinterpret_cast<const char*>(xyz), sizeof(xyz));
    }
    for (const auto& t : triangles) {
      const std::uint8_t corners = 3;
      const std::int32_t index[3] = {t[0], t[1], t[2]};
      out.write(reinterpret_cast<const char*>(&corners), 1);
      out.write(reinterpret_cast<const char*>(index), sizeof(index));
    }
  });
}

}  // namespace spall::io::output
