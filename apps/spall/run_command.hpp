#pragma once
#include <string>
#include <vector>

namespace spall::cli {

struct RunOptions {
  std::string deck;
  std::string output_dir;
  int threads = 0;
  std::vector<std::string> skip;  // physics keywords to run without (--skip)
  std::string restart_dir;        // --restart: continue the run of this output folder
  long long checkpoint_every = 0;  // --checkpoint-every: steps between restart files (0: the deck's)
  // Under MPI (solver::LoadBalance): steps between checks of the ranks' work (--balance-every), and
  // the excess of the busiest rank over the mean that deals the nodes anew (--balance-threshold).
  long long balance_every = 100;
  double balance_threshold = 0.1;
};

// Reads, checks and runs a deck, or continues a run from its restart file; writes the output
// folder. Returns the exit code.
int run_deck(const RunOptions& options);

// Reads and checks a deck, builds the problem without running it. Returns the exit code.
int check_deck(const std::string& deck, const std::vector<std::string>& skip);

}  // namespace spall::cli
