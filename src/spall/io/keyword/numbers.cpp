#include "spall/io/keyword/numbers.hpp"

#include <cctype>
#include <charconv>
#include <cmath>

namespace spall::io::keyword {

std::string_view trim(std::string_view text) {
  const auto blank = [](char c) { return c == ' ' || c == '\t'; };
  while (!text.empty() && blank(text.front())) text.remove_prefix(1);
  while (!text.empty() && blank(text.back())) text.remove_suffix(1);
  return text;
}

std::optional<double> parse_real(std::string_view text) {
  if (text.empty() || text.size() > 60) return std::nullopt;
  // from_chars takes neither a leading `+` nor `inf`/`nan`, which no deck means as a number.
  if (text.front() == '+') text.remove_prefix(1);
  if (text.empty()) return std::nullopt;
  const char first = text.front();
  if (!(first == '-' || first == '.' || (first >= '0' && first <= '9'))) return std::nullopt;

  // from_chars reads `-inf` and `-nan` too: no deck means them, and no later check expects them.
  double value = 0;
  auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error == std::errc{} && end == text.data() + text.size())
    return std::isfinite(value) ? std::optional(value) : std::nullopt;

  // Fortran exponents: `D` for `E`, or a bare sign after the mantissa (`1.0+4`, `3.5-10`).
  char buffer[72];
  std::size_t size = 0;
  bool has_exponent = false;
  for (std::size_t i = 0; i < text.size(); ++i) {
    char c = text[i];
    if (c == 'D' || c == 'd') c = 'E';
    if (c == 'E' || c == 'e') has_exponent = true;
    const bool after_mantissa = i > 0 && (std::isdigit(static_cast<unsigned char>(text[i - 1])) ||
                                          text[i - 1] == '.');
    if ((c == '+' || c == '-') && after_mantissa && !has_exponent) {
      buffer[size++] = 'E';
      has_exponent = true;
    }
    buffer[size++] = c;
  }
  auto [end2, error2] = std::from_chars(buffer, buffer + size, value);
  if (error2 == std::errc{} && end2 == buffer + size && std::isfinite(value)) return value;
  return std::nullopt;
}

IntegerParse parse_integer(std::string_view text, std::int64_t& value) {
  std::string_view digits = text;
  if (!digits.empty() && digits.front() == '+') digits.remove_prefix(1);
  auto [end, error] = std::from_chars(digits.data(), digits.data() + digits.size(), value);
  if (!digits.empty() && error == std::errc{} && end == digits.data() + digits.size())
    return IntegerParse::ok;
  const auto real = parse_real(text);
  if (!real) return IntegerParse::not_a_number;
  if (*real != std::trunc(*real) || std::abs(*real) > 9.0e18) return IntegerParse::not_integral;
  value = static_cast<std::int64_t>(*real);
  return IntegerParse::ok;
}

}  // namespace spall::io::keyword
