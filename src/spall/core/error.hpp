#pragma once
// Errors with context. Bad input is an InputError: one line `file:line: *KEYWORD: what is wrong`,
// exit code 2. A run that goes numerically unstable is an InstabilityError, exit code 3. An output
// file that cannot be written (a full disk, no permission) is an OutputError, exit code 4.
#include <cstdint>
#include <stdexcept>
#include <string>
#include <string_view>

namespace spall {

// 1: an internal error (a bug in Spall, reported with what failed rather than an abort).
enum ExitCode : int { exit_success = 0, exit_internal = 1, exit_bad_input = 2, exit_unstable = 3, exit_output = 4 };

// The name of a file input was read from, as messages give it, held once for the life of the
// process: every node and element of a deck remembers where it was read, and a copy of the name in
// each would weigh more than the node itself (a million-particle deck read from a long path: 150 MB).
// A FileName is the name's number in the process's table (4 B, so that a location is 8 B).
class FileName {
 public:
  FileName() = default;  // not from a file
  // Implicit, so that a name given as text is a FileName: each looks the name up in the process's
  // table, so a reader makes one per file and copies it.
  FileName(std::string_view name);
  FileName(const std::string& name) : FileName(std::string_view(name)) {}
  FileName(const char* name) : FileName(std::string_view(name)) {}
  const std::string& str() const;
  bool empty() const { return number_ == 0; }

 private:
  std::uint32_t number_ = 0;  // 0: none; else the name's place in the table, from 1
};

// Where something was read: a file and a 1-based line number (0 when not from a file).
struct SourceLocation {
  FileName file;
  int line = 0;
};

// "file:line".
std::string to_string(const SourceLocation& where);

class InputError : public std::runtime_error {
 public:
  InputError(SourceLocation where, std::string keyword, std::string message);
  // A model-level error with no single line (e.g. a missing *CONTROL_TERMINATION).
  explicit InputError(std::string message);

  const SourceLocation& where() const { return where_; }
  const std::string& keyword() const { return keyword_; }
  const std::string& message() const { return message_; }

 private:
  SourceLocation where_;
  std::string keyword_;
  std::string message_;
};

// Stops the set-up at a card: throws InputError(where, keyword, message). For the code that turns
// the model into formulations and refuses, at the card's line, what the solver cannot run.
[[noreturn]] void fail_at(const SourceLocation& where, const std::string& keyword, const std::string& message);

class InstabilityError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// "cannot write PATH: why". Every output file is written whole or not at all (io/output), so the
// files written before stay complete. Under MPI, `every_rank` when every rank throws it alike (they
// agreed on it by a reduction) and all end with it; any other is one rank's, and ends the whole job
// at once (apps/spall/main.cpp) rather than leave the other ranks waiting for it.
class OutputError : public std::runtime_error {
 public:
  explicit OutputError(const std::string& what, bool every_rank = false)
      : std::runtime_error(what), every_rank_(every_rank) {}
  bool every_rank() const { return every_rank_; }

 private:
  bool every_rank_ = false;
};

}  // namespace spall
