#pragma once
// Neighbour search: a cell-linked list (cell_list.hpp) builds Verlet lists with a skin; particles
// can be put in cell order for memory locality. OpenMP inside; the result never depends on the
// thread count.
#include <span>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::neighbors {

// Compressed rows: the neighbours of particle i are neighbors[offsets[i] .. offsets[i+1]).
// Full lists (j in i's row and i in j's row), self excluded, each row sorted ascending.
struct NeighborList {
  std::vector<Index> offsets;
  std::vector<Index> neighbors;
  Index count(Index i) const { return offsets[i + 1] - offsets[i]; }
};

class VerletList {
 public:
  // Lists every pair closer than cutoff + skin (cutoff > 0, skin >= 0). The list stays valid
  // (contains every pair closer than cutoff) until a particle has moved more than skin / 2 from
  // where it was at the build. Throws InstabilityError when a position is not finite.
  void build(std::span<const Vec3> x, Real cutoff, Real skin);
  // True when some particle moved more than skin / 2 since the build (or has a non-finite
  // position, or the particle count changed, or there was no build).
  bool needs_rebuild(std::span<const Vec3> x) const;
  const NeighborList& list() const { return list_; }
  Real cutoff() const { return cutoff_; }
  Real skin() const { return skin_; }
  // Bytes held besides the list itself: the positions saved at the build.
  std::size_t reference_positions_bytes() const { return x_at_build_.capacity() * sizeof(Vec3); }

 private:
  NeighborList list_;
  std::vector<Vec3> x_at_build_;
  Real cutoff_ = 0;
  Real skin_ = 0;
};

// A permutation that puts particles in cell order (cells of `cell_size`, row-major over the cell
// grid of the bounding box, ties in input order): new index k holds the particle formerly at
// order[k].
std::vector<Index> spatial_order(std::span<const Vec3> x, Real cell_size);

}  // namespace spall::neighbors
