#include "spall/core/error.hpp"

#include <deque>
#include <map>
#include <mutex>

namespace spall {

namespace {
// The names read so far, in the order they were first met (a deque's elements stay where they are
// as it grows; names are never removed), and each name's number, by a view of the name.
struct FileNames {
  std::mutex mutex;
  std::deque<std::string> names;
  std::map<std::string_view, std::uint32_t> number;
};
FileNames& file_names() {
  static FileNames table;
  return table;
}
}  // namespace

FileName::FileName(std::string_view name) {
  if (name.empty()) return;
  FileNames& table = file_names();
  const std::lock_guard lock(table.mutex);
  auto it = table.number.find(name);
  if (it == table.number.end()) {
    table.names.emplace_back(name);
    it = table.number.emplace(std::string_view(table.names.back()), static_cast<std::uint32_t>(table.names.size()))
             .first;
  }
  number_ = it->second;
}

const std::string& FileName::str() const {
  static const std::string none;
  if (number_ == 0) return none;
  FileNames& table = file_names();
  const std::lock_guard lock(table.mutex);
  return table.names[number_ - 1];
}

std::string to_string(const SourceLocation& where) { return where.file.str() + ":" + std::to_string(where.line); }

namespace {
std::string format_input_error(const SourceLocation& where, const std::string& keyword,
                               const std::string& message) {
  std::string text;
  if (!where.file.empty()) text += to_string(where) + ": ";
  if (!keyword.empty()) text += keyword + ": ";
  return text + message;
}
}  // namespace

InputError::InputError(SourceLocation where, std::string keyword, std::string message)
    : std::runtime_error(format_input_error(where, keyword, message)),
      where_(std::move(where)),
      keyword_(std::move(keyword)),
      message_(std::move(message)) {}

InputError::InputError(std::string message)
    : std::runtime_error(message), message_(std::move(message)) {}

void fail_at(const SourceLocation& where, const std::string& keyword, const std::string& message) {
  throw InputError(where, keyword, message);
}

}  // namespace spall
