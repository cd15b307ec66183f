#pragma once
// Time histories as CSV (glstat.csv, ...): a header line of `name [unit]` columns, one row per
// output time, flushed on every row so a crashed run keeps its history.
#include <filesystem>
#include <fstream>
#include <span>
#include <string>
#include <vector>

namespace spall::io::output {

struct Column {
  std::string name;
  std::string unit;  // empty for dimensionless
};

class CsvHistory {
 public:
  // Creates (or truncates) the file and writes the header. Throws std::runtime_error naming the
  // path when it cannot be written, std::invalid_argument for no columns.
  CsvHistory(const std::filesystem::path& path, std::vector<Column> columns);
  // One value per column (std::invalid_argument otherwise), with 10 significant digits.
  void append(std::span<const double> row);

 private:
  void flush_or_throw();

  std::filesystem::path path_;
  std::ofstream out_;
  std::size_t columns_ = 0;
};

}  // namespace spall::io::output
