#include "spall/core/parallel.hpp"

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <tuple>
#include <utility>
#include <omp.h>
#include <sys/resource.h>

namespace spall::parallel {

int Team::index() const { return omp_get_thread_num(); }

int Team::size() const { return omp_get_num_threads(); }

namespace {
bool fixed_by_user = std::getenv("OMP_NUM_THREADS") != nullptr;
}  // namespace

int thread_count() { return omp_get_max_threads(); }

void set_thread_count(int threads) {
  omp_set_num_threads(threads);
  fixed_by_user = true;
}

bool thread_count_fixed() { return fixed_by_user; }

namespace {

double seconds_now() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

// The process's involuntary context switches and its processor time in seconds, over all threads.
std::pair<long, double> process_usage() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  const auto seconds = [](const timeval& t) { return double(t.tv_sec) + 1e-6 * double(t.tv_usec); };
  return {usage.ru_nivcsw, seconds(usage.ru_utime) + seconds(usage.ru_stime)};
}

// A run shares its cores when its threads are preempted more often than this (a second, a thread)
// and it gets fewer than three quarters of a core a thread. Measured on the 2-core VM (AMD EPYC,
// two threads): a run alone 7 to 40 switches a second (the elastic bar's short steps 50 to 80)
// on 1.6 to 2.0 cores; two runs at once 80 to 135 on 0.9 to 1.0 (docs/PERFORMANCE.md).
constexpr double shared_core_switch_rate = 70;
constexpr double window = 0.1;     // seconds between two looks at the usage
constexpr double longest_wait = 16;  // seconds between two tries of the full thread count

}  // namespace

CoreShare::CoreShare(bool adapt) : adapt_(adapt), most_(omp_get_max_threads()), threads_(most_) {
  window_start_ = seconds_now();
  std::tie(switches_at_start_, cpu_at_start_) = process_usage();
}

CoreShare::~CoreShare() { omp_set_num_threads(most_); }

void CoreShare::between_steps() {
  if (!adapt_) return;
  const double now = seconds_now();
  if (now - window_start_ < window) return;
  const auto [switches, cpu] = process_usage();
  const double rate = (switches - switches_at_start_) / (now - window_start_) / threads_;
  const double cores = (cpu - cpu_at_start_) / (now - window_start_);  // the cores the run got
  window_start_ = now;
  switches_at_start_ = switches;
  cpu_at_start_ = cpu;
  int threads = threads_;
  if (rate > shared_core_switch_rate && cores < 0.75 * threads_ && threads_ > 1) {
    threads = std::max(1, threads_ / 2);
    if (threads_ == most_ && next_try_ > 0) wait_ = std::min(2 * wait_, longest_wait);  // a try that failed
    next_try_ = now + wait_;
  } else if (threads_ < most_ && now >= next_try_) {
    threads = most_;
  } else if (threads_ == most_ && next_try_ > 0 && now >= next_try_ + window) {
    wait_ = 1;  // the full count held for a window: the cores are free again
    next_try_ = 0;
  }
  if (threads != threads_) {
    threads_ = threads;
    omp_set_num_threads(threads);
  }
}

}  // namespace spall::parallel
