#include "spall/io/output/history.hpp"

#include <cerrno>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

namespace spall::io::output {
namespace {

// RFC 4180: a header cell with a comma, quote or line break is quoted, quotes doubled, so that
// spreadsheet and pandas readers keep the columns apart.
std::string csv_cell(std::string_view text) {
  if (text.find_first_of(",\"\r\n") == std::string_view::npos) return std::string(text);
  std::string quoted = "\"";
  for (const char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + '"';
}

std::string column_heading(const Column& column) {
  return column.unit.empty() ? column.name : fmt::format("{} [{}]", column.name, column.unit);
}

}  // namespace

CsvHistory::CsvHistory(const std::filesystem::path& path, std::vector<Column> columns)
    : path_(path), columns_(columns.size()) {
  if (columns.empty()) {
    throw std::invalid_argument(fmt::format("history {}: no columns", path_.string()));
  }
  out_.open(path_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw std::runtime_error(fmt::format("cannot write {}: {}", path_.string(), std::strerror(errno)));
  }
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) header += ',';
    header += csv_cell(column_heading(columns[i]));
  }
  out_ << header << '\n';
  flush_or_throw();
}

void CsvHistory::append(std::span<const double> row) {
  if (row.size() != columns_) {
    throw std::invalid_argument(fmt::format("history {}: row of {} values for {} columns",
                                            path_.string(), row.size(), columns_));
  }
  // fmt, not iostreams or printf: the numbers must not follow a user's locale (decimal comma).
  fmt::memory_buffer line;
  for (std::size_t i = 0; i < row.size(); ++i) {
    if (i > 0) line.push_back(',');
    fmt::format_to(std::back_inserter(line), "{:.10g}", row[i]);
  }
  line.push_back('\n');
  out_.write(line.data(), static_cast<std::streamsize>(line.size()));
  flush_or_throw();
}

// Every row reaches the file at once, so that a run that crashes keeps its history so far.
void CsvHistory::flush_or_throw() {
  out_.flush();
  if (!out_) throw std::runtime_error(fmt::format("cannot write {}", path_.string()));
}

}  // namespace spall::io::output
