#pragma once
// A triangle surface as a binary little-endian PLY file (Turk 1994's format), which ParaView,
// MeshLab and Blender open: vertices as float x y z, faces as lists of int vertex indices.
#include <array>
#include <filesystem>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::io::output {

// Throws std::invalid_argument for a triangle naming a vertex that does not exist,
// std::runtime_error (naming the path) when the file cannot be written. Written through a
// temporary file.
void write_ply(const std::filesystem::path& path, const std::vector<Vec3>& vertices,
               const std::vector<std::array<Index, 3>>& triangles);

}  // namespace spall::io::output
