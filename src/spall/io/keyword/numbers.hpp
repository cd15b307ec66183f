#pragma once
// Numbers as LS-DYNA writes them: `1.5`, `1.5E+4`, and the Fortran forms `1.5+4` (= 1.5E+4),
// `3.5-10` and `1.0D4`, which FORTRAN list-directed input accepts and real decks contain.
#include <cstdint>
#include <optional>
#include <string_view>

namespace spall::io::keyword {

// Leading and trailing blanks (space, tab) removed.
std::string_view trim(std::string_view text);

// The whole of `text` (already trimmed) as a number, or nothing if it is not one.
std::optional<double> parse_real(std::string_view text);

// The whole of `text` (already trimmed) as an integer. A real with an integral value (`2.`,
// `2.0`, `1.0E3`) is accepted, because decks and real-valued parameters write IDs that way.
enum class IntegerParse { ok, not_a_number, not_integral };
IntegerParse parse_integer(std::string_view text, std::int64_t& value);

}  // namespace spall::io::keyword
