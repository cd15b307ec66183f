#include "spall/core/parallel.hpp"

#include <cstdlib>
#include <omp.h>
#include <unistd.h>

namespace spall::parallel {

int thread_count() { return omp_get_max_threads(); }

void set_thread_count(int threads) { omp_set_num_threads(threads); }

void wait_politely(char** argv) {
  if (std::getenv("OMP_WAIT_POLICY") || std::getenv("GOMP_SPINCOUNT")) return;  // the user's choice
  // The spin is counted in pause-loop iterations (tens of ns each on x86): a thread that finds no
  // work sleeps after about a millisecond instead of about 30 ms (libgomp's 3e5 with the
  // default policy), long enough to bridge the barriers between the loops of one step.
  ::setenv("GOMP_SPINCOUNT", polite_spin_count, 1);
  ::execv("/proc/self/exe", argv);
  // exec failed (no /proc): run on with the runtime's default policy.
}

}  // namespace spall::parallel
