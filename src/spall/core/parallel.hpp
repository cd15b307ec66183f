#pragma once
// The seam between the physics and the machine (DESIGN, "one forall"): loops over an index
// range, over the rows of a neighbour list, and reductions in a fixed order. Physics is written
// as a function of the index (or pair) and never names OpenMP; a GPU backend later is a new body
// for these functions, not a second copy of the physics. Bodies must not allocate, throw or keep
// thread_local scratch.
#include <algorithm>
#include <array>
#include <atomic>
#include <concepts>
#include <limits>
#include <type_traits>
#include <utility>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/exact_sum.hpp"
#include "spall/core/types.hpp"

namespace spall {

// N sums taken in one pass, as plain scalars. A term built entry by entry in an Eigen vector is
// stored to the stack one lane at a time and reloaded whole for the sum, which stalls store
// forwarding (most of the time loop's energy pass; docs/PERFORMANCE.md).
template <int N>
struct Sums {
  static constexpr int size = N;
  Real value[N] = {};
  Real& operator[](int i) { return value[i]; }
  Real operator[](int i) const { return value[i]; }
  Sums& operator+=(const Sums& other) {
    for (int i = 0; i < N; ++i) value[i] += other.value[i];
    return *this;
  }
};

namespace parallel {

// How a loop's range is shared: statically (one contiguous piece per thread) or in chunks of
// `chunk` handed out as threads finish (rows of very different cost); a range shorter than
// `serial_below` runs on the calling thread alone (starting a team costs more than it saves).
struct Schedule {
  Index chunk = 0;  // 0: static
  Index serial_below = 0;
};

// The indices [begin, end): the loops below run over one as over [0, n) (under MPI a rank's own
// particles, or the stretch of them its passes read). The body is inlined into the loop, as if
// written there (a body called as a function reloads what it captures after each store).
struct Range {
  Index begin = 0;
  Index end = 0;
  Index size() const { return end > begin ? end - begin : 0; }
};
// The smallest range that holds both (an empty one adds nothing).
inline Range hull(Range r, Range s) {
  if (s.begin >= s.end) return r;
  if (r.begin >= r.end) return s;
  return {std::min(r.begin, s.begin), std::max(r.end, s.end)};
}

// body(i) for every i in [0, n).
template <std::integral I, class Body>
void for_each(I n, Body&& body, Schedule schedule = {}) {
  if (schedule.chunk > 0) {
#pragma omp parallel for schedule(dynamic, schedule.chunk) if (std::cmp_greater_equal(n, schedule.serial_below))
    for (I i = 0; i < n; ++i) body(i);
  } else {
#pragma omp parallel for schedule(static) if (std::cmp_greater_equal(n, schedule.serial_below))
    for (I i = 0; i < n; ++i) body(i);
  }
}
// body(i) for every i in the range.
template <class Body>
void for_each(Range range, Body&& body, Schedule schedule = {}) {
  for_each(range.size(), [&](Index k) __attribute__((always_inline)) { body(range.begin + k); }, schedule);
}

// Each thread folds its share of [0, n) into its own T, starting from identity, with add(t, i);
// then the threads' Ts are merged with merge(t, other) in some order: only for operations whose
// result does not depend on the order (min, max, logical or, integer sums); sums of reals go
// through exact_sum. In place, for a T of several parts (a box, a minimum and a flag): a T built
// per item and combined cost twice the work (measured on the neighbour list's motion check).
template <std::integral I, typename T, class Add, class Merge>
T fold_exact(I n, T identity, Add&& add, Merge&& merge, Schedule schedule = {}) {
  T result = identity;
#pragma omp parallel if (std::cmp_greater_equal(n, schedule.serial_below))
  {
    T local = identity;
    if (schedule.chunk > 0) {
#pragma omp for schedule(dynamic, schedule.chunk) nowait
      for (I i = 0; i < n; ++i) add(local, i);
    } else {
#pragma omp for schedule(static) nowait
      for (I i = 0; i < n; ++i) add(local, i);
    }
#pragma omp critical(spall_parallel_reduce_exact)
    merge(result, local);
  }
  return result;
}
// The same over the items of a range: add(t, i) for i in it.
template <typename T, class Add, class Merge>
T fold_exact(Range range, T identity, Add&& add, Merge&& merge, Schedule schedule = {}) {
  return fold_exact(
      range.size(), identity, [&](T& t, Index k) __attribute__((always_inline)) { add(t, range.begin + k); }, merge,
      schedule);
}

// combine(... combine(identity, term(0)) ..., term(n - 1)) in some order, under fold_exact's rule.
template <std::integral I, typename T, class Term, class Combine>
T reduce_exact(I n, T identity, Term&& term, Combine&& combine, Schedule schedule = {}) {
  return fold_exact(
      n, identity, [&](T& t, I i) { t = combine(t, term(i)); }, [&](T& t, const T& other) { t = combine(t, other); },
      schedule);
}
// The same over the terms of a range.
template <typename T, class Term, class Combine>
T reduce_exact(Range range, T identity, Term&& term, Combine&& combine, Schedule schedule = {}) {
  return reduce_exact(
      range.size(), identity, [&](Index k) __attribute__((always_inline)) { return term(range.begin + k); }, combine,
      schedule);
}

// body(block) for every block in [0, blocks), where a block may write to its own and the next
// block's data: the even blocks run side by side, and an odd block runs once the even blocks on
// either side of it are done, so no two neighbouring blocks ever run at once and each item is
// written first by its even block, then by its odd neighbour, whatever the thread count. A task per
// block with those dependences rather than a sweep of the even blocks and then one of the odd: the
// end of each sweep would leave threads idle.
template <class Body>
void for_each_alternating_block(Index blocks, Body&& body) {
  std::vector<char> finished(blocks + 2);  // a dependence token per block, from block -1
  char* const token = finished.data() + 1;
#pragma omp parallel
#pragma omp single
  for (Index parity = 0; parity < 2; ++parity)
    for (Index block = parity; block < blocks; block += 2) {
#pragma omp task firstprivate(block) depend(in : token[block - 1], token[block + 1]) depend(out : token[block])
      body(block);
    }
}

// The lowest index a parallel loop reports (the same for any thread count), -1 if none: for the
// first particle whose state broke, which the error message names.
class LowestIndex {
 public:
  void report(Index i) {
    Index seen = lowest_.load(std::memory_order_relaxed);
    while (i < seen && !lowest_.compare_exchange_weak(seen, i, std::memory_order_relaxed)) {
    }
  }
  Index value() const {
    const Index i = lowest_.load(std::memory_order_relaxed);
    return i == std::numeric_limits<Index>::max() ? Index(-1) : i;
  }

