#pragma once
// A triangle mesh of a reconstructed surface and the measures that check it: area, enclosed volume
// and the edge topology of a closed surface.
#include <array>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::surface {

struct TriangleMesh {
  std::vector<Vec3> vertices;
  // Vertex indices, counter-clockwise seen from outside: the right-hand normal points out of the body.
  std::vector<std::array<Index, 3>> triangles;
};

Real area(const TriangleMesh& mesh);

// (1/6) sum over triangles of x0 . (x1 x x2) (divergence theorem): the volume enclosed by a closed,
// outward-oriented mesh, whatever the origin.
Real enclosed_volume(const TriangleMesh& mesh);

struct EdgeTopology {
  long long edges = 0;           // distinct edges
  long long boundary_edges = 0;  // used by one triangle: a hole
  long long non_manifold_edges = 0;  // used by three or more
  long long misoriented_edges = 0;   // used twice in the same direction: neighbours disagree on out
  // V - E + F over the vertices that triangles use; 2 per closed surface of genus 0.
  long long euler_characteristic = 0;

  // Every edge used by exactly two triangles, once in each direction.
  bool closed() const { return boundary_edges == 0 && non_manifold_edges == 0 && misoriented_edges == 0; }
};

EdgeTopology edge_topology(const TriangleMesh& mesh);

}  // namespace spall::surface
