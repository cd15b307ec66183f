#pragma once
// The seam between the physics and the machine (DESIGN, "one forall"): loops over an index
// range, over the rows of a neighbour list, and reductions in a fixed order. Physics is written
// as a function of the index (or pair) and never names OpenMP; a GPU backend later is a new body
// for these functions, not a second copy of the physics. Bodies must not allocate, throw or keep
// thread_local scratch.
#include <algorithm>
#include <vector>

#include "spall/core/types.hpp"

namespace spall {

// N sums taken in one pass, as plain scalars. A term built entry by entry in an Eigen vector is
// stored to the stack one lane at a time and reloaded whole for the sum, which stalls store
// forwarding (most of the time loop's energy pass; docs/PERFORMANCE.md).
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

namespace parallel {

// body(i) for every i in [0, n), the range cut into one contiguous piece per thread.
template <class Body>
void for_each(Index n, Body&& body) {
#pragma omp parallel for schedule(static)
  for (Index i = 0; i < n; ++i) body(i);
}

// sum_{i < n} term(i); T is Real or Sums<N> (several sums in one pass). The sums do not depend on
// the thread count: the range is cut into fixed blocks, each block is summed in index order (the
// blocks in parallel), and the block sums are added in block order. An OpenMP reduction would add
// the threads' partial sums in an order that depends on how many there are, so the energies' last
// digits would follow the thread count.
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

// The number of threads the loops above run on, and setting it (the CLI's --threads).
int thread_count();
void set_thread_count(int threads);

// Idle threads of one run must not spin against the working threads of another: two runs on a
// 2-core machine took 9x their time alone with the OpenMP runtime's default (libgomp spins about
// 3e5 iterations at each barrier before it sleeps). libgomp reads its policy from the environment
// once, as it loads, before main; so, unless the user set OMP_WAIT_POLICY or GOMP_SPINCOUNT, this
// sets GOMP_SPINCOUNT to `polite_spin_count` and executes the program again with the same
// arguments (argv as main received it). Returns only when nothing is to be done or exec failed.
// Measured: docs/PERFORMANCE.md, "Two runs on one machine".
inline constexpr const char* polite_spin_count = "10000";
void wait_politely(char** argv);

}  // namespace parallel
}  // namespace spall
