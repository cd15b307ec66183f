#include "spall/surface/vertex_fields.hpp"

#include <algorithm>
#include <limits>
#include <stdexcept>
#include <variant>

#include <fmt/format.h>

#include "spall/core/parallel.hpp"
#include "spall/kernels/cubic_spline.hpp"
#include "spall/surface/particle_bins.hpp"

namespace spall::surface {

namespace {
using Kernel = kernels::CubicSpline<3>;  // as in colour_grid.cpp

// The particles that reach a vertex with their kernel weights V_b W_b, and the nearest particle.
struct Stencil {
  std::vector<std::pair<Index, Real>> weights;
  Index nearest = -1;
  Real weight_sum = 0;
};
}  // namespace

std::vector<discretization::Field> vertex_fields(const SurfaceParticles& particles,
                                                  const std::vector<discretization::Field>& fields,
                                                  const std::vector<Vec3>& vertices) {
  const std::size_t n = particles.x.size();
  for (const auto& f : fields) {
    const std::size_t size = std::visit([](const auto& v) { return v.size(); }, f.values);
    if (size != n * static_cast<std::size_t>(f.components))
      throw std::invalid_argument(fmt::format("vertex_fields: field '{}' does not fit {} particles", f.name, n));
  }
  if (n == 0 && !vertices.empty()) throw std::invalid_argument("vertex_fields: vertices but no particles");
  std::vector<discretization::Field> out;
  for (const auto& f : fields) {
    out.push_back({f.name, f.components, {}, f.component_names});
    std::visit([&](const auto& v) { out.back().values = std::decay_t<decltype(v)>(vertices.size() * f.components); },
               f.values);
  }
  if (vertices.empty()) return out;

  const auto& h = particles.smoothing_length;
  const Real largest_support = 2 * *std::max_element(h.begin(), h.end());
  const ParticleBins bins(particles.x, largest_support);

  const Index vertex_count = static_cast<Index>(vertices.size());
  Index unreached = 0;  // vertices out of every particle's support
  parallel::region([&](const parallel::Team& team) {
    Stencil stencil;
    Index unreached_here = 0;
    team.for_each(vertex_count, [&](Index v) {
      stencil.weights.clear();
      stencil.nearest = -1;
      stencil.weight_sum = 0;
      Real nearest_distance = std::numeric_limits<Real>::max();
      const Vec3& p = vertices[v];
      const Vec3 reach = Vec3::Constant(largest_support);
      // Bins in fixed order: the same sums on any number of threads.
      bins.for_each_in_box(p - reach, p + reach, [&](Index b) {
        const Real r = (p - particles.x[b]).norm();
        if (r < nearest_distance) {
          nearest_distance = r;
          stencil.nearest = b;
        }
        const Real support = 2 * h[b];
        if (r >= support) return;
        const Real w = particles.volume[b] * Kernel::value(r, support);
        stencil.weights.emplace_back(b, w);
        stencil.weight_sum += w;
      });
      if (stencil.weights.empty()) {
        ++unreached_here;
        return;
      }
      for (std::size_t k = 0; k < fields.size(); ++k) {
        const int components = fields[k].components;
        std::visit(
            [&](const auto& values) {
              using Value = typename std::decay_t<decltype(values)>::value_type;
              auto& result = std::get<std::vector<Value>>(out[k].values);
              for (int c = 0; c < components; ++c) {
                Value& target = result[std::size_t(v) * components + c];
                if constexpr (std::is_same_v<Value, double>) {
                  Real sum = 0;
                  for (const auto& [b, w] : stencil.weights) sum += w * values[std::size_t(b) * components + c];
                  target = sum / stencil.weight_sum;
                } else {
                  target = values[std::size_t(stencil.nearest) * components + c];
                }
              }
            },
            fields[k].values);
      }
    });
    team.one_at_a_time([&] { unreached += unreached_here; });
  });
  if (unreached > 0)
    throw std::invalid_argument(fmt::format("vertex_fields: {} vertices out of every particle's support", unreached));
  return out;
}

}  // namespace spall::surface
