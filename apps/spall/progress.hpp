#pragma once
// The progress line of a long run: rewritten in place on a terminal; otherwise (logs, CI) one line
// per 10 % of the end time, and at least one a minute, so that a slow run shows it is alive.
#include <chrono>
#include <cstdio>
#include <functional>

#include "spall/solver/simulation.hpp"

namespace spall::cli {

class Progress {
 public:
  using Clock = std::chrono::steady_clock;

  // Where the lines go and what time it is: stderr, its tty status and the steady clock by
  // default; a test passes its own clock (no sleeping) and file.
  struct Environment {
    std::function<Clock::time_point()> now = [] { return Clock::now(); };
    std::FILE* out = stderr;
    bool terminal = false;
    static Environment standard();
  };

  // Off a terminal, the longest wall time between two lines.
  static constexpr std::chrono::seconds quiet_limit{60};

  Progress(spall::Real end_time, long long nodes, Environment environment = Environment::standard());
  // A restarted run: its rate and ETA count the steps and time from `step` on, which this process
  // takes, not those of the run it continues; the deciles already passed print no line.
  void continue_from(const spall::solver::StepInfo& step);
  void update(const spall::solver::StepInfo& step);
  void finish(const spall::solver::StepInfo& step);
  double elapsed_seconds() const;
  // Steps this process has taken by `step`.
  long long steps_taken(const spall::solver::StepInfo& step) const { return step.step - first_step_; }

 private:
  void print(const spall::solver::StepInfo& step, bool final);

  Environment environment_;
  spall::Real end_time_;
  long long nodes_;
  Clock::time_point start_;
  Clock::time_point last_print_;
  spall::Real last_dt_ = 0;
  int next_decile_ = 1;
  long long first_step_ = 0;  // where this process started: 0, or the restart's step
  spall::Real first_time_ = 0;
};

}  // namespace spall::cli
