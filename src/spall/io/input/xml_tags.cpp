#include "spall/io/input/xml_tags.hpp"

namespace spall::io::input {

namespace {
// The five entities of XML; the writers produce the first four (xml_escaped in io/output).
std::string unescaped(std::string_view text) {
  static constexpr std::pair<std::string_view, char> entities[] = {
      {"&amp;", '&'}, {"&lt;", '<'}, {"&gt;", '>'}, {"&quot;", '"'}, {"&apos;", '\''}};
  std::string out;
  for (std::size_t i = 0; i < text.size();) {
    bool replaced = false;
    if (text[i] == '&') {
      for (const auto& [entity, c] : entities) {
        if (text.substr(i, entity.size()) == entity) {
          out += c;
          i += entity.size();
          replaced = true;
          break;
        }
      }
    }
    if (!replaced) out += text[i++];
  }
  return out;
}

bool is_space(char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; }
}  // namespace

std::vector<XmlTag> xml_tags(std::string_view xml) {
  std::vector<XmlTag> tags;
  for (std::size_t open = xml.find('<'); open != std::string_view::npos; open = xml.find('<', open)) {
    const std::size_t close = xml.find('>', open);
    if (close == std::string_view::npos) break;
    const std::string_view text = xml.substr(open + 1, close - open - 1);
    std::size_t end = 0;
    while (end < text.size() && !is_space(text[end]) && text[end] != '/') ++end;
    // A closing tag keeps its slash: "/PointData".
    if (end == 0 && !text.empty() && text[0] == '/') {
      end = 1;
      while (end < text.size() && !is_space(text[end])) ++end;
    }
    tags.push_back({text.substr(0, end), text});
    open = close + 1;
  }
  return tags;
}

std::optional<std::string> xml_attribute(const XmlTag& tag, std::string_view key) {
  // The attribute starts after a blank, so that "Name" does not match "ComponentName0".
  for (std::size_t at = tag.text.find(key); at != std::string_view::npos; at = tag.text.find(key, at + 1)) {
    if (at == 0 || !is_space(tag.text[at - 1])) continue;
    std::size_t i = at + key.size();
    while (i < tag.text.size() && is_space(tag.text[i])) ++i;
    if (i >= tag.text.size() || tag.text[i] != '=') continue;
    ++i;
    while (i < tag.text.size() && is_space(tag.text[i])) ++i;
    if (i >= tag.text.size() || tag.text[i] != '"') continue;
    const std::size_t end = tag.text.find('"', i + 1);
    if (end == std::string_view::npos) return std::nullopt;
    return unescaped(tag.text.substr(i + 1, end - i - 1));
  }
  return std::nullopt;
}

}  // namespace spall::io::input
