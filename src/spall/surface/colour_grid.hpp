#pragma once
// The colour field of the particles on an OpenVDB sparse grid (only blocks of voxels that some
// particle's kernel reaches are stored). Internal to src/spall/surface: the rest of Spall does not
// see OpenVDB.
#include <openvdb/openvdb.h>

#include "spall/surface/reconstruct.hpp"

namespace spall::surface {

// A grid of voxel size `cell` whose voxel (i, j, k) sits at origin + (i, j, k) cell and holds
// iso - c there: negative inside, positive outside, as a level set, so that the surface is its
// zero crossing. Voxels out of every particle's reach hold the background value iso (c = 0).
openvdb::FloatGrid::Ptr colour_level_grid(const SurfaceParticles& particles, Real cell, Real iso,
                                          const Vec3& origin);

}  // namespace spall::surface
