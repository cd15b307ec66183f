#pragma once
#include <string>

namespace spall::cli {

struct RunOptions {
  std::string deck;
  std::string output_dir;
  int threads = 0;
};

// Reads, checks and runs a deck; writes the output folder. Returns the exit code.
int run_deck(const RunOptions& options);

// Reads and checks a deck, builds the problem without running it. Returns the exit code.
int check_deck(const std::string& deck);

}  // namespace spall::cli
