// Surface reconstruction (`spall surface`, src/spall/surface) against the geometry the particles
// fill: a lattice sphere and a lattice cube of SPH particles must give closed meshes (every edge in
// two triangles, once each way; Euler characteristic 2) whose area and enclosed volume match the
// body's. References are the exact sphere (area 4 pi r^2, volume 4/3 pi r^3) and cube (6 L^2, L^3)
// whose volume the particles' cells fill; tolerances are in each test.
#include <gtest/gtest.h>
#include <omp.h>
#include <tbb/global_control.h>

#include <cmath>
#include <numbers>

#include "spall/core/error.hpp"
#include "spall/surface/reconstruct.hpp"
#include "spall/surface/triangle_mesh.hpp"

using namespace spall;

namespace {

constexpr Real pi = std::numbers::pi_v<Real>;

struct Lattice {
  std::vector<Vec3> x;
  std::vector<Real> volume, h;
  surface::SurfaceParticles particles() const { return {x, volume, h}; }
};

// Cubic lattice of spacing dx, smoothing length 1.2 dx (CSLH 1.2, as the examples use), each
// particle the volume dx^3 of its cell; a point (i, j, k) dx + offset is kept when `inside` says so.
template <typename Inside>
Lattice lattice(Real dx, int half_width, const Vec3& offset, Inside inside) {
  Lattice l;
  for (int i = -half_width; i <= half_width; ++i)
    for (int j = -half_width; j <= half_width; ++j)
      for (int k = -half_width; k <= half_width; ++k) {
        const Vec3 p = dx * Vec3(i, j, k);
        if (!inside(p)) continue;
        l.x.push_back(p + offset);
        l.volume.push_back(dx * dx * dx);
        l.h.push_back(1.2 * dx);
      }
  return l;
}

Lattice sphere(Real r, Real dx, const Vec3& centre = Vec3::Zero()) {
  return lattice(dx, static_cast<int>(std::ceil(r / dx)) + 1, centre,
                 [&](const Vec3& p) { return p.norm() < r; });
}

}  // namespace

TEST(SurfaceReconstruction, LatticeSphereIsClosedWithTheSphereAreaAndVolume) {
  // r = 10 dx: 4139 particles, whose cells fill 1.2 % less than the ball (4/3 pi r^3 = 4189 dx^3).
  // The iso-surface c = 1/2 of a curved body sits slightly inside where the material ends (the
  // kernel sees more empty space outside a convex surface than outside a flat one), by O(h^2/r).
  // Measured at CSLH 1.2: area -0.9 %, volume -2.9 % (docs/THEORY.md §8); the bound is 5 %.
  const Real dx = 1e-3, r = 10 * dx;
  const Lattice body = sphere(r, dx);
  const surface::TriangleMesh mesh = surface::reconstruct_surface(body.particles(), {});
  const auto topology = surface::edge_topology(mesh);
  EXPECT_TRUE(topology.closed()) << topology.boundary_edges << " boundary, " << topology.non_manifold_edges
                                 << " non-manifold, " << topology.misoriented_edges << " misoriented edges";
  EXPECT_EQ(topology.euler_characteristic, 2);

  const Real area = surface::area(mesh), volume = surface::enclosed_volume(mesh);
  const Real area_error = area / (4 * pi * r * r) - 1, volume_error = volume / (4 * pi * r * r * r / 3) - 1;
  std::printf("sphere r = 10 dx, %zu particles, %zu triangles: area error %+.4f, volume error %+.4f\n",
              body.x.size(), mesh.triangles.size(), area_error, volume_error);
  EXPECT_LT(std::abs(area_error), 0.05);
  EXPECT_LT(std::abs(volume_error), 0.05);
}

