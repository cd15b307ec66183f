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
  CsvHistory(const std::filesystem::path& path, std::vector<Column> columns);
  void append(std::span<const double> row);

 private:
  std::ofstream out_;
  std::size_t columns_ = 0;
};

}  // namespace spall::io::output
