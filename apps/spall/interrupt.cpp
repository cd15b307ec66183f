#include "interrupt.hpp"

#include <csignal>

namespace spall::cli {

namespace {

volatile std::sig_atomic_t received_signal = 0;

// Only a flag: the run looks at it between steps. SA_RESETHAND puts the default action back, so
// the next signal ends the process.
extern "C" void note_signal(int signal) { received_signal = signal; }

struct sigaction previous_int, previous_term;

}  // namespace

InterruptWatch::InterruptWatch() {
  received_signal = 0;
  struct sigaction action {};
  action.sa_handler = note_signal;
  sigemptyset(&action.sa_mask);
  action.sa_flags = SA_RESETHAND | SA_RESTART;
  sigaction(SIGINT, &action, &previous_int);
  sigaction(SIGTERM, &action, &previous_term);
}

InterruptWatch::~InterruptWatch() {
  sigaction(SIGINT, &previous_int, nullptr);
  sigaction(SIGTERM, &previous_term, nullptr);
}

int InterruptWatch::received() const { return received_signal; }

}  // namespace spall::cli
