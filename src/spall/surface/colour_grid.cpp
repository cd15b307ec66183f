#include "spall/surface/colour_grid.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include <fmt/format.h>

#include "spall/core/error.hpp"
#include "spall/core/parallel.hpp"
#include "spall/kernels/cubic_spline.hpp"
#include "spall/surface/particle_bins.hpp"

namespace spall::surface {

namespace {

using Kernel = kernels::CubicSpline<3>;  // seed 000 eq. 3; support 2h as in LS-DYNA
using Leaf = openvdb::FloatTree::LeafNodeType;
constexpr int leaf_dim = static_cast<int>(Leaf::DIM);  // voxels along a leaf's edge
constexpr int leaf_voxels = static_cast<int>(Leaf::SIZE);

// A grid of this many leaves (512 voxels, 2 KiB each) would take 8 GiB: a cell far too small for
// the body, which a user should hear about instead of watching the machine swap.
constexpr std::size_t max_leaves = std::size_t(1) << 22;

// Voxel index of the first / last voxel at or after / before a coordinate (relative to the origin).
std::int32_t voxel_at_or_after(Real coordinate, Real cell) {
  return static_cast<std::int32_t>(std::ceil(coordinate / cell));
}
std::int32_t voxel_at_or_before(Real coordinate, Real cell) {
  return static_cast<std::int32_t>(std::floor(coordinate / cell));
}
std::int32_t leaf_origin_of(std::int32_t voxel) {
  return static_cast<std::int32_t>(std::floor(Real(voxel) / leaf_dim)) * leaf_dim;
}

}  // namespace

openvdb::FloatGrid::Ptr colour_level_grid(const SurfaceParticles& particles, Real cell, Real iso,
                                          const Vec3& origin) {
  const std::size_t n = particles.x.size();
  std::vector<Vec3> x(n);
  for (std::size_t b = 0; b < n; ++b) x[b] = particles.x[b] - origin;
  const auto& h = particles.smoothing_length;
  const Real largest_support = 2 * *std::max_element(h.begin(), h.end());
  const ParticleBins bins(x, largest_support);
  // Voxel indices are 32-bit: the body with its supports must span fewer than 2^30 cells.
  Vec3 extent = Vec3::Zero();
  for (const Vec3& p : x) extent = extent.cwiseMax(p);
  if ((extent.maxCoeff() + 2 * largest_support) / cell > double(1 << 30))
    throw InputError(fmt::format("surface grid of cell {:g} across a body {:g} wide: more than 2^30 cells "
                                 "along an axis; use a larger cell",
                                 cell, extent.maxCoeff()));

  const auto too_large = [&](double leaves) {
    return InputError(fmt::format("surface grid of cell {:g} needs at least {:.3g} blocks of {} voxels "
                                  "({:.1f} GiB); use a larger cell",
                                  cell, leaves, leaf_voxels, leaves * sizeof(Leaf) / (1 << 30)));
  };
  // The leaves any particle's support reaches, from each bin's box of supports. A bin's box is
  // counted before it is listed, so that a cell far too small fails at once.
  std::vector<openvdb::Coord> leaf_origins;
  for (Index bin = 0; bin < bins.bin_count(); ++bin) {
    Vec3 lo = Vec3::Constant(std::numeric_limits<Real>::max()), hi = -lo;
    for (Index b : bins.bin(bin)) {
      lo = lo.cwiseMin(x[b] - Vec3::Constant(2 * h[b]));
      hi = hi.cwiseMax(x[b] + Vec3::Constant(2 * h[b]));
    }
    double box_leaves = 1;
    for (int d = 0; d < 3; ++d) box_leaves *= (hi[d] - lo[d]) / (cell * leaf_dim);
    if (box_leaves > max_leaves) throw too_large(box_leaves);
    std::array<std::int32_t, 3> first, last;
    for (int d = 0; d < 3; ++d) {
      first[d] = leaf_origin_of(voxel_at_or_after(lo[d], cell));
      last[d] = leaf_origin_of(voxel_at_or_before(hi[d], cell));
    }
    for (std::int32_t i = first[0]; i <= last[0]; i += leaf_dim)
      for (std::int32_t j = first[1]; j <= last[1]; j += leaf_dim)
        for (std::int32_t k = first[2]; k <= last[2]; k += leaf_dim) leaf_origins.emplace_back(i, j, k);
    if (leaf_origins.size() > 2 * max_leaves) {  // merge the repeats before memory runs out
      std::sort(leaf_origins.begin(), leaf_origins.end());
      leaf_origins.erase(std::unique(leaf_origins.begin(), leaf_origins.end()), leaf_origins.end());
      if (leaf_origins.size() > max_leaves) throw too_large(double(leaf_origins.size()));
    }
  }
  std::sort(leaf_origins.begin(), leaf_origins.end());
  leaf_origins.erase(std::unique(leaf_origins.begin(), leaf_origins.end()), leaf_origins.end());
  if (leaf_origins.size() > max_leaves) throw too_large(double(leaf_origins.size()));

  auto grid = openvdb::FloatGrid::create(static_cast<float>(iso));
  grid->setTransform(openvdb::math::Transform::createLinearTransform(cell));
  // The tree's structure is built here, one thread; the values below, one leaf per thread.
  std::vector<Leaf*> leaves;
  leaves.reserve(leaf_origins.size());
  for (const auto& o : leaf_origins) leaves.push_back(grid->tree().touchLeaf(o));

  const Index leaf_count = static_cast<Index>(leaves.size());
  parallel::for_each(leaf_count, [&](Index l) {
    Leaf& leaf = *leaves[l];
    const openvdb::Coord o = leaf.origin();
    std::array<Real, leaf_voxels> colour{};
    const Vec3 lo = Vec3(o.x(), o.y(), o.z()) * cell - Vec3::Constant(largest_support);
    const Vec3 hi = Vec3(o.x() + leaf_dim - 1, o.y() + leaf_dim - 1, o.z() + leaf_dim - 1) * cell +
                    Vec3::Constant(largest_support);
    // Every voxel sums its particles in the bins' fixed order: the same sum on any thread count.
    bins.for_each_in_box(lo, hi, [&](Index b) {
      const Real support = 2 * h[b];
      std::array<std::int32_t, 3> first, last;
      for (int d = 0; d < 3; ++d) {
        first[d] = std::max(o[d], voxel_at_or_after(x[b][d] - support, cell));
        last[d] = std::min(o[d] + leaf_dim - 1, voxel_at_or_before(x[b][d] + support, cell));
        if (first[d] > last[d]) return;
      }
      const Real volume = particles.volume[b];
      for (std::int32_t i = first[0]; i <= last[0]; ++i) {
        for (std::int32_t j = first[1]; j <= last[1]; ++j) {
          for (std::int32_t k = first[2]; k <= last[2]; ++k) {
            const Real r = (Vec3(i, j, k) * cell - x[b]).norm();
            if (r >= support) continue;
            colour[Leaf::coordToOffset(openvdb::Coord(i, j, k))] += volume * Kernel::value(r, support);
          }
        }
      }
    });
    for (int offset = 0; offset < leaf_voxels; ++offset)
      leaf.setValueOn(offset, static_cast<float>(iso - colour[offset]));
  }, {.chunk = 8});
  return grid;
}

}  // namespace spall::surface
