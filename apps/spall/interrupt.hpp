#pragma once
// Ctrl-C (SIGINT) or a scheduler's SIGTERM during a run: the first asks the run to stop between two
// steps, where it writes a checkpoint, its last state and run.json (status "interrupted") and
// exits with 128 + the signal's number, as a shell reports a process the signal ended; a second
// one ends the process at once (the signal's default action).
namespace spall::cli {

class InterruptWatch {
 public:
  InterruptWatch();   // handlers for SIGINT and SIGTERM
  ~InterruptWatch();  // the handlers before it back
  InterruptWatch(const InterruptWatch&) = delete;
  InterruptWatch& operator=(const InterruptWatch&) = delete;

  // The signal received, or 0.
  int received() const;
};

}  // namespace spall::cli
