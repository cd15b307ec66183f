#pragma once
// The progress line of a long run: rewritten in place on a terminal, one line per 10 % of the
// end time otherwise (logs, CI).
#include <chrono>

#include "spall/solver/simulation.hpp"

namespace spall::cli {

class Progress {
 public:
  Progress(spall::Real end_time, long long nodes);
  void update(const spall::solver::StepInfo& step);
  void finish(const spall::solver::StepInfo& step);
  double elapsed_seconds() const;

 private:
  void print(const spall::solver::StepInfo& step, bool final);

  using Clock = std::chrono::steady_clock;
  spall::Real end_time_;
  long long nodes_;
  bool terminal_;
  Clock::time_point start_ = Clock::now();
  Clock::time_point last_print_ = start_;
  spall::Real last_dt_ = 0;
  int next_decile_ = 1;
};

}  // namespace spall::cli
