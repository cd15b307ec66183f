#include "spall/io/keyword/unsupported.hpp"

#include <algorithm>
#include <cctype>

#include "spall/core/error.hpp"

namespace spall::io::keyword {

namespace {

std::string normalized(std::string_view name) {
  if (!name.empty() && name.front() == '*') name.remove_prefix(1);
  std::string out(name);
  for (char& c : out) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return out;
}

bool starts_with_family(std::string_view keyword, std::string_view family) {
  return keyword == family || (keyword.size() > family.size() && keyword.substr(0, family.size()) == family &&
                               keyword[family.size()] == '_');
}

}  // namespace

bool defines_physics(std::string_view keyword) {
  // Families of keywords that define the problem itself. Unread *SECTION_, *MAT_, *EOS_, *SET_ and
  // *DEFINE_ cards are harmless until a part or a card uses them, and validate() refuses that use,
  // except the *DEFINE_ cards that make particles or couple bodies by themselves, and the *MAT_ADD_
  // cards, which change the material of their ID (expansion, damage, failure) rather than define one.
  static constexpr std::string_view physics[] = {
      "CONTACT",  "ELEMENT",       "PART",     "CONSTRAINED",       "BOUNDARY", "LOAD",
      "INITIAL",  "RIGIDWALL",     "DAMPING",  "AIRBAG",            "ALE",      "CONTROL_IMPLICIT",
      "CASE",     "INCLUDE_TRANSFORM", "DEFORMABLE_TO_RIGID", "TERMINATION", "INTERFACE", "RIGIDBODY",
      "DEFINE_SPH_MESH_SURFACE", "DEFINE_SPH_INJECTION", "DEFINE_SPH_TO_SPH_COUPLING",
      "DEFINE_ADAPTIVE_SOLID_TO_SPH", "DEFINE_ADAPTIVE_SOLID_TO_DES", "DEFINE_CONTACT_EXCLUSION", "MAT_ADD"};
  const std::string name = normalized(keyword);
  return std::any_of(std::begin(physics), std::end(physics),
                     [&](std::string_view family) { return starts_with_family(name, family); });
}

bool skip_matches(std::string_view name, std::string_view keyword) {
  return starts_with_family(normalized(keyword), normalized(name));
}

void refuse_unsupported_physics(const model::Model& model, const std::vector<std::string>& skip) {
  for (const auto& u : model.unsupported) {
    if (!defines_physics(u.keyword)) continue;
    if (std::any_of(skip.begin(), skip.end(), [&](const std::string& name) { return skip_matches(name, u.keyword); }))
      continue;
    throw InputError(u.where, u.keyword,
                     "not supported by Spall, and it defines physics: running without it would solve another "
                     "problem (`spall run --skip " + normalized(u.keyword) + "` runs without it, knowingly)");
  }
}

}  // namespace spall::io::keyword
