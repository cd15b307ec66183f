#pragma once
// The work of one fuzz input, shared by the libFuzzer target (clang, fuzz/keyword_fuzz.cpp) and its
// replay and mutation test in the normal build (GCC, tests/unit/test_keyword_fuzz.cpp).
#include <string_view>

namespace spall::fuzz {

// Reads `text` as the deck `fuzz.k` in the working folder (its *INCLUDEs are looked for there) and
// checks it as `spall check` does before it builds the problem: unsupported physics refused, cross
// references validated. Bad input throws InputError; anything else that escapes is a bug.
void check_deck_text(std::string_view text);

}  // namespace spall::fuzz
