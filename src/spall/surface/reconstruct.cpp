#include "spall/surface/reconstruct.hpp"

#include <algorithm>
#include <stdexcept>
#include <vector>

#include <openvdb/tools/VolumeToMesh.h>

#include "spall/surface/colour_grid.hpp"

namespace spall::surface {

namespace {

void check(const SurfaceParticles& p, const SurfaceSettings& settings) {
  const std::size_t n = p.x.size();
  if (n == 0) throw std::invalid_argument("surface reconstruction: no particles");
  if (p.volume.size() != n || p.smoothing_length.size() != n)
    throw std::invalid_argument("surface reconstruction: positions, volumes and smoothing lengths differ in count");
  for (std::size_t b = 0; b < n; ++b) {
    if (!(p.volume[b] > 0) || !(p.smoothing_length[b] > 0) || !p.x[b].allFinite())
      throw std::invalid_argument("surface reconstruction: a particle with a volume or smoothing length "
                                  "not positive, or a position not finite");
  }
  if (!(settings.iso > 0)) throw std::invalid_argument("surface reconstruction: iso must be positive");
  if (!(settings.cell >= 0)) throw std::invalid_argument("surface reconstruction: cell must be positive");
}

// Each quad in two triangles, split along its shorter diagonal (the better-shaped pair).
void add_quad(const openvdb::Vec4I& q, const std::vector<Vec3>& vertices,
              std::vector<std::array<Index, 3>>& triangles) {
  const auto v = [&](int k) { return static_cast<Index>(q[k]); };
  if ((vertices[v(0)] - vertices[v(2)]).squaredNorm() <= (vertices[v(1)] - vertices[v(3)]).squaredNorm()) {
    triangles.push_back({v(0), v(1), v(2)});
    triangles.push_back({v(0), v(2), v(3)});
  } else {
    triangles.push_back({v(0), v(1), v(3)});
    triangles.push_back({v(1), v(2), v(3)});
  }
}

}  // namespace

Real default_cell(std::span<const Real> smoothing_length) {
  std::vector<Real> h(smoothing_length.begin(), smoothing_length.end());
  if (h.empty()) throw std::invalid_argument("default_cell: no particles");
  const auto middle = h.begin() + h.size() / 2;
  std::nth_element(h.begin(), middle, h.end());
  return *middle / 2;
}

TriangleMesh reconstruct_surface(const SurfaceParticles& particles, const SurfaceSettings& settings) {
  check(particles, settings);
  const Real cell = settings.cell > 0 ? settings.cell : default_cell(particles.smoothing_length);
  // The grid and the mesher work in single precision: relative to the body's corner, a vertex keeps
  // seven digits of the body's size rather than of its distance from the deck's origin.
  Vec3 origin = particles.x.front();
  for (const Vec3& p : particles.x) origin = origin.cwiseMin(p);

  const auto grid = colour_level_grid(particles, cell, settings.iso, origin);
  std::vector<openvdb::Vec3s> points;
  std::vector<openvdb::Vec4I> quads;
  // Adaptivity 0: a uniform mesh, one vertex per voxel that the surface crosses.
  openvdb::tools::volumeToMesh(*grid, points, quads, 0.0);

  TriangleMesh mesh;
  mesh.vertices.reserve(points.size());
  for (const auto& p : points) mesh.vertices.push_back(origin + Vec3(p.x(), p.y(), p.z()));
  mesh.triangles.reserve(2 * quads.size());
  for (const auto& q : quads) add_quad(q, mesh.vertices, mesh.triangles);
  return mesh;
}

}  // namespace spall::surface
