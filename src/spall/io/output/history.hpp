#pragma once
// Time histories as CSV (glstat.csv, ...): a header line of `name [unit]` columns, one row per
// output time, flushed on every row so a crashed run keeps its history.
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "spall/core/archive.hpp"

namespace spall::io::output {

struct Column {
  std::string name;
  std::string unit;  // empty for dimensionless

  void checkpoint(Archive& a) { a(name, unit); }
};

class CsvHistory {
 public:
  // Creates (or truncates) the file and writes the header. Throws OutputError naming the
  // path when it cannot be written, std::invalid_argument for no columns.
  CsvHistory(const std::filesystem::path& path, std::vector<Column> columns);
  // Continues a file written with these columns, kept to its first `resume_at` bytes (a restart
  // drops the rows written after its checkpoint). Throws InputError naming the path when
  // the file is shorter or its header differs.
  CsvHistory(const std::filesystem::path& path, std::vector<Column> columns, std::uint64_t resume_at);
  // One value per column (std::invalid_argument otherwise), with 10 significant digits.
  void append(std::span<const double> row);
  // Bytes in the file so far (header and rows), what a checkpoint keeps.
  std::uint64_t bytes() const { return bytes_; }

 private:
  void write(std::string_view text);

  std::filesystem::path path_;
  std::ofstream out_;
  std::size_t columns_ = 0;
  std::uint64_t bytes_ = 0;
};

}  // namespace spall::io::output
