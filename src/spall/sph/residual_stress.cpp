// Residual-stress detection of seed 000 (issue 4): von Mises statistics per part and per colour-
// field category, and the count of particles whose stress exceeds a fraction of yield while they
// hardly deform any more.
#include <algorithm>
#include <cmath>

#include "spall/materials/elastic.hpp"
#include "spall/sph/solid.hpp"

namespace spall::sph {

namespace {
// The 95th percentile by the nearest-rank method.
Real percentile95(std::vector<Real> values) {
  if (values.empty()) return 0;
  const std::size_t rank = static_cast<std::size_t>(std::ceil(0.95 * static_cast<double>(values.size())));
  const std::size_t k = std::clamp<std::size_t>(rank, 1, values.size()) - 1;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(k), values.end());
  return values[k];
}
}  // namespace

std::vector<ResidualStressRow> SolidFormulation::residual_stress(
    const ResidualStressCriterion& criterion) const {
  const Index n = particle_count();
  std::vector<Real> rate(static_cast<std::size_t>(n));  // effective strain rates of the last step
  for (Index a = 0; a < n; ++a) rate[a] = std::sqrt(strain_rate_squared_[a]);
  const Real largest_rate = n > 0 ? *std::max_element(rate.begin(), rate.end()) : 0;
  const Real rate_limit = criterion.strain_rate > 0 ? criterion.strain_rate : 0.01 * largest_rate;

  const std::size_t parts = materials_.size();
  const int categories = category_.empty() ? 0 : 3;
  // Von Mises values grouped by (part, category + 1), category 0 of the grouping being "all".
  std::vector<std::vector<Real>> von_mises(parts * (categories + 1));
  std::vector<Index> residual(von_mises.size(), 0);
  for (Index a = 0; a < n; ++a) {
    const Real q = materials::von_mises(state_[a].deviatoric_stress);
    const Real yield = materials::static_yield_stress(materials_[material_[a]], state_[a]);
    const bool is_residual = q > criterion.yield_fraction * yield && rate[a] <= rate_limit;
    std::size_t groups[2] = {material_[a] * std::size_t(categories + 1), 0};
    int count = 1;
    if (categories) groups[count++] = groups[0] + 1 + static_cast<std::size_t>(category_[a]);
    for (int g = 0; g < count; ++g) {
      von_mises[groups[g]].push_back(q);
      residual[groups[g]] += is_residual;
    }
  }
  std::vector<ResidualStressRow> rows;
  for (std::size_t part = 0; part < parts; ++part)
    for (int c = -1; c < categories; ++c) {
      const std::size_t g = part * (categories + 1) + static_cast<std::size_t>(c + 1);
      const auto& values = von_mises[g];
      ResidualStressRow row;
      row.part = part < options_.part_ids.size() ? options_.part_ids[part] : 0;
      row.category = c;
      row.particles = static_cast<Index>(values.size());
      if (!values.empty()) {
        row.von_mises_max = *std::max_element(values.begin(), values.end());
        Real sum = 0;
        for (Real v : values) sum += v;
        row.von_mises_mean = sum / static_cast<Real>(values.size());
        row.von_mises_p95 = percentile95(values);
      }
      row.residual = residual[g];
      rows.push_back(row);
    }
  return rows;
}

}  // namespace spall::sph
