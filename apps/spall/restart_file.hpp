#pragma once
// Running restart files (*DATABASE_BINARY_RUNRSF, `spall run --checkpoint-every`): the state of a
// run between two steps, written atomically, NR files in turn (runrsf, or runrsf01 ... runrsfNN),
// read back by `spall run --restart DIR` from the newest one. A file is a header (this version of
// Spall, the deck's name in DIR/deck, the step and time) and the archive of the run's state
// (core/archive.hpp).
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "spall/core/archive.hpp"

namespace spall::cli {

struct RestartHeader {
  std::string version;
  std::string deck;  // the deck's path in the output folder's deck/ copy
  std::vector<std::string> skip;  // --skip of the run
  long long step = 0;
  double time = 0;

  void checkpoint(Archive& a);
};

class RestartFiles {
 public:
  RestartFiles(std::filesystem::path folder, int count);
  // The next file in turn, through a temporary file renamed over it: a run killed while it is
  // written keeps the file before. Returns the file's path. Under MPI every rank calls it: rank 0
  // (`writes`) writes the file as the archive fills (what state() writes is not held whole), the
  // others' state() calls write their pieces into it at their places (core/pieces.hpp) and keep
  // nothing else, and return an empty path.
  std::filesystem::path write(RestartHeader header, const std::function<void(Archive&)>& state, bool writes = true);

 private:
  std::filesystem::path folder_;
  int count_;
  int next_ = 0;
};

struct Restart {
  std::filesystem::path file;
  RestartHeader header;
  Archive state;  // positioned after the header
};

// The newest restart file (the largest step) in `folder`. InputError when there is none, or when
// it was written by another version of Spall.
Restart read_newest_restart(const std::filesystem::path& folder);

}  // namespace spall::cli
