#pragma once
// Builds SPG models in code for tests and benchmarks: a box meshed with nx x ny x nz hexahedra
// (*ELEMENT_SOLID), one part with *SECTION_SOLID_SPG and *MAT_ELASTIC, and the controls a deck
// would give. Interior nodes can be jittered to make the particle set irregular. With `fem` set,
// the same mesh runs as solid finite elements (*SECTION_SOLID, and *HOURGLASS when given).
#include <cmath>
#include <optional>
#include <random>

#include "spall/model/model.hpp"

namespace spall::test_support {

// The block as finite elements: ELFORM and, for ELFORM 1, its *HOURGLASS card (HGID 1).
struct FiniteElements {
  int elform = 1;
  std::optional<model::Hourglass> hourglass;
};

struct SpgBlock {
  Vec3 size = Vec3(1, 0.1, 0.1);
  std::array<int, 3> elements = {20, 2, 2};
  Real density = 7850, young = 200e9, poisson = 0.3;
  model::SectionSolidSpg section;  // its defaults: DX 1.6, KERNEL 0, SMSTEP 15, ITB 1
  Real jitter = 0;                 // interior nodes moved by up to jitter x spacing per axis
  unsigned seed = 1;
  Real end_time = 1e-4;
  std::optional<FiniteElements> fem;
};

// The bar of the tests over ranks: 3 x 3 x 24 elements, 0.24 m along z, the node order's slowest
// axis, so that a rank's block of it is a stretch of the bar.
inline SpgBlock bar_along_z() {
  SpgBlock b;
  b.size = Vec3(0.03, 0.03, 0.24);
  b.elements = {3, 3, 24};
  return b;
}

// 2 x 2 x `layers` elements of 0.1 m with DX 1.0: on a regular mesh the support ends exactly at
// the neighbours, where the window is 0, so node 1's moment matrix is singular.
inline SpgBlock support_too_small(int layers) {
  SpgBlock b;
  b.elements = {2, 2, layers};
  b.size = Vec3(0.2, 0.2, layers / 10.0);
  b.section.dx = b.section.dy = b.section.dz = 1.0;
  return b;
}

inline Id spg_node_id(const SpgBlock& b, int i, int j, int k) {
  return 1 + i + (b.elements[0] + 1) * (j + (b.elements[1] + 1) * k);
}

inline model::Model spg_block_model(const SpgBlock& b) {
  model::Model m;
  m.parts.push_back({1, "block", 1, 1, 0, 0, 0, {}, {}});
  if (b.fem) {
    model::SectionSolid section;
    section.id = 1;
    section.elform = b.fem->elform;
    m.sections[1] = section;
    if (b.fem->hourglass) {
      m.hourglasses[1] = *b.fem->hourglass;
      m.hourglasses[1].id = 1;
      m.parts.back().hgid = 1;
    }
  } else {
    model::SectionSolidSpg section = b.section;
    section.id = 1;
    m.sections[1] = section;
  }
  model::Material mat;
  mat.id = 1;
  mat.keyword = "*MAT_ELASTIC";
  mat.params = model::MatElastic{b.density, b.young, b.poisson, 0, 0};
  m.materials[1] = mat;
  const auto [nx, ny, nz] = b.elements;
  const Vec3 h(b.size.x() / nx, b.size.y() / ny, b.size.z() / nz);
  std::mt19937 rng(b.seed);
  std::uniform_real_distribution<Real> jitter(-b.jitter, b.jitter);
  for (int k = 0; k <= nz; ++k)
    for (int j = 0; j <= ny; ++j)
      for (int i = 0; i <= nx; ++i) {
        Vec3 x = h.cwiseProduct(Vec3(i, j, k));
        const bool interior = i > 0 && i < nx && j > 0 && j < ny && k > 0 && k < nz;
        if (interior && b.jitter > 0) x += h.cwiseProduct(Vec3(jitter(rng), jitter(rng), jitter(rng)));
        m.nodes.push_back({spg_node_id(b, i, j, k), x, 0, 0, {}});
      }
  Id eid = 1;
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        model::ElementSolid e;
        e.eid = eid++;
        e.pid = 1;
        e.n = {spg_node_id(b, i, j, k),         spg_node_id(b, i + 1, j, k),
               spg_node_id(b, i + 1, j + 1, k), spg_node_id(b, i, j + 1, k),
               spg_node_id(b, i, j, k + 1),     spg_node_id(b, i + 1, j, k + 1),
               spg_node_id(b, i + 1, j + 1, k + 1), spg_node_id(b, i, j + 1, k + 1)};
        m.solid_elements.push_back(e);
      }
  model::ControlTermination term;
  term.endtim = b.end_time;
  m.termination = term;
  return m;
}

}  // namespace spall::test_support
