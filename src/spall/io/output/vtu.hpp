#pragma once
// ParaView output: a .vtu file per output time (VTK XML UnstructuredGrid, binary appended data,
// one vertex cell per point) and a .pvd series that lists them with their times.
#include <cstdint>
#include <filesystem>
#include <string>
#include <utility>
#include <variant>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::io::output {

// A point field: `components` values per point, point-major (x0 y0 z0 x1 y1 z1 ...).
// Three components show in ParaView as a vector. component_names, when given (one per component),
// label the components in ParaView, e.g. symmetric_tensor_components for a stress in Voigt order.
struct PointField {
  std::string name;
  int components = 1;
  std::variant<std::vector<double>, std::vector<std::int64_t>> values;
  std::vector<std::string> component_names = {};
};

// Voigt order of a symmetric tensor's six components, as the solver stores stress and strain.
inline const std::vector<std::string> symmetric_tensor_components = {"xx", "yy", "zz",
                                                                     "xy", "yz", "zx"};

// Writes the points as VTK_VERTEX cells with the fields as point data, through a temporary file.
// Throws std::invalid_argument for a field whose size or names do not fit, std::runtime_error
// (naming the path) when the file cannot be written.
void write_vtu(const std::filesystem::path& path, const std::vector<Vec3>& points,
               const std::vector<PointField>& fields);

class PvdSeries {
 public:
  explicit PvdSeries(std::filesystem::path path) : path_(std::move(path)) {}
  // Adds a dataset (path relative to the .pvd file) and rewrites the .pvd, so that a series
  // stays openable when a run stops early. Throws std::runtime_error when it cannot be written.
  void add(double time, const std::string& relative_file);

 private:
  std::filesystem::path path_;
  std::vector<std::pair<double, std::string>> entries_;
};

}  // namespace spall::io::output
