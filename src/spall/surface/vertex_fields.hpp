#pragma once
// The particles' point fields carried onto the vertices of their reconstructed surface, so that
// ParaView colours the surface by pressure or plastic strain (seed 000 Fig. 3).
#include <span>
#include <vector>

#include "spall/core/types.hpp"
#include "spall/io/output/vtu.hpp"
#include "spall/surface/reconstruct.hpp"

namespace spall::surface {

// For every field (one value set per particle of `particles`):
//   Float64: the Shepard-normalised SPH interpolant A(x) = sum_b V_b A_b W_b / sum_b V_b W_b,
//            W_b = W(x - x_b, 2 h_b) (cubic spline), component by component;
//   Int64 (part_id, category, ...): the value of the nearest particle, since an average of labels
//            means nothing.
// Throws std::invalid_argument for a field that does not fit the particles, or a vertex that no
// particle's kernel reaches (none on a mesh of c = iso > 0, where the weights sum to iso).
std::vector<discretization::Field> vertex_fields(const SurfaceParticles& particles,
                                                  const std::vector<discretization::Field>& fields,
                                                  const std::vector<Vec3>& vertices);

}  // namespace spall::surface
