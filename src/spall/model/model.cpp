#include "spall/model/model.hpp"

namespace spall::model {

const Part* Model::find_part(Id id) const {
  for (const auto& part : parts)
    if (part.id == id) return &part;
  return nullptr;
}

const MatRigid* Model::rigid_material(const Part& part) const {
  auto it = materials.find(part.mid);
  return it == materials.end() ? nullptr : std::get_if<MatRigid>(&it->second.params);
}

}  // namespace spall::model
