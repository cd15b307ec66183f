// The measures that check a reconstructed surface (area, enclosed volume, edge topology) on meshes
// whose answers are known by hand, and the fields carried from particles onto its vertices.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/surface/triangle_mesh.hpp"
#include "spall/surface/vertex_fields.hpp"

using namespace spall;
using surface::TriangleMesh;

namespace {
// The unit right tetrahedron, outward counter-clockwise: volume 1/6, area 3/2 + sqrt(3)/2.
TriangleMesh tetrahedron() {
  return {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}}, {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
}
}  // namespace

TEST(SurfaceMesh, TetrahedronMeasures) {
  TriangleMesh t = tetrahedron();
  EXPECT_NEAR(surface::area(t), 1.5 + std::sqrt(3.0) / 2, 1e-15);
  EXPECT_NEAR(surface::enclosed_volume(t), 1.0 / 6, 1e-15);
  // The divergence theorem does not care where the origin is.
  for (Vec3& v : t.vertices) v += Vec3(10, -20, 30);
  EXPECT_NEAR(surface::enclosed_volume(t), 1.0 / 6, 1e-12);
  const auto topology = surface::edge_topology(t);
  EXPECT_TRUE(topology.closed());
  EXPECT_EQ(topology.edges, 6);
  EXPECT_EQ(topology.euler_characteristic, 2);
}

TEST(SurfaceMesh, TopologyFindsHolesFoldsAndFlippedTriangles) {
  TriangleMesh open = tetrahedron();
  open.triangles.pop_back();
  auto topology = surface::edge_topology(open);
  EXPECT_EQ(topology.boundary_edges, 3);
  EXPECT_FALSE(topology.closed());
  EXPECT_EQ(topology.euler_characteristic, 1);  // a disc

  TriangleMesh flipped = tetrahedron();
  std::swap(flipped.triangles[3][0], flipped.triangles[3][1]);
  topology = surface::edge_topology(flipped);
  EXPECT_EQ(topology.misoriented_edges, 3);
  EXPECT_FALSE(topology.closed());

  TriangleMesh fin = tetrahedron();  // a third triangle on edge 1-2
  fin.vertices.push_back({1, 1, 1});
  fin.triangles.push_back({1, 2, 4});
  topology = surface::edge_topology(fin);
  EXPECT_EQ(topology.non_manifold_edges, 1);
  EXPECT_EQ(topology.boundary_edges, 2);
}

TEST(SurfaceVertexFields, ConstantsExactlyLabelsFromTheNearestParticle) {
  // Two rows of particles: part 1 at x < 0, part 2 at x > 0; a Shepard interpolant reproduces a
  // constant (the weights sum to one after normalising), whatever the spacing.
  std::vector<Vec3> x;
  std::vector<Real> volume, h;
  std::vector<double> constant, linear;
  std::vector<std::int64_t> part;
  for (int i = -5; i <= 5; ++i) {
    if (i == 0) continue;
    for (int j = -2; j <= 2; ++j) {
      x.emplace_back(i * 0.1, j * 0.1, 0);
      volume.push_back(1e-3);
      h.push_back(0.12);
      constant.insert(constant.end(), {2.5, -1.0});
      linear.push_back(3 * x.back().x());
      part.push_back(i < 0 ? 1 : 2);
    }
  }
  const surface::SurfaceParticles particles{x, volume, h};
  const std::vector<Vec3> vertices = {{-0.32, 0.01, 0.05}, {0.27, -0.04, 0.02}, {0.0, 0.0, 0.0}};
  const auto fields = surface::vertex_fields(
      particles, {{"c", 2, constant}, {"linear", 1, linear}, {"part_id", 1, part}}, vertices);
  ASSERT_EQ(fields.size(), 3u);
  const auto& c = std::get<std::vector<double>>(fields[0].values);
  for (double value : {c[0], c[2], c[4]}) EXPECT_NEAR(value, 2.5, 1e-14);
  for (double value : {c[1], c[3], c[5]}) EXPECT_NEAR(value, -1.0, 1e-14);
  // Symmetric particles around the middle vertex: the linear field interpolates to 0 there.
  EXPECT_NEAR(std::get<std::vector<double>>(fields[1].values)[2], 0.0, 1e-14);
  const auto& p = std::get<std::vector<std::int64_t>>(fields[2].values);
  EXPECT_EQ(p[0], 1);
  EXPECT_EQ(p[1], 2);

  EXPECT_THROW(surface::vertex_fields(particles, {{"c", 1, constant}}, vertices), std::invalid_argument);
  // A vertex out of every support.
  EXPECT_THROW(surface::vertex_fields(particles, {{"linear", 1, linear}}, {Vec3(5, 5, 5)}),
               std::invalid_argument);
}
