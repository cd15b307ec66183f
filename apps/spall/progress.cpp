#include "progress.hpp"

#include <fmt/core.h>
#include <unistd.h>

#include <utility>

namespace spall::cli {

Progress::Environment Progress::Environment::standard() {
  Environment environment;
  environment.terminal = isatty(STDERR_FILENO) != 0;
  return environment;
}

Progress::Progress(spall::Real end_time, long long nodes, Environment environment)
    : environment_(std::move(environment)), end_time_(end_time), nodes_(nodes), start_(environment_.now()),
      last_print_(start_) {}

void Progress::continue_from(const spall::solver::StepInfo& step) {
  first_step_ = step.step;
  first_time_ = step.time;
  while (next_decile_ < 10 && step.time >= next_decile_ * 0.1 * end_time_ * (1 - 1e-9)) ++next_decile_;
}

double Progress::elapsed_seconds() const {
  return std::chrono::duration<double>(environment_.now() - start_).count();
}

void Progress::update(const spall::solver::StepInfo& step) {
  // The state at the end time is reached by a step of length zero (the velocity synchronisation);
  // the line shows the last step actually taken.
  if (step.dt > 0) last_dt_ = step.dt;
  const auto now = environment_.now();
  if (environment_.terminal) {
    if (now - last_print_ < std::chrono::milliseconds(250)) return;
    last_print_ = now;
    print(step, false);
    return;
  }
  const bool decile = step.time >= next_decile_ * 0.1 * end_time_ * (1 - 1e-9);
  if (!decile && now - last_print_ < quiet_limit) return;
  while (step.time >= next_decile_ * 0.1 * end_time_ * (1 - 1e-9)) ++next_decile_;
  last_print_ = now;
  print(step, false);
}

void Progress::finish(const spall::solver::StepInfo& step) {
  // Off a terminal the 100 % line has already been printed by update().
  if (environment_.terminal) print(step, true);
}

void Progress::print(const spall::solver::StepInfo& step, bool final) {
  const double seconds = elapsed_seconds();
  const double rate = seconds > 0 ? nodes_ * double(steps_taken(step)) / seconds : 0;
  const double fraction = end_time_ > 0 ? step.time / end_time_ : 1;
  // The rest of the run at the pace of this process's part of it.
  const double done = step.time - first_time_, left = end_time_ - step.time;
  const double eta = done > 0 ? seconds * left / done : 0;
  const std::string line =
      fmt::format("t {:.4e} ({:5.1f}%)  step {}  dt {:.3e}  {:.3e} node-steps/s  ETA {:.0f} s",
                  step.time, 100 * fraction, step.step, last_dt_, rate, eta);
  if (environment_.terminal)
    fmt::print(environment_.out, "\r{}{}", line, final ? "\n" : "   ");
  else
    fmt::print(environment_.out, "{}\n", line);
  std::fflush(environment_.out);
}

}  // namespace spall::cli
