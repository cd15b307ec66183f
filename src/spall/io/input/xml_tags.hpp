#pragma once
// The few pieces of XML the readers of Spall's own VTK files need: the tags of a header in order,
// and an attribute of a tag. Enough for the files src/spall/io/output writes (one tag per element,
// attributes in double quotes, no comments or CDATA in the header), not a general XML parser.
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace spall::io::input {

struct XmlTag {
  std::string_view name;  // "DataArray", "/PointData", "?xml", ...
  std::string_view text;  // the whole tag without its angle brackets
};

// Every tag of `xml`, in order.
std::vector<XmlTag> xml_tags(std::string_view xml);

// The value of attribute `key` of a tag, with the XML entities replaced; nullopt when absent.
std::optional<std::string> xml_attribute(const XmlTag& tag, std::string_view key);

}  // namespace spall::io::input
