#include "spall/core/error.hpp"

#include <functional>
#include <mutex>
#include <set>

namespace spall {

FileName::FileName(std::string_view name) {
  // A set's elements stay where they are as it grows; names are never removed.
  static std::mutex mutex;
  static std::set<std::string, std::less<>> names;
  const std::lock_guard lock(mutex);
  auto it = names.find(name);
  if (it == names.end()) it = names.emplace(name).first;
  name_ = &*it;
}

const std::string& FileName::str() const {
  static const std::string none;
  return name_ ? *name_ : none;
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
