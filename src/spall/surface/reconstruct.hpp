#pragma once
// Surface of an SPH body: the colour field
//   c(x) = sum_b V_b W(x - x_b, 2 h_b)          (seed 000 eq. 10, evaluated off the particles)
// on a sparse grid (OpenVDB), meshed where c = iso (OpenVDB's volumeToMesh). Inside the body c is
// about one, outside zero; iso 1/2 puts the surface half a particle spacing beyond the outer layer,
// where the material ends. docs/THEORY.md §8 has the details.
#include <span>

#include "spall/core/types.hpp"
#include "spall/surface/triangle_mesh.hpp"

namespace spall::surface {

struct SurfaceParticles {
  std::span<const Vec3> x;
  std::span<const Real> volume;            // V_b = m_b / rho_b
  std::span<const Real> smoothing_length;  // h_b; the cubic-spline support is 2 h_b
};

struct SurfaceSettings {
  Real iso = 0.5;  // c on the surface
  Real cell = 0;   // grid spacing; 0: default_cell(smoothing_length)
};

// Half the median smoothing length: a few grid points across a particle, and set by the typical
// particle rather than by one much smaller than the rest.
Real default_cell(std::span<const Real> smoothing_length);

// The mesh of c = iso, counter-clockwise seen from outside. Throws std::invalid_argument when the
// spans differ in size, a volume or smoothing length is not positive, iso or cell is not positive;
// InputError when the grid would take more memory than a workstation has (a cell far too small).
TriangleMesh reconstruct_surface(const SurfaceParticles& particles, const SurfaceSettings& settings);

}  // namespace spall::surface
