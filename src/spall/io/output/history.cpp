#include "spall/io/output/history.hpp"

#include <cerrno>
#include <cstring>
#include <iterator>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>

#include "spall/core/error.hpp"

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

std::string header_line(const std::filesystem::path& path, const std::vector<Column>& columns) {
  if (columns.empty()) throw std::invalid_argument(fmt::format("history {}: no columns", path.string()));
  std::string header;
  for (std::size_t i = 0; i < columns.size(); ++i) {
    if (i > 0) header += ',';
    header += csv_cell(column_heading(columns[i]));
  }
  return header + '\n';
}

}  // namespace

CsvHistory::CsvHistory(const std::filesystem::path& path, std::vector<Column> columns)
    : path_(path), columns_(columns.size()) {
  const std::string header = header_line(path_, columns);
  out_.open(path_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw OutputError(fmt::format("cannot write {}: {}", path_.string(), std::strerror(errno)));
  }
  write(header);
}

CsvHistory::CsvHistory(const std::filesystem::path& path, std::vector<Column> columns, std::uint64_t resume_at)
    : path_(path), columns_(columns.size()), bytes_(resume_at) {
  const std::string header = header_line(path_, columns);
  std::error_code error;
  const auto size = std::filesystem::file_size(path_, error);
  std::string first(header.size(), '\0');
  std::ifstream in(path_, std::ios::binary);
  if (error || size < resume_at || resume_at < header.size() || !in.read(first.data(), std::ssize(first)) ||
      first != header)
    throw InputError(fmt::format("cannot continue {}: it is not the file the checkpoint was written with",
                                         path_.string()));
  in.close();
  std::filesystem::resize_file(path_, resume_at);
  out_.open(path_, std::ios::binary | std::ios::app);
  if (!out_) {
    throw OutputError(fmt::format("cannot write {}: {}", path_.string(), std::strerror(errno)));
  }
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
  write(std::string_view(line.data(), line.size()));
}

// Every row reaches the file at once, so that a run that crashes keeps its history so far.
void CsvHistory::write(std::string_view text) {
  out_.write(text.data(), static_cast<std::streamsize>(text.size()));
  out_.flush();
  if (!out_) throw OutputError(fmt::format("cannot write {}: {}", path_.string(), std::strerror(errno)));
  bytes_ += text.size();
}

}  // namespace spall::io::output
