// Residual-stress detection of seed 000 (issue 4): von Mises statistics per part and per colour-
// field category, and the count of particles whose stress exceeds a fraction of yield while they
// hardly deform any more.
#include <algorithm>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>

#include "spall/core/communicator.hpp"
#include "spall/core/exact_sum.hpp"
#include "spall/materials/elastic.hpp"
#include "spall/sph/solid.hpp"

namespace spall::sph {

namespace {
// A von Mises value's place in the order of nonnegative doubles (their bit patterns are in it).
std::uint64_t order_key(Real q) { return q == 0 ? 0 : std::bit_cast<std::uint64_t>(q); }

// The k-th smallest (from 0) of each group's values over the ranks, groups with k < 0 skipped (0):
// the smallest key whose count of values at or below it exceeds k, found by bisection on the keys
// with one sum of the groups' counts over the ranks a round, so that no rank gathers another's
// values. `sorted[g]`: this rank's values of group g, in the order of their keys.
std::vector<Real> kth_smallest(const std::vector<std::vector<Real>>& sorted, const std::vector<std::int64_t>& k,
                               const parallel::Communicator& ranks) {
  const std::size_t groups = sorted.size();
  std::vector<std::uint64_t> low(groups, 0), high(groups, std::numeric_limits<std::uint64_t>::max());
  std::vector<std::int64_t> at_or_below(groups);
  const auto open = [&](std::size_t g) { return k[g] >= 0 && low[g] < high[g]; };
  // Every rank takes the same bounds from the same sums, so all run the same rounds (at most 64).
  for (;;) {
    bool any = false;
    for (std::size_t g = 0; g < groups; ++g) {
      at_or_below[g] = 0;
      if (!open(g)) continue;
      any = true;
      const std::uint64_t middle = low[g] + (high[g] - low[g]) / 2;
      at_or_below[g] = std::upper_bound(sorted[g].begin(), sorted[g].end(), middle,
                                        [](std::uint64_t key, Real q) { return key < order_key(q); }) -
                       sorted[g].begin();
    }
    if (!any) break;
    ranks.sum(at_or_below);
    for (std::size_t g = 0; g < groups; ++g) {
      if (!open(g)) continue;
      const std::uint64_t middle = low[g] + (high[g] - low[g]) / 2;
      if (at_or_below[g] > k[g])
        high[g] = middle;
      else
        low[g] = middle + 1;
    }
  }
  std::vector<Real> value(groups, 0);
  for (std::size_t g = 0; g < groups; ++g)
    if (k[g] >= 0) value[g] = std::bit_cast<Real>(low[g]);
  return value;
}
}  // namespace

// Each rank reads its own particles, whose state is current there alone (docs/SCALING.md §3); the
// statistics over the ranks are exact, so the same for any number of ranks: counts, largest
// values, the mean from the exact sum, and the 95th percentile by the nearest-rank method.
std::vector<ResidualStressRow> SolidFormulation::residual_stress(
    const ResidualStressCriterion& criterion) const {
  const parallel::Communicator& ranks = parallel::world();
  const Index n = particle_count();
  std::vector<Real> rate(static_cast<std::size_t>(n));  // effective strain rates of the last step
  double negated_largest_rate = 0;
  for (Index a = 0; a < n; ++a) {
    if (!owns(a)) continue;
    rate[a] = std::sqrt(strain_rate_squared_[a]);
    negated_largest_rate = std::min(negated_largest_rate, -rate[a]);
  }
  ranks.minimum({&negated_largest_rate, 1});
  const Real rate_limit = criterion.strain_rate > 0 ? criterion.strain_rate : -0.01 * negated_largest_rate;

  const std::size_t parts = materials_.size();
  const int categories = category_.empty() ? 0 : 3;
  // Von Mises values grouped by (part, category + 1), category 0 of the grouping being "all".
  const std::size_t groups = parts * (categories + 1);
  std::vector<std::vector<Real>> von_mises(groups);
  std::vector<std::int64_t> counts(2 * groups, 0);  // particles, then those with residual stress
  std::vector<ExactSum> sum(groups);
  std::vector<double> negated_max(groups, 0);
  for (Index a = 0; a < n; ++a) {
    if (!owns(a)) continue;
    const Real q = materials::von_mises(state_[a].deviatoric_stress);
    const Real yield = materials::static_yield_stress(materials_[material_[a]], state_[a]);
    const bool is_residual = q > criterion.yield_fraction * yield && rate[a] <= rate_limit;
    std::size_t in[2] = {material_[a] * std::size_t(categories + 1), 0};
    int count = 1;
    if (categories) in[count++] = in[0] + 1 + static_cast<std::size_t>(category_[a]);
    for (int k = 0; k < count; ++k) {
      const std::size_t g = in[k];
      von_mises[g].push_back(q);
      ++counts[g];
      counts[groups + g] += is_residual;
      sum[g] += q;
      negated_max[g] = std::min(negated_max[g], -q);
    }
  }
  ranks.sum(counts);
  ranks.sum(sum);
  ranks.minimum(negated_max);
  std::vector<std::int64_t> k(groups);
  for (std::size_t g = 0; g < groups; ++g) {
    std::sort(von_mises[g].begin(), von_mises[g].end(), [](Real p, Real q) { return order_key(p) < order_key(q); });
    const auto rank = static_cast<std::int64_t>(std::ceil(0.95 * static_cast<double>(counts[g])));
    k[g] = counts[g] == 0 ? -1 : std::clamp<std::int64_t>(rank, 1, counts[g]) - 1;
  }
  const std::vector<Real> p95 = kth_smallest(von_mises, k, ranks);

  std::vector<ResidualStressRow> rows;
  for (std::size_t part = 0; part < parts; ++part)
    for (int c = -1; c < categories; ++c) {
      const std::size_t g = part * (categories + 1) + static_cast<std::size_t>(c + 1);
      ResidualStressRow row;
      row.part = part < options_.part_ids.size() ? options_.part_ids[part] : 0;
      row.category = c;
      row.particles = static_cast<Index>(counts[g]);
      if (counts[g] > 0) {
        row.von_mises_max = -negated_max[g];
        row.von_mises_mean = sum[g].value() / static_cast<Real>(counts[g]);
        row.von_mises_p95 = p95[g];
      }
      row.residual = static_cast<Index>(counts[groups + g]);
      rows.push_back(row);
    }
  return rows;
}

}  // namespace spall::sph
