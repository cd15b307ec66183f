// Colour-field categorization (seed 000 §4, eqs. 9-10), calibrated on bodies at rest: a cube must
// flag exactly its outer layer of particles as surface and the next layer as inner layer (faces,
// edges and corners alike); a lattice sphere must flag a shell of uniform thickness. The default
// thresholds (neighbour fraction 0.8, |n| h > 0.3) hold for CSLH 1.0-1.5 and every kernel; the
// calibration table of docs/THEORY.md comes from the printout of the first test.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "spall/core/log.hpp"
#include "spall/solver/problem.hpp"
#include "spall/sph/solid.hpp"
#include "support/sph_block.hpp"

using namespace spall;

namespace {

struct Categorized {
  std::vector<Vec3> x;  // particle positions
  std::vector<int> category;
  std::vector<Real> normal_h, count_fraction;
};

// Builds the model, evaluates one force pass at rest and returns each particle's category.
Categorized categorize(model::Model model, int kernel = 0) {
  for (auto& [id, section] : model.sections) std::get<model::SectionSph>(section).sphkern = kernel;
  model.sph_colour_fields.push_back(model::SphColourField{});
  solver::Problem problem = solver::build_problem(model);
  problem.formulations[0]->compute_forces(problem.nodes, 0);
  const auto& sph = dynamic_cast<const sph::SolidFormulation&>(*problem.formulations[0]);
  discretization::FieldSet field_set(problem.nodes.size());
  sph.write_fields(field_set, problem.nodes);
  const auto& fields = field_set.node_fields();
  auto field = [&](const std::string& name) -> const discretization::Field& {
    return *std::find_if(fields.begin(), fields.end(), [&](const auto& f) { return f.name == name; });
  };
  const auto& normal = std::get<std::vector<double>>(field("colour_normal").values);
  const auto& h = std::get<std::vector<double>>(field("smoothing_length").values);
  const auto& count = std::get<std::vector<std::int64_t>>(field("neighbour_count").values);
  Categorized c;
  for (Index a = 0; a < sph.particle_count(); ++a) {
    const Index i = sph.node_of(a);
    c.x.push_back(problem.nodes.x[i]);
    c.category.push_back(static_cast<int>(sph.categories()[a]));
    c.normal_h.push_back(Vec3(normal[3 * i], normal[3 * i + 1], normal[3 * i + 2]).norm() * h[i]);
    c.count_fraction.push_back(static_cast<Real>(count[i]));
  }
  return c;
}

// Lattice depth of a particle of an n x n x n cube of spacing dx: 0 on the outer layer.
int depth_in_cube(const Vec3& x, Real dx, int n) {
  int depth = n;
  for (int d = 0; d < 3; ++d) {
    const int i = static_cast<int>(std::floor(x[d] / dx));
    depth = std::min({depth, i, n - 1 - i});
  }
  return depth;
}

}  // namespace

TEST(ColourField, CubeFlagsItsOuterLayerAsSurfaceAndTheNextAsInnerLayer) {
  log::set_quiet(true);
  const int n = 10;
  const Real dx = 0.01;
  for (Real cslh : {1.0, 1.2, 1.5}) {
    for (int kernel : {0, 1, 4}) {
      test_support::ElasticBlock block;
      block.size = Vec3(n * dx, n * dx, n * dx);
      block.spacing = dx;
      block.cslh = cslh;
      const Categorized c = categorize(test_support::elastic_block_model(block), kernel);
      int wrong = 0;
      Real min_surface_nh = 1e30, max_inner_nh = 0;
      for (std::size_t a = 0; a < c.x.size(); ++a) {
        const int depth = depth_in_cube(c.x[a], dx, n);
        const int expected = depth == 0 ? 2 : depth == 1 ? 1 : 0;
        if (c.category[a] != expected) ++wrong;
        if (depth == 0) min_surface_nh = std::min(min_surface_nh, c.normal_h[a]);
        if (depth == 1) max_inner_nh = std::max(max_inner_nh, c.normal_h[a]);
      }
      std::printf("CSLH %.1f kernel %d: |n|h on the outer layer >= %.3f, on the next <= %.3f; %d wrong\n",
                  cslh, kernel, min_surface_nh, max_inner_nh, wrong);
      EXPECT_EQ(wrong, 0) << "CSLH " << cslh << " kernel " << kernel;
    }
  }
}

TEST(ColourField, SphereFlagsAShellOfUniformThickness) {
  log::set_quiet(true);
  const Real dx = 0.01, radius = 8 * dx;
  test_support::ElasticBlock block;
  block.size = Vec3(2 * radius, 2 * radius, 2 * radius);
  block.spacing = dx;
  model::Model model = test_support::elastic_block_model(block);
  // Keep the lattice points inside the sphere.
  const Vec3 centre(radius, radius, radius);
  std::vector<model::Node> nodes;
  std::vector<model::ElementSph> particles;
  for (std::size_t k = 0; k < model.nodes.size(); ++k)
    if ((model.nodes[k].x - centre).norm() < radius) {
      nodes.push_back(model.nodes[k]);
      particles.push_back(model.sph_elements[k]);
    }
  model.nodes = nodes;
  model.sph_elements = particles;
  const Categorized c = categorize(model);
  // The outermost particle centres lie within half a spacing of r = R - dx/2 on the lattice.
  Real surface_min = 1e30, surface_max = 0, inner_min = 1e30, inner_max = 0, interior_min_depth = 1e30;
  for (std::size_t a = 0; a < c.x.size(); ++a) {
    const Real depth = (radius - (c.x[a] - centre).norm()) / dx;  // in spacings below the sphere
    if (c.category[a] == 2) surface_min = std::min(surface_min, depth), surface_max = std::max(surface_max, depth);
    if (c.category[a] == 1) inner_min = std::min(inner_min, depth), inner_max = std::max(inner_max, depth);
    if (c.category[a] == 0) interior_min_depth = std::min(interior_min_depth, depth);
  }
  std::printf("sphere R = 8 dx: surface at depths %.2f-%.2f dx, inner layer %.2f-%.2f dx, interior from %.2f dx\n",
              surface_min, surface_max, inner_min, inner_max, interior_min_depth);
  // A shell of uniform thickness: the surface is the outermost particle shell (about one spacing
  // thick), the inner layer the next one, and every interior particle lies deeper than both.
  EXPECT_LT(surface_max, 1.25);
  EXPECT_GT(inner_min, 0.5);
  EXPECT_LT(inner_max, 2.5);
  EXPECT_GT(interior_min_depth, 1.5);
  EXPECT_GE(interior_min_depth, inner_max - 0.25);
}
