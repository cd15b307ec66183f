#include "progress.hpp"

#include <cstdio>
#include <fmt/core.h>
#include <unistd.h>

namespace spall::cli {

Progress::Progress(spall::Real end_time, long long nodes)
    : end_time_(end_time), nodes_(nodes), terminal_(isatty(STDERR_FILENO) != 0) {}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(Clock::now() - start_).count();
}

void Progress::update(const spall::solver::StepInfo& step) {
  // The state at the end time is reached by a step of length zero (the velocity synchronisation);
  // the line shows the last step actually taken.
  if (step.dt > 0) last_dt_ = step.dt;
  if (terminal_) {
    const auto now = Clock::now();
    if (now - last_print_ < std::chrono::milliseconds(250)) return;
    last_print_ = now;
    print(step, false);
  } else if (step.time >= next_decile_ * 0.1 * end_time_ * (1 - 1e-9)) {
    while (step.time >= next_decile_ * 0.1 * end_time_ * (1 - 1e-9)) ++next_decile_;
    print(step, false);
  }
}

void Progress::finish(const spall::solver::StepInfo& step) {
  // Off a terminal the 100 % line has already been printed by update().
  if (terminal_) print(step, true);
}

void Progress::print(const spall::solver::StepInfo& step, bool final) {
  const double seconds = elapsed_seconds();
  const double rate = seconds > 0 ? nodes_ * double(step.step) / seconds : 0;
  const double fraction = end_time_ > 0 ? step.time / end_time_ : 1;
  const double eta = fraction > 0 ? seconds * (1 - fraction) / fraction : 0;
  const std::string line =
      fmt::format("t {:.4e} ({:5.1f}%)  step {}  dt {:.3e}  {:.3e} node-steps/s  ETA {:.0f} s",
                  step.time, 100 * fraction, step.step, last_dt_, rate, eta);
  if (terminal_)
    fmt::print(stderr, "\r{}{}", line, final ? "\n" : "   ");
  else
    fmt::print(stderr, "{}\n", line);
  std::fflush(stderr);
}

}  // namespace spall::cli
