#pragma once
// Cutting one data line into fields and reading them with the card's defaults.
//
//  - Fixed format: fields are cut by column, never by blanks, because LS-DYNA's fixed fields may
//    run together (`       0.01.000000E8` is 0.0 and 1.0E8).
//  - Free format: a line containing a comma is split at commas; missing trailing fields are blank.
//  - Long format (`*KEYWORD LONG=Y`, or `+` after a keyword name): every field is 20 characters.
//  - A blank field takes the card's default. `&name` / `-&name` takes a *PARAMETER value.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "spall/core/error.hpp"
#include "spall/core/types.hpp"
#include "spall/io/keyword/deck_lines.hpp"
#include "spall/io/keyword/parameters.hpp"

namespace spall::io::keyword {

// Standard column widths of a card: 8 fields of 10 characters.
inline constexpr std::array<int, 8> standard_fields = {10, 10, 10, 10, 10, 10, 10, 10};
// The fields of a card of eight IDs (*SET_NODE_LIST's members, *DATABASE_HISTORY_NODE's nodes).
inline constexpr const char* id_field_names[8] = {"ID1", "ID2", "ID3", "ID4", "ID5", "ID6", "ID7", "ID8"};

// `text` in single quotes, for messages that show the text found.
std::string quoted(std::string_view text);

// What every card of a keyword block needs to read its fields and to name itself in messages.
struct CardContext {
  const KeywordBlock& block;
  std::string keyword;  // `*` + the keyword name as written, for messages
  const Parameters& parameters;
  bool long_format = false;

  SourceLocation where(int line) const { return {block.file, line}; }
  [[noreturn]] void fail(int line, const std::string& message) const;
};

class Card {
 public:
  static constexpr int max_fields = 16;

  Card(const CardContext& context, const DataLine& line, std::span<const int> widths);

  int line() const { return line_; }
  const CardContext& context() const { return *context_; }
  SourceLocation where() const { return context_->where(line_); }
  bool blank(int field) const { return field >= count_ || fields_[field].empty(); }
  // The field's text, trimmed; empty when blank.
  std::string_view text(int field) const { return field < count_ ? fields_[field] : std::string_view{}; }

  Real real(int field, std::string_view name, Real fallback) const;
  Real required_real(int field, std::string_view name) const;
  std::int64_t integer(int field, std::string_view name, std::int64_t fallback) const;
  std::int64_t required_integer(int field, std::string_view name) const;
  // An integer field that a 32-bit int holds (flags, options, counts): a value beyond it is an
  // error, never its low 32 bits.
  int int32(int field, std::string_view name, int fallback) const;
  int required_int32(int field, std::string_view name) const;
  // A switch: blank reads as 0; a value other than 0 or 1 is an error naming the field.
  int zero_or_one(int field, std::string_view name) const;

  [[noreturn]] void fail(std::string_view name, const std::string& message) const;

 private:
  std::optional<Real> number(int field, std::string_view name) const;
  std::optional<std::int64_t> whole_number(int field, std::string_view name) const;
  // The value of a `&name` / `-&name` field; nullptr when the field is not a reference.
  const ParameterValue* reference(std::string_view field_text, std::string_view name,
                                  bool& negated) const;

  const CardContext* context_;
  int line_;
  int count_ = 0;
  std::array<std::string_view, max_fields> fields_{};
};

// Walks the data lines of a block, card by card.
class CardCursor {
 public:
  explicit CardCursor(const CardContext& context) : context_(context) {}

  bool done() const { return next_ >= context_.block.data.size(); }
  const DataLine& peek() const { return context_.block.data[next_]; }
  // The next line as a card; throws InputError naming `card` if the block has no more lines.
  Card next(std::span<const int> widths, std::string_view card);
  // The next line if there is one (an optional card).
  std::optional<Card> next_if_any(std::span<const int> widths);
  // The next line as free text (a title or heading), blanks at either end removed.
  std::string next_text(std::string_view card);
  // Skips lines that are entirely blank (blank separators between repeated cards).
  void skip_blank_lines();
  // The keyword's cards end here, after `last_card`: a further data line (blank lines aside) fails
  // as "unexpected data line after <last_card>" ("unexpected data line" where last_card is empty),
  // and `why` after a semicolon where given ("one *MAT_RIGID defines one material"), rather than
  // being read as a second item or dropped without a word.
  void expect_end(std::string_view last_card, std::string_view why = {});
  int line_of_block() const { return context_.block.line; }
  const CardContext& context() const { return context_; }

 private:
  const CardContext& context_;
  std::size_t next_ = 0;
};

}  // namespace spall::io::keyword
