#include "spall/io/keyword/card.hpp"

#include <cmath>
#include <limits>

#include "spall/io/keyword/numbers.hpp"

namespace spall::io::keyword {

std::string quoted(std::string_view text) {
  std::string result;
  result.reserve(text.size() + 2);
  result += '\'';
  result += text;
  result += '\'';
  return result;
}

void CardContext::fail(int line, const std::string& message) const {
  throw InputError(where(line), keyword, message);
}

Card::Card(const CardContext& context, const DataLine& line, std::span<const int> widths)
    : context_(&context), line_(line.line) {
  const std::string_view text = line.text;
  if (text.find(',') != std::string_view::npos) {
    // A value past the card's last field would be lost: it is an error (blank trailing fields, as
    // a closing comma leaves, are not).
    std::size_t start = 0;
    std::size_t given = 0;  // fields up to the last that holds a value
    for (std::size_t index = 0;; ++index) {
      const std::size_t comma = text.find(',', start);
      const std::string_view field =
          trim(text.substr(start, comma == std::string_view::npos ? comma : comma - start));
      if (count_ < max_fields) fields_[count_++] = field;
      if (!field.empty()) given = index + 1;
      if (comma == std::string_view::npos) break;
      start = comma + 1;
    }
    if (given > widths.size())
      context.fail(line_, std::to_string(given) + " comma-separated values on a card of " +
                              std::to_string(widths.size()) + " fields; the values past its last field go on a "
                              "card of their own");
    return;
  }
  std::size_t column = 0;
  for (int width : widths) {
    if (count_ == max_fields) break;
    if (context.long_format && width < 20) width = 20;
    fields_[count_++] = column < text.size() ? trim(text.substr(column, width)) : std::string_view{};
    column += static_cast<std::size_t>(width);
  }
}

void Card::fail(std::string_view name, const std::string& message) const {
  context_->fail(line_, "field " + std::string(name) + ": " + message);
}

const ParameterValue* Card::reference(std::string_view field_text, std::string_view name,
                                      bool& negated) const {
  negated = false;
  if (field_text.front() == '-' && field_text.size() > 1 && field_text[1] == '&') {
    negated = true;
    field_text.remove_prefix(1);
  }
  if (field_text.front() != '&') return nullptr;
  const std::string_view parameter = trim(field_text.substr(1));
  const ParameterValue* value = context_->parameters.find(parameter);
  if (!value)
    fail(name, "parameter '" + std::string(parameter) + "' is not defined (or not visible here)");
  if (value->type == 'C')
    fail(name, "parameter '" + std::string(parameter) + "' is text ('" + value->text +
                   "'), not a number");
  return value;
}

std::optional<Real> Card::number(int field, std::string_view name) const {
  if (blank(field)) return std::nullopt;
  const std::string_view field_text = fields_[field];
  bool negated = false;
  if (const ParameterValue* value = reference(field_text, name, negated))
    return negated ? -value->number : value->number;
  const auto value = parse_real(field_text);
  if (!value) fail(name, "cannot read '" + std::string(field_text) + "' as a number");
  return value;
}

std::optional<std::int64_t> Card::whole_number(int field, std::string_view name) const {
  if (blank(field)) return std::nullopt;
  const std::string_view field_text = fields_[field];
  bool negated = false;
  if (const ParameterValue* value = reference(field_text, name, negated)) {
    const double number = negated ? -value->number : value->number;
    if (std::abs(number) > 9.0e18 || number != std::trunc(number))
      fail(name, "parameter " + std::string(field_text) + " = " + std::to_string(number) +
                     " is not an integer");
    return static_cast<std::int64_t>(number);
  }
  std::int64_t value = 0;
  switch (parse_integer(field_text, value)) {
    case IntegerParse::ok: return value;
    case IntegerParse::not_integral:
      fail(name, quoted(field_text) + " is not an integer");
    case IntegerParse::not_a_number:
      fail(name, "cannot read '" + std::string(field_text) + "' as an integer");
  }
  return value;
}

Real Card::real(int field, std::string_view name, Real fallback) const {
  return number(field, name).value_or(fallback);
}

Real Card::required_real(int field, std::string_view name) const {
  const auto value = number(field, name);
  if (!value) fail(name, "is blank but has no default; a value is required");
  return *value;
}

std::int64_t Card::integer(int field, std::string_view name, std::int64_t fallback) const {
  return whole_number(field, name).value_or(fallback);
}

std::int64_t Card::required_integer(int field, std::string_view name) const {
  const auto value = whole_number(field, name);
  if (!value) fail(name, "is blank but has no default; a value is required");
  return *value;
}

namespace {
int narrowed(const Card& card, int field, std::string_view name, std::int64_t value) {
  if (value < std::numeric_limits<int>::min() || value > std::numeric_limits<int>::max())
    card.fail(name, quoted(card.text(field)) + " is beyond the range of this field (a 32-bit integer)");
  return static_cast<int>(value);
}
}  // namespace

int Card::int32(int field, std::string_view name, int fallback) const {
  const auto value = whole_number(field, name);
  return value ? narrowed(*this, field, name, *value) : fallback;
}

int Card::required_int32(int field, std::string_view name) const {
  return narrowed(*this, field, name, required_integer(field, name));
}

int Card::zero_or_one(int field, std::string_view name) const {
  const std::int64_t value = whole_number(field, name).value_or(0);
  if (value != 0 && value != 1) fail(name, quoted(text(field)) + " is not 0 or 1");
  return static_cast<int>(value);
}

Card CardCursor::next(std::span<const int> widths, std::string_view card) {
  if (done()) {
    const int line = context_.block.data.empty() ? context_.block.line
                                                 : context_.block.data.back().line;
    context_.fail(line, "missing " + std::string(card));
  }
  return Card(context_, context_.block.data[next_++], widths);
}

std::optional<Card> CardCursor::next_if_any(std::span<const int> widths) {
  if (done()) return std::nullopt;
  return Card(context_, context_.block.data[next_++], widths);
}

std::string CardCursor::next_text(std::string_view card) {
  if (done()) context_.fail(context_.block.line, "missing " + std::string(card));
  // Headings are free text: LS-PrePost and Workbench pad them on either side.
  return std::string(trim(context_.block.data[next_++].text));
}

void CardCursor::skip_blank_lines() {
  while (!done() && trim(peek().text).empty()) ++next_;
}

void CardCursor::expect_end(std::string_view last_card, std::string_view why) {
  skip_blank_lines();
  if (done()) return;
  std::string message = "unexpected data line";
  if (!last_card.empty()) message += " after " + std::string(last_card);
  if (!why.empty()) message += "; " + std::string(why);
  context_.fail(peek().line, message);
}

}  // namespace spall::io::keyword
