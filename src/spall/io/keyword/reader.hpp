#pragma once
// LS-DYNA keyword reader: deck file(s) -> model::Model.
#include <filesystem>
#include <string>

#include "spall/model/model.hpp"

namespace spall::io::keyword {

// Reads the deck at `path` and every file it includes (*INCLUDE, relative to the including file),
// expanding *PARAMETER references. Cards Spall does not support are recorded in
// Model::unsupported (one entry per keyword occurrence). Throws InputError on the first bad card,
// with file, line, keyword and what is wrong (field name and the text found). With `cards` dealing
// them, only this rank's share of the *NODE and *ELEMENT_SPH cards is kept (every line still read).
model::Model read_deck(const std::filesystem::path& path, model::CardShare cards = {});
// The same for a deck held in memory: `text` read as if it were the file at `path`, which names it
// in messages and places the files it includes.
model::Model read_deck_text(std::string text, const std::filesystem::path& path, model::CardShare cards = {});

// Cross-reference checks on a model as read: unique IDs; every part's section and material exist;
// element nodes, set members, curve IDs used by loads and BCs exist. Throws InputError.
void validate(const model::Model& model);

}  // namespace spall::io::keyword
