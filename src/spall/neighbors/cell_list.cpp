#include "spall/neighbors/cell_list.hpp"

#include <algorithm>
#include <bit>
#include <cmath>
#include <stdexcept>
#include <string>
#include <utility>

#include "spall/core/bounding_box.hpp"
#include "spall/core/error.hpp"

namespace spall::neighbors {

namespace {

// The particles' box; a non-finite position is an instability, named by its particle.
BoundingBox particle_box(std::span<const Vec3> x) {
  const BoundingBox box = bounding_box(x.size(), [&](std::size_t i) { return x[i]; });
  if (!box.finite) {
    const auto bad = std::find_if(x.begin(), x.end(), [](const Vec3& p) { return !p.allFinite(); });
    throw InstabilityError("neighbour search: particle " + std::to_string(bad - x.begin()) +
                           " has a non-finite position");
  }
  return box;
}

// LSD radix sort of (key, particle) by key, 11 bits a pass. Stable, so particles of one cell keep
// their input order, and the result is unique whatever the thread count. Serial: a few passes over
// N integers cost little next to the neighbour loops.
// Only the digits the largest key uses are sorted: two passes for a million-particle block.
void sort_by_key(std::vector<CellKey>& key, std::vector<Index>& particle) {
  constexpr int digit_bits = 11;
  constexpr std::size_t buckets = std::size_t{1} << digit_bits;
  const CellKey max_key = key.empty() ? 0 : *std::max_element(key.begin(), key.end());
  const auto high = static_cast<std::uint64_t>(max_key >> 64);
  const int key_bits = high != 0 ? 64 + std::bit_width(high)
                                 : std::bit_width(static_cast<std::uint64_t>(max_key));
  std::vector<CellKey> key_out(key.size());
  std::vector<Index> particle_out(particle.size());
  std::vector<std::size_t> start(buckets);
  for (int shift = 0; shift < key_bits; shift += digit_bits) {
    std::fill(start.begin(), start.end(), 0);
    for (const CellKey k : key) ++start[(k >> shift) & (buckets - 1)];
    std::size_t sum = 0;
    for (std::size_t& s : start) sum += std::exchange(s, sum);
    for (std::size_t i = 0; i < key.size(); ++i) {
      const std::size_t to = start[(key[i] >> shift) & (buckets - 1)]++;
      key_out[to] = key[i];
      particle_out[to] = particle[i];
    }
    key.swap(key_out);
    particle.swap(particle_out);
  }
}

}  // namespace

Real CellList::cell_size_over(const BoundingBox& box, Real cell_size) {
  // Past 2^42 cells on an axis (so that the key fits 126 bits) the cells grow; a double then
  // resolves a position in the box to a thousandth of a cell or worse, so no run that means
  // anything gets there.
  constexpr Real max_cells_along_axis = 0x1p42 - 1;
  return box.empty() ? cell_size : std::max(cell_size, (box.upper - box.lower).maxCoeff() / max_cells_along_axis);
}

void CellList::build(std::span<const Vec3> x, Real cell_size, std::span<const Id> tie, const BoundingBox* grid) {
  if (!(cell_size > 0) || !std::isfinite(cell_size)) {
    throw std::invalid_argument("neighbour search: cell size must be positive and finite, got " +
                                std::to_string(cell_size));
  }
  const auto n = static_cast<std::int64_t>(x.size());
  order_.clear();
  cell_key_.assign(1, ~CellKey(0));
  cell_start_.assign(1, 0);
  cell_size_ = cell_size;
  cells_ = {1, 1, 1};
  lower_ = Vec3::Zero();
  if (n == 0 && (grid == nullptr || grid->empty())) return;

  const BoundingBox particles = particle_box(x);
  const BoundingBox& box = grid != nullptr ? *grid : particles;
  lower_ = box.lower;
  const Vec3 extent = box.upper - box.lower;
  if (!extent.allFinite()) {
    throw InstabilityError("neighbour search: particles span more than the largest double");
  }
  // Cells along an axis: floor(extent / h) + 1 covers [lower, upper] with cells of edge h, and
  // gives one cell to an axis of zero extent (particles in a plane or a line).
  cell_size_ = cell_size_over(box, cell_size_);
  const Vec3 cells = (extent.array() / cell_size_).floor() + 1;
  cells_ = {static_cast<std::int64_t>(cells.x()), static_cast<std::int64_t>(cells.y()),
            static_cast<std::int64_t>(cells.z())};

  std::vector<CellKey> particle_key(n);
  const Real inverse_size = 1 / cell_size_;
  parallel::for_each(n, [&](std::int64_t i) {
    // Relative to the box corner, so positions far from the origin bin as well as near it; the
    // clamp guards the particles on the upper faces against rounding.
    std::array<std::int64_t, 3> ic;
    for (int d = 0; d < 3; ++d) {
      const auto c = static_cast<std::int64_t>((x[i][d] - box.lower[d]) * inverse_size);
      ic[d] = std::clamp<std::int64_t>(c, 0, cells_[d] - 1);
    }
    particle_key[i] = key(ic[0], ic[1], ic[2]);
  });
  sort_into_cells(particle_key, tie);
}

void CellList::build_from_keys(std::span<const CellKey> key, std::span<const Id> tie, const Vec3& lower,
                               Real cell_size, const std::array<std::int64_t, 3>& cells_along) {
  lower_ = lower;
  cell_size_ = cell_size;
  cells_ = cells_along;
  cell_key_.assign(1, ~CellKey(0));
  cell_start_.assign(1, 0);
  std::vector<CellKey> particle_key(key.begin(), key.end());
  sort_into_cells(particle_key, tie);
}

void CellList::sort_into_cells(std::vector<CellKey>& particle_key, std::span<const Id> tie) {
  const auto n = static_cast<std::int64_t>(particle_key.size());
  order_.resize(n);
  for (std::int64_t i = 0; i < n; ++i) order_[i] = static_cast<Index>(i);
  if (n == 0) return;
  if (!tie.empty()) {
    // In tie order first; the stable sort by cell keeps it within each cell. Keys from the least,
    // so that the sort takes only the digits their spread needs.
    const Id least = *std::min_element(tie.begin(), tie.end());
    std::vector<CellKey> tie_key(n);
    for (std::int64_t i = 0; i < n; ++i)
      tie_key[i] = static_cast<std::uint64_t>(tie[i]) - static_cast<std::uint64_t>(least);
    sort_by_key(tie_key, order_);
    for (std::int64_t k = 0; k < n; ++k) tie_key[k] = particle_key[order_[k]];
    particle_key.swap(tie_key);
  }
  sort_by_key(particle_key, order_);

  for (std::int64_t k = 0; k < n; ++k) {
    if (k == 0 || particle_key[k] != particle_key[k - 1]) {
      cell_key_.back() = particle_key[k];
      cell_key_.push_back(~CellKey(0));
      if (k > 0) cell_start_.push_back(static_cast<Index>(k));
    }
  }
  cell_start_.push_back(static_cast<Index>(n));
}

// Steps that double away from the hint bracket the answer, then bisection finds it: the cost grows
// with the log of its distance from the hint, where a bisection of the whole list costs log2 of
// the cells and as many cache misses (docs/PERFORMANCE.md, session 20).
Index CellList::first_cell_near(CellKey k, Index hint) const {
  const Index count = cell_count();
  const auto first = cell_key_.begin();
  hint = std::clamp<Index>(hint, 0, count);
  if (cell_key_[hint] >= k) {  // at or before the hint: key[low - 1] < k <= key[high]
    Index high = hint;
    for (Index step = 1;; step *= 2) {
      const Index probe = high - step;
      if (probe < 0 || cell_key_[probe] < k) {
        const Index low = std::max<Index>(probe + 1, 0);
        return static_cast<Index>(std::lower_bound(first + low, first + high, k) - first);
      }
      high = probe;
    }
  }
  // After the hint: key[low - 1] < k <= key[probe]; the sentinel key[count] exceeds every key.
  Index low = hint + 1;
  for (Index step = 1;; step *= 2) {
    const Index probe = std::min(low - 1 + step, count);
    if (cell_key_[probe] >= k) return static_cast<Index>(std::lower_bound(first + low, first + probe, k) - first);
    low = probe + 1;
  }
}

std::array<std::int64_t, 3> CellList::coordinates(Index c) const {
  const CellKey k = cell_key_[c];
  const CellKey row = k / CellKey(cells_[0]);
  return {static_cast<std::int64_t>(k - row * CellKey(cells_[0])),
          static_cast<std::int64_t>(row % CellKey(cells_[1])),
          static_cast<std::int64_t>(row / CellKey(cells_[1]))};
}

}  // namespace spall::neighbors
