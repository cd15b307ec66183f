#include "spall/core/parallel.hpp"

#include <cstdlib>
#include <omp.h>
#include <unistd.h>

namespace spall::parallel {

int Team::index() const { return omp_get_thread_num(); }

int Team::size() const { return omp_get_num_threads(); }

int thread_count() { return omp_get_max_threads(); }

void set_thread_count(int threads) { omp_set_num_threads(threads); }

void wait_politely(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;  // the user's choice
  // The spin is counted in pause-loop iterations: 3000 of them (tens of microseconds) bridge most
  // barriers between the loops of one step when a run is alone, while libgomp's 300000 keep a
  // core busy for milliseconds that another run's threads needed. Two runs at once on 2 cores:
  // 1.7-2.3x their time alone with 3000, 3-7x with the runtime's default. Alone, 3000 costs the
  // elastic bar nothing measurable and the 10^5-particle Taylor bar 5-8 % (1000 cost 16 %):
  // docs/PERFORMANCE.md, "Two runs on one machine".
  ::setenv("GOMP_SPINCOUNT", polite_spin_count, 1);
  ::execv("/proc/self/exe", argv);
  // exec failed (no /proc): run on with the runtime's default policy.
}

}  // namespace spall::parallel
