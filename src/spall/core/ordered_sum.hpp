#pragma once
// Sums that do not depend on the thread count: the index range is cut into fixed blocks, each
// block is summed in index order (the blocks in parallel), and the block sums are added in block
// order. An OpenMP reduction would add the threads' partial sums in an order that depends on how
// many there are, so the energies' last digits would follow the thread count.
#include <algorithm>
#include <vector>

#include "spall/core/types.hpp"

namespace spall {

// N sums taken in one pass, as plain scalars. A term built entry by entry in an Eigen vector is
// stored to the stack one lane at a time and reloaded whole for the sum, which stalls store
// forwarding (most of the time loop's energy pass; docs/PERFORMANCE.md, session 20).
template <int N>
struct Sums {
  Real value[N] = {};
  Real& operator[](int i) { return value[i]; }
  Real operator[](int i) const { return value[i]; }
  Sums& operator+=(const Sums& other) {
    for (int i = 0; i < N; ++i) value[i] += other.value[i];
    return *this;
  }
};

// sum_{i < n} term(i); T is Real or Sums<N> (several sums in one pass).
template <typename T, typename Term>
T ordered_sum(Index n, Term&& term, T zero) {
  constexpr Index block = 4096;
  const Index blocks = (n + block - 1) / block;
  std::vector<T> partial(blocks, zero);
#pragma omp parallel for schedule(static)
  for (Index k = 0; k < blocks; ++k) {
    T sum = zero;
    const Index end = std::min(n, (k + 1) * block);
    for (Index i = k * block; i < end; ++i) sum += term(i);
    partial[k] = sum;
  }
  T total = zero;
  for (const T& p : partial) total += p;
  return total;
}

}  // namespace spall