TEST(SurfaceReconstruction, LatticeCubeSurfaceLiesHalfASpacingBeyondTheOuterLayer) {
  // n^3 particles at (i + 1/2) dx fill the cube [0, n dx]^3; c = 1/2 on a flat face is where the
  // material ends (half the kernel inside), so the faces sit at 0 and n dx: within 0.05 dx. The
  // edges and corners round off: at an edge only a quarter of the support is inside. A cube
  // rounded with radius rho loses 12 (2 - pi/2) rho L of its 6 L^2 of area and about
  // 12 (1 - pi/4) rho^2 L of its volume; the measured area (-7.6 %) means rho = 1.39 dx = 1.16 h,
  // which predicts -1.9 % of volume (measured -2.2 %). Tolerances: area 10 %, volume 3 %.
  const Real dx = 0.5;
  const int n = 16;
  const Real L = n * dx;
  const Lattice body = lattice(dx, n, Vec3::Constant(dx / 2), [&](const Vec3& p) {
    return p.minCoeff() >= 0 && p.maxCoeff() < L - dx / 2;
  });
  ASSERT_EQ(body.x.size(), std::size_t(n * n * n));
  const surface::TriangleMesh mesh = surface::reconstruct_surface(body.particles(), {});
  const auto topology = surface::edge_topology(mesh);
  EXPECT_TRUE(topology.closed());
  EXPECT_EQ(topology.euler_characteristic, 2);

  // The face centres: the vertex nearest the middle of the face x = L.
  Real face = 0, best = 1e30;
  for (const Vec3& v : mesh.vertices) {
    const Real off_centre = std::hypot(v.y() - L / 2, v.z() - L / 2);
    if (v.x() > L / 2 && off_centre < best) best = off_centre, face = v.x();
  }
  const Real area_error = surface::area(mesh) / (6 * L * L) - 1;
  const Real volume_error = surface::enclosed_volume(mesh) / (L * L * L) - 1;
  std::printf("cube n = %d: face at %.4f dx beyond the outer layer (0.5 expected), area error %+.4f, "
              "volume error %+.4f\n",
              n, (face - (L - dx / 2)) / dx, area_error, volume_error);
  EXPECT_NEAR(face, L, 0.05 * dx);
  EXPECT_LT(std::abs(area_error), 0.10);
  EXPECT_LT(std::abs(volume_error), 0.03);
}

TEST(SurfaceReconstruction, MeshDoesNotDependOnThreadsOrOnWhereTheBodyIs) {
  const Real dx = 1e-3, r = 6 * dx;
  const Lattice here = sphere(r, dx);
  // Far from the origin: 1 km away, a single-precision coordinate would keep only 0.1 mm.
  const Vec3 far(1000.0, -2000.0, 500.0);
  const Lattice there = sphere(r, dx, far);

  omp_set_num_threads(1);
  surface::TriangleMesh one;
  {
    const tbb::global_control serial(tbb::global_control::max_allowed_parallelism, 1);
    one = surface::reconstruct_surface(here.particles(), {});
  }
  omp_set_num_threads(2);
  const surface::TriangleMesh two = surface::reconstruct_surface(here.particles(), {});
  ASSERT_EQ(one.vertices.size(), two.vertices.size());
  ASSERT_EQ(one.triangles, two.triangles);
  for (std::size_t v = 0; v < one.vertices.size(); ++v) ASSERT_EQ(one.vertices[v], two.vertices[v]);

  const surface::TriangleMesh moved = surface::reconstruct_surface(there.particles(), {});
  EXPECT_TRUE(surface::edge_topology(moved).closed());
  EXPECT_NEAR(surface::area(moved), surface::area(one), 1e-6 * surface::area(one));
}

TEST(SurfaceReconstruction, IsoAndCellChangeTheSurfaceAsTheyShould) {
  // A higher iso pulls the surface inwards (c falls off monotonically across it); a finer cell
  // changes the area by little (the field, not the grid, sets the surface).
  const Real dx = 1e-3, r = 8 * dx;
  const Lattice body = sphere(r, dx);
  const Real base = surface::area(surface::reconstruct_surface(body.particles(), {}));
  const Real inner = surface::area(surface::reconstruct_surface(body.particles(), {.iso = 0.8}));
  const Real fine = surface::area(surface::reconstruct_surface(body.particles(), {.cell = 0.3 * dx}));
  EXPECT_LT(inner, 0.95 * base);
  EXPECT_NEAR(fine, base, 0.01 * base);
}

TEST(SurfaceReconstruction, RejectsWhatItCannotMesh) {
  const Lattice body = sphere(3e-3, 1e-3);
  auto bad = body;
  bad.volume[3] = 0;
  EXPECT_THROW(surface::reconstruct_surface(bad.particles(), {}), std::invalid_argument);
  EXPECT_THROW(surface::reconstruct_surface(body.particles(), {.iso = 0}), std::invalid_argument);
  // A cell a thousand times smaller than the particles: a grid far beyond memory, refused at once.
  EXPECT_THROW(surface::reconstruct_surface(body.particles(), {.cell = 1e-6}), InputError);
}
