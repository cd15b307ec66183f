#pragma once
// A triangle surface for ParaView: VTK XML PolyData (.vtp), raw binary appended data, with point
// fields on the vertices.
#include <array>
#include <filesystem>
#include <vector>

#include "spall/core/types.hpp"
#include "spall/io/output/vtu.hpp"

namespace spall::io::output {

// Writes the triangles (vertex indices into `vertices`) as Polys, the fields as point data, through
// a temporary file. Throws std::invalid_argument for a field that does not fit the vertices or a
// triangle naming a vertex that does not exist, std::runtime_error (naming the path) when the file
// cannot be written.
void write_vtp(const std::filesystem::path& path, const std::vector<Vec3>& vertices,
               const std::vector<std::array<Index, 3>>& triangles, const std::vector<discretization::Field>& fields);

}  // namespace spall::io::output
