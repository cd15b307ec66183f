#pragma once
// What to do with the keywords Spall does not read (Model::unsupported): one that defines bodies,
// contacts, constraints, loads, initial or boundary conditions or the analysis type stops the
// check, since running without it would be another problem; an output or tuning keyword is a
// warning. A user may skip a physics keyword knowingly (`spall run --skip NAME`), and the run then
// says its physics is incomplete.
#include <string>
#include <string_view>
#include <vector>

#include "spall/model/model.hpp"

namespace spall::io::keyword {

// True for a keyword (as written, with or without its leading '*') that defines physics.
bool defines_physics(std::string_view keyword);

// True when `name` (with or without '*', any case) names `keyword` itself or a family of it: the
// keyword equals the name or starts with it followed by '_' (CONTACT skips every *CONTACT_...).
bool skip_matches(std::string_view name, std::string_view keyword);

// Throws InputError at the first unsupported physics keyword that no `skip` name matches.
void refuse_unsupported_physics(const model::Model& model, const std::vector<std::string>& skip);

}  // namespace spall::io::keyword
