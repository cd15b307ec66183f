#include "spall/io/keyword/deck_lines.hpp"

#include <cctype>
#include <fstream>
#include <iterator>
#include <utility>

namespace spall::io::keyword {

bool DeckFile::load(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return false;
  text_.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  if (in.bad()) return false;
  path_ = path;
  name_ = path.lexically_normal().string();
  return true;
}

void DeckFile::assign(std::string text, const std::filesystem::path& path) {
  text_ = std::move(text);
  path_ = path;
  name_ = path.lexically_normal().string();
}

void DeckFile::start_block(std::string_view keyword_line, KeywordBlock& block) {
  // The name ends at the first blank or comma: LS-PrePost writes `*ELEMENT_SOLID (ten nodes
  // format)`, and `*KEYWORD 100000000 LONG=Y` carries options after the name.
  std::size_t end = 1;
  while (end < keyword_line.size() && keyword_line[end] != ' ' && keyword_line[end] != '\t' &&
         keyword_line[end] != ',')
    ++end;
  std::string_view name = keyword_line.substr(1, end - 1);
  block.width = WidthOverride::none;
  if (!name.empty() && name.back() == '+') {
    block.width = WidthOverride::long_fields;
    name.remove_suffix(1);
  } else if (!name.empty() && name.back() == '-') {
    block.width = WidthOverride::standard_fields;
    name.remove_suffix(1);
  }
  block.name.assign(name);
  for (char& c : block.name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  block.trailing = keyword_line.substr(end);
}

}  // namespace spall::io::keyword
