#include "spall/surface/triangle_mesh.hpp"

#include <algorithm>
#include <cstdint>

namespace spall::surface {

Real area(const TriangleMesh& mesh) {
  Real sum = 0;
  for (const auto& t : mesh.triangles) {
    const Vec3& a = mesh.vertices[t[0]];
    sum += 0.5 * (mesh.vertices[t[1]] - a).cross(mesh.vertices[t[2]] - a).norm();
  }
  return sum;
}

Real enclosed_volume(const TriangleMesh& mesh) {
  Real sum = 0;
  for (const auto& t : mesh.triangles)
    sum += mesh.vertices[t[0]].dot(mesh.vertices[t[1]].cross(mesh.vertices[t[2]]));
  return sum / 6;
}

EdgeTopology edge_topology(const TriangleMesh& mesh) {
  // Each directed edge (from, to) as one sortable key; an edge's two uses in a closed,
  // consistently oriented mesh are (a, b) and (b, a).
  struct DirectedEdge {
    Index low, high;
    bool forward;  // from low to high
    auto operator<=>(const DirectedEdge&) const = default;
  };
  std::vector<DirectedEdge> uses;
  uses.reserve(3 * mesh.triangles.size());
  std::vector<char> used(mesh.vertices.size(), 0);
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      const Index from = t[k], to = t[(k + 1) % 3];
      uses.push_back({std::min(from, to), std::max(from, to), from < to});
      used[from] = 1;
    }
  }
  std::sort(uses.begin(), uses.end());

  EdgeTopology topology;
  for (std::size_t i = 0; i < uses.size();) {
    std::size_t j = i, forward = 0;
    while (j < uses.size() && uses[j].low == uses[i].low && uses[j].high == uses[i].high) forward += uses[j++].forward;
    const std::size_t count = j - i;
    ++topology.edges;
    if (count == 1) ++topology.boundary_edges;
    if (count > 2) ++topology.non_manifold_edges;
    if (count == 2 && forward != 1) ++topology.misoriented_edges;
    i = j;
  }
  const long long vertices = std::count(used.begin(), used.end(), 1);
  topology.euler_characteristic =
      vertices - topology.edges + static_cast<long long>(mesh.triangles.size());
  return topology;
}

}  // namespace spall::surface
