#include "spall/core/error.hpp"

namespace spall {

namespace {
std::string format_input_error(const SourceLocation& where, const std::string& keyword,
                               const std::string& message) {
  std::string text;
  if (!where.file.empty()) text += where.file + ":" + std::to_string(where.line) + ": ";
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
