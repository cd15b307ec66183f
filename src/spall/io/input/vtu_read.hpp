#pragma once
// Reads back the files src/spall/io/output/vtu.cpp writes: a .vtu snapshot (VTK XML
// UnstructuredGrid, raw binary appended data, UInt64 headers, little-endian), a .pvtu that joins
// such pieces (an MPI run's), and their .pvd series.
// Post-processing (`spall surface`) reads a run's output with it; it reads no other VTK flavour
// (no compression, no inline or base64 data) and says so.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "spall/core/types.hpp"
#include "spall/io/output/vtu.hpp"

namespace spall::io::input {

struct VtuSnapshot {
  std::vector<Vec3> points;
  std::vector<discretization::Field> fields;  // Float64 fields as double, Int64 as int64, file order

  // The field called `name`, or nullptr.
  const discretization::Field* field(std::string_view name) const;
};

// A .vtu, or the pieces of a .pvtu one after the other. Throws InputError ("PATH: what is wrong")
// for a file it cannot read or that is not in the format above.
VtuSnapshot read_vtu(const std::filesystem::path& path);

struct SeriesEntry {
  double time = 0;
  std::string file;  // as written in the .pvd: relative to the .pvd's folder
};

// The datasets of a .pvd collection in file order. Throws InputError as read_vtu does.
std::vector<SeriesEntry> read_pvd(const std::filesystem::path& path);

}  // namespace spall::io::input
