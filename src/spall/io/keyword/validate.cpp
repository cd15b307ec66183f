// validate(): cross-references between the cards of a model as read.
#include <algorithm>
#include <string>
#include <unordered_set>
#include <vector>

#include "spall/io/keyword/reader.hpp"

namespace spall::io::keyword {

void validate(const model::Model&) {}

}  // namespace spall::io::keyword
