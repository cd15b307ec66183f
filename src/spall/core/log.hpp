#pragma once
// Messages to the user. Everything goes to stderr so that stdout stays clean for data.
#include <string_view>

#include <fmt/core.h>

namespace spall::log {

void info(std::string_view message);
void warning(std::string_view message);
void error(std::string_view message);

// When quiet, info() prints nothing (tests, benchmarks); warnings and errors always print.
void set_quiet(bool quiet);

}  // namespace spall::log
