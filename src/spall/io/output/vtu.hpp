#pragma once
// ParaView output: a .vtu file per output time (VTK XML UnstructuredGrid, binary appended data,
// one vertex cell per point) and a .pvd series that lists them with their times.
#include <cstdint>
#include <filesystem>
#include <string>
#include <variant>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::io::output {

// A point field: `components` values per point, point-major (x0 y0 z0 x1 y1 z1 ...).
struct PointField {
  std::string name;
  int components = 1;
  std::variant<std::vector<double>, std::vector<std::int64_t>> values;
};

void write_vtu(const std::filesystem::path& path, const std::vector<Vec3>& points,
               const std::vector<PointField>& fields);

class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path path) : path_(std::move(path)) {}
  // Adds a dataset (path relative to the .pvd file) and rewrites the .pvd, so that a series
  // stays openable when a run stops early.
  void add(double time, const std::string& relative_file);

 private:
  std::filesystem::path path_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace spall::io::output
