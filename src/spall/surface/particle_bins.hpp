#pragma once
// Particles binned into cubes of a fixed edge, for the surface module's box queries: which particles
// can reach a block of grid voxels, or a mesh vertex. A bin's particles keep their input order and
// bins are visited in (z, y, x) order, so that every sum over the particles a query returns adds
// its terms in the same order whatever the number of threads.
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "spall/core/types.hpp"

namespace spall::surface {

class ParticleBins {
 public:
  // Bins the positions into cubes of edge `bin_size` (> 0).
  ParticleBins(std::span<const Vec3> x, Real bin_size);

  // Calls visit(b) for every particle b in a bin that overlaps the box [lo, hi]: a superset of the
  // particles inside it.
  template <typename Visit>
  void for_each_in_box(const Vec3& lo, const Vec3& hi, Visit&& visit) const {
    const BinKey first = key_of(lo), last = key_of(hi);
    for (std::int64_t z = first[0]; z <= last[0]; ++z) {
      for (std::int64_t y = first[1]; y <= last[1]; ++y) {
        for (Index bin = first_bin_from({z, y, first[2]});
             bin < bin_count() && bin_key_[bin] <= BinKey{z, y, last[2]}; ++bin) {
          for (Index k = bin_start_[bin]; k < bin_start_[bin + 1]; ++k) visit(order_[k]);
        }
      }
    }
  }

  Index bin_count() const { return static_cast<Index>(bin_key_.size()); }
  // The particles of bin `bin`, in input order.
  std::span<const Index> bin(Index bin) const {
    return std::span<const Index>(order_).subspan(bin_start_[bin], bin_start_[bin + 1] - bin_start_[bin]);
  }

 private:
  using BinKey = std::array<std::int64_t, 3>;  // (z, y, x): lexicographic order is row-major
  BinKey key_of(const Vec3& p) const;
  Index first_bin_from(const BinKey& key) const;

  Real bin_size_;
  std::vector<Index> order_;     // particle indices, grouped by bin
  std::vector<BinKey> bin_key_;  // occupied bins, ascending
  std::vector<Index> bin_start_; // bin_count() + 1 entries into order_
};

}  // namespace spall::surface
