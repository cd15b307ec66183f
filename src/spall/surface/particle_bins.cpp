#include "spall/surface/particle_bins.hpp"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace spall::surface {

ParticleBins::ParticleBins(std::span<const Vec3> x, Real bin_size) : bin_size_(bin_size) {
  std::vector<BinKey> key(x.size());
  for (std::size_t b = 0; b < x.size(); ++b) key[b] = key_of(x[b]);
  order_.resize(x.size());
  std::iota(order_.begin(), order_.end(), Index(0));
  // Stable: within a bin, particles stay in input order.
  std::stable_sort(order_.begin(), order_.end(), [&](Index a, Index b) { return key[a] < key[b]; });
  for (std::size_t k = 0; k < order_.size(); ++k) {
    const BinKey& current = key[order_[k]];
    if (bin_key_.empty() || bin_key_.back() != current) {
      bin_key_.push_back(current);
      bin_start_.push_back(static_cast<Index>(k));
    }
  }
  bin_start_.push_back(static_cast<Index>(order_.size()));
}

ParticleBins::BinKey ParticleBins::key_of(const Vec3& p) const {
  const auto bin = [&](Real coordinate) {
    return static_cast<std::int64_t>(std::floor(coordinate / bin_size_));
  };
  return {bin(p.z()), bin(p.y()), bin(p.x())};
}

Index ParticleBins::first_bin_from(const BinKey& key) const {
  return static_cast<Index>(std::lower_bound(bin_key_.begin(), bin_key_.end(), key) - bin_key_.begin());
}

}  // namespace spall::surface
