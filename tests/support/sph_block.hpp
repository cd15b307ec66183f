#pragma once
// Builds SPH models in code for verification tests: a box of particles on a cubic lattice, one
// part with *SECTION_SPH and *MAT_ELASTIC, and the controls a deck would give.
#include "spall/model/model.hpp"

namespace spall::test_support {

struct ElasticBlock {
  Vec3 size = Vec3(1, 0.1, 0.1);
  Real spacing = 0.02;
  Real density = 7850, young = 200e9, poisson = 0.3;
  Real cslh = 1.2;
  Real end_time = 1e-4;
};

inline model::Model elastic_block_model(const ElasticBlock& b) {
  model::Model m;
  m.parts.push_back({1, "block", 1, 1, 0, 0, 0, {}, {}});
  model::SectionSph section;
  section.id = 1;
  section.cslh = b.cslh;
  section.hmin = section.hmax = 1.0;
  m.sections[1] = section;
  model::Material mat;
  mat.id = 1;
  mat.keyword = "*MAT_ELASTIC";
  mat.params = model::MatElastic{b.density, b.young, b.poisson, 0, 0};
  m.materials[1] = mat;
  const int nx = static_cast<int>(std::lround(b.size.x() / b.spacing));
  const int ny = static_cast<int>(std::lround(b.size.y() / b.spacing));
  const int nz = static_cast<int>(std::lround(b.size.z() / b.spacing));
  const Real volume = b.spacing * b.spacing * b.spacing;
  Id id = 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i, ++id) {
        m.nodes.push_back({id, b.spacing * Vec3(i + 0.5, j + 0.5, k + 0.5), 0, 0, {}});
        m.sph_elements.push_back({id, 1, -volume, {}});
      }
  model::ControlTermination term;
  term.endtim = b.end_time;
  m.termination = term;
  return m;
}

}  // namespace spall::test_support
