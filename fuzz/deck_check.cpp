#include "deck_check.hpp"

#include <string>

#include "spall/io/keyword/reader.hpp"
#include "spall/io/keyword/unsupported.hpp"

namespace spall::fuzz {

void check_deck_text(std::string_view text) {
  const model::Model model = io::keyword::read_deck_text(std::string(text), "fuzz.k");
  io::keyword::refuse_unsupported_physics(model, {});
  io::keyword::validate(model);
}

}  // namespace spall::fuzz