 private:
  std::atomic<Index> lowest_{std::numeric_limits<Index>::max()};
};

// The lowest i in the range for which failed(i) holds, -1 if none: the same for any thread count.
// failed(i) is evaluated for every i (it may do the loop's work).
template <class Failed>
Index first_failure(Range range, Failed&& failed, Schedule schedule = {}) {
  LowestIndex lowest;
  for_each(range, [&](Index i) {
    if (failed(i)) lowest.report(i);
  }, schedule);
  return lowest.value();
}
// The same in [0, n).
template <class Failed>
Index first_failure(Index n, Failed&& failed, Schedule schedule = {}) {
  return first_failure(Range{0, n}, failed, schedule);
}

// The threads of a parallel region, for work that keeps per-thread buffers: each thread runs the
// region's body with its Team, and the loops it starts through the team share their range among
// the team's threads.
class Team {
 public:
  int index() const;  // 0 .. size() - 1
  int size() const;
  // body(i) for every i in [0, n), shared among the team (each thread calls it with the same n).
  // The team waits at the end until every thread has finished its share.
  template <std::integral I, class Body>
  void for_each(I n, Body&& body, Schedule schedule = {}) const {
    if (schedule.chunk > 0) {
#pragma omp for schedule(dynamic, schedule.chunk)
      for (I i = 0; i < n; ++i) body(i);
    } else {
#pragma omp for schedule(static)
      for (I i = 0; i < n; ++i) body(i);
    }
  }
  template <class Body>
  void for_each(Range range, Body&& body, Schedule schedule = {}) const {
    for_each(range.size(), [&](Index k) __attribute__((always_inline)) { body(range.begin + k); }, schedule);
  }
  // body() on one thread of the team while the others wait.
  template <class Body>
  void single(Body&& body) const {
#pragma omp single
    body();
  }
  // body() on each thread in turn (in no fixed order: for exact merges, like a min).
  template <class Body>
  void one_at_a_time(Body&& body) const {
#pragma omp critical(spall_parallel_team)
    body();
  }
};

// body(team) on every thread of a team (on the calling thread alone when `in_parallel` is false).
template <class Body>
void region(Body&& body, bool in_parallel = true) {
#pragma omp parallel if (in_parallel)
  {
    const Team team;
    body(team);
  }
}

// sum_{i < n} term(i), where term returns a Real or a Sums<N> (several sums in one pass): each sum
// exact until it is rounded once at the end (ExactSum), so it does not depend on the thread count,
// on the order of the terms or on how they are split (ranks, threads). An OpenMP reduction of
// doubles would follow the thread count in the last digits; summing fixed index blocks in order
// would not, but would still follow the storage order, which MPI changes (docs/SCALING.md §2).
// With `across`, each sum is taken over the terms of every rank (each rank's own n and terms).
template <typename Term>
auto exact_sum(Index n, Term&& term, const Communicator* across = nullptr) {
  using T = std::invoke_result_t<Term&, Index>;
  constexpr int parts = [] {
    if constexpr (std::is_same_v<T, Real>)
      return 1;
    else
      return T::size;
  }();
  const auto part = [](const T& t, int k) {
    if constexpr (std::is_same_v<T, Real>)
      return t;
    else
      return t[k];
  };
  std::array<ExactSum, parts> total;
#pragma omp parallel
  {
    std::array<ExactSum, parts> local;
#pragma omp for schedule(static) nowait
    for (Index i = 0; i < n; ++i) {
      const T t = term(i);
      for (int k = 0; k < parts; ++k) local[k] += part(t, k);
    }
#pragma omp critical(spall_parallel_exact_sum)
    for (int k = 0; k < parts; ++k) total[k] += local[k];
  }
  if (across) across->sum(total);
  T result{};
  if constexpr (std::is_same_v<T, Real>)
    result = total[0].value();
  else
    for (int k = 0; k < parts; ++k) result[k] = total[k].value();
  return result;
}

// For each group g < groups, the sum of term(i) over the i < n with group(i) == g (i left out where
// group(i) < 0), each exact as exact_sum's, into a vector of `groups` sums.
template <typename Group, typename Term>
std::vector<Real> exact_sums_by_group(Index n, int groups, Group&& group, Term&& term,
                                      const Communicator* across = nullptr) {
  std::vector<ExactSum> total(static_cast<std::size_t>(groups));
#pragma omp parallel
  {
    std::vector<ExactSum> local(total.size());
#pragma omp for schedule(static) nowait
    for (Index i = 0; i < n; ++i) {
      const int g = group(i);
      if (g >= 0) local[static_cast<std::size_t>(g)] += term(i);
    }
#pragma omp critical(spall_parallel_exact_sum)
    for (std::size_t g = 0; g < total.size(); ++g) total[g] += local[g];
  }
  if (across) across->sum(total);
  std::vector<Real> result(total.size());
  for (std::size_t g = 0; g < total.size(); ++g) result[g] = total[g].value();
  return result;
}

// The same over the terms of a range.
template <typename Term>
auto exact_sum(Range range, Term&& term, const Communicator* across = nullptr) {
  return exact_sum(
      range.size(), [&](Index k) __attribute__((always_inline)) { return term(range.begin + k); }, across);
}

// The number of threads the loops above run on, and setting it (the CLI's --threads). A count
// set here or by OMP_NUM_THREADS is the user's: CoreShare keeps it.
int thread_count();
void set_thread_count(int threads);
bool thread_count_fixed();

// Fewer threads while the machine is oversubscribed. Idle OpenMP threads spin at the barriers
// between loops before they sleep (libgomp: about 3e5 iterations), which is fastest for a run
// alone and ruinous for runs that share the cores: the spinning threads of one take the cores the
// working threads of the other need (two runs on a 2-core machine took 9x their time alone). A
// run sees that it shares its cores by its threads being preempted: the kernel switches them out
// involuntarily (getrusage's ru_nivcsw) hundreds of times a second then, a few times alone.
// Asked between steps by the time loop, CoreShare halves the threads of the loops above while
// that rate is high, and tries the full count again after a wait that doubles with every try
// that finds the cores still shared (1 s to 16 s). Results do not depend on the thread count, so
// neither do they on this. The thread count in force when it is made is the most it uses, and is
// restored when it ends; a count the user fixed is kept (adapt false). Measured:
// docs/PERFORMANCE.md, "Two runs on one machine".
class CoreShare {
 public:
  explicit CoreShare(bool adapt = !thread_count_fixed());
  ~CoreShare();
  CoreShare(const CoreShare&) = delete;
  CoreShare& operator=(const CoreShare&) = delete;
  // Cheap (a clock read) but for every tenth of a second, when it reads the process's usage.
  void between_steps();
  int threads() const { return threads_; }

 private:
  bool adapt_ = true;
  int most_ = 1, threads_ = 1;
  double window_start_ = 0;     // seconds, steady clock
  long switches_at_start_ = 0;  // involuntary context switches of the process
  double cpu_at_start_ = 0;     // processor seconds of the process
  double next_try_ = 0;         // when to try most_ threads again
  double wait_ = 1;             // seconds before the next try
};

}  // namespace parallel
}  // namespace spall
