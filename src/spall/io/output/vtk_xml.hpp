#pragma once
// The pieces the VTK XML writers share (vtu.cpp: particles, vtp.cpp: surface meshes): arrays in a
// raw binary appended section, each a UInt64 byte count followed by its values, little-endian, and
// point fields checked against the point count.
#include <cstdint>
#include <filesystem>
#include <functional>
#include <ostream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "spall/io/output/vtu.hpp"

namespace spall::io::output::vtk_xml {

std::string escaped(std::string_view text);

template <class T>
void write_raw(std::ostream& out, std::span<const T> values) {
  out.write(reinterpret_cast<const char*>(values.data()),
            static_cast<std::streamsize>(values.size_bytes()));
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

// Checks that every field fits `point_count` points and that no name repeats (ParaView keeps only
// one of two arrays with the same name); throws std::invalid_argument naming the field otherwise.
void check_point_fields(const std::vector<discretization::Field>& fields, std::size_t point_count);

// The array of a point field; it refers to the field's values, which must outlive it.
AppendedArray point_field_array(const discretization::Field& field);

// Arrays listed in the XML header in the order they are described, then written in that order.
class AppendedSection {
 public:
  // The <DataArray .../> line of `array` at the next offset, with `indent` before it.
  std::string describe(AppendedArray array, std::string_view indent);
  // The <PDataArray .../> line of `array` in a parallel file (.pvtu) that lists the pieces which
  // hold it, with `indent` before it.
  static std::string describe_in_pieces(const AppendedArray& array, std::string_view indent);

  // Writes `header` (the file up to and including the closing tag of the dataset element), the
  // appended section and </VTKFile>, through a temporary file.
  void write_file(const std::filesystem::path& path, const std::string& header) const;

 private:
  static std::string attributes(const AppendedArray& array);

  std::vector<AppendedArray> arrays_;
  std::uint64_t offset_ = 0;
};

// The line that opens a VTKFile of type `type` with the byte order and header type the appended
// section uses.
std::string file_opening(std::string_view type);

}  // namespace spall::io::output::vtk_xml
