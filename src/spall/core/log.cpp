#include "spall/core/log.hpp"

#include <atomic>
#include <cstdio>

namespace spall::log {

namespace {
std::atomic<bool> quiet_flag{false};

void emit(std::string_view prefix, std::string_view message) {
  fmt::print(stderr, "{}{}\n", prefix, message);
  std::fflush(stderr);
}
}  // namespace

void info(std::string_view message) {
  if (!quiet_flag.load(std::memory_order_relaxed)) emit("", message);
}
void warning(std::string_view message) { emit("warning: ", message); }
void error(std::string_view message) { emit("error: ", message); }
void set_quiet(bool quiet) { quiet_flag.store(quiet, std::memory_order_relaxed); }

}  // namespace spall::log
