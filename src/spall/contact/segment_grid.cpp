#include "spall/contact/segment_grid.hpp"

#include <algorithm>
#include <cmath>

namespace spall::contact {

void SegmentGrid::build(std::span<const Segment> segments, std::span<const Real> reach, std::span<const Vec3> x) {
  const Index count = static_cast<Index>(segments.size());
  dims_ = {0, 0, 0};
  first_.assign(1, 0);
  list_.clear();
  if (count == 0) return;
  box_lo_.resize(count);
  box_hi_.resize(count);
  Vec3 lower = Vec3::Constant(std::numeric_limits<Real>::infinity()), upper = -lower;
  Real largest = 0;
  for (Index s = 0; s < count; ++s) {
    const Segment& seg = segments[s];
    Vec3 lo = x[seg.node[0]], hi = lo;
    for (int k = 1; k < seg.corners(); ++k) {
      lo = lo.cwiseMin(x[seg.node[k]]);
      hi = hi.cwiseMax(x[seg.node[k]]);
    }
    lo.array() -= reach[s];
    hi.array() += reach[s];
    box_lo_[s] = lo;
    box_hi_[s] = hi;
    lower = lower.cwiseMin(lo);
    upper = upper.cwiseMax(hi);
    largest = std::max(largest, (hi - lo).maxCoeff());
  }
  // Cells as large as the largest box, so that a box spans at most two cells a way; larger when
  // that would make many more cells than segments (a few large segments among many small ones).
  const Vec3 extent = (upper - lower).cwiseMax(Vec3::Constant(largest * 1e-6 + 1e-300));
  Real cell = std::max(largest, Real(1e-300));
  auto cells_of = [&](Real h) {
    std::array<Index, 3> d;
    for (int a = 0; a < 3; ++a) d[a] = std::max<Index>(1, static_cast<Index>(std::ceil(extent[a] / h)));
    return d;
  };
  const double most = 8.0 * count + 64;
  while (double(cells_of(cell)[0]) * cells_of(cell)[1] * cells_of(cell)[2] > most) cell *= 1.5;
  dims_ = cells_of(cell);
  lower_ = lower;
  inverse_cell_ = 1 / cell;
  const Index cells = dims_[0] * dims_[1] * dims_[2];

  auto range = [&](const Vec3& lo, const Vec3& hi) {
    std::array<Index, 6> r;
    for (int a = 0; a < 3; ++a) {
      r[a] = std::clamp<Index>(static_cast<Index>((lo[a] - lower_[a]) * inverse_cell_), 0, dims_[a] - 1);
      r[3 + a] = std::clamp<Index>(static_cast<Index>((hi[a] - lower_[a]) * inverse_cell_), 0, dims_[a] - 1);
    }
    return r;
  };
  // Counting sort: count, prefix sum, fill in segment order (so every cell lists ascending IDs).
  first_.assign(cells + 1, 0);
  for (int fill = 0; fill < 2; ++fill) {
    if (fill == 1) {
      for (Index c = 0; c < cells; ++c) first_[c + 1] += first_[c];
      list_.resize(first_[cells]);
    }
    std::vector<Index> next;
    if (fill == 1) next.assign(first_.begin(), first_.end() - 1);
    for (Index s = 0; s < count; ++s) {
      const auto r = range(box_lo_[s], box_hi_[s]);
      for (Index k = r[2]; k <= r[5]; ++k)
        for (Index j = r[1]; j <= r[4]; ++j)
          for (Index i = r[0]; i <= r[3]; ++i) {
            const Index c = (k * dims_[1] + j) * dims_[0] + i;
            if (fill == 0) ++first_[c + 1];
            else list_[next[c]++] = s;
          }
    }
  }
}

std::span<const Index> SegmentGrid::candidates(const Vec3& p) const {
  if (dims_[0] == 0) return {};
  Index c = 0, stride = 1;
  for (int a = 0; a < 3; ++a) {
    const Real u = (p[a] - lower_[a]) * inverse_cell_;
    if (!(u >= 0 && u < Real(dims_[a]))) return {};
    c += static_cast<Index>(u) * stride;
    stride *= dims_[a];
  }
  return {list_.data() + first_[c], list_.data() + first_[c + 1]};
}

}  // namespace spall::contact
