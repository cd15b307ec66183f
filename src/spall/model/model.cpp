#include "spall/model/model.hpp"

namespace spall::model {

const Part* Model::find_part(Id id) const {
  for (const auto& part : parts)
    if (part.id == id) return &part;
  return nullptr;
}

}  // namespace spall::model
