#pragma once
#include <string>
#include <vector>

namespace spall::cli {

struct RunOptions {
  std::string deck;
  std::string output_dir;
  int threads = 0;
  std::vector<std::string> skip;  // physics keywords to run without (--skip)
};

// Reads, checks and runs a deck; writes the output folder. Returns the exit code.
int run_deck(const RunOptions& options);

// Reads and checks a deck, builds the problem without running it. Returns the exit code.
int check_deck(const std::string& deck, const std::vector<std::string>& skip);

}  // namespace spall::cli
