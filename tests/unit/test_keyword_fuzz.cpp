// The keyword reader's fuzz target in the normal build: its entry (fuzz/deck_check.cpp) compiled by
// GCC, without libFuzzer. Every seed, corpus input and regression either reads and builds (the
// solver's set-up, which the libFuzzer target leaves out) or fails with a one-line InputError, and a
// short deterministic mutation run over the seeds does the same. The
// long libFuzzer run (make fuzz, docs/RELIABILITY.md) explores far more; this keeps what it found.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <random>
#include <string>
#include <vector>

#include "deck_check.hpp"
#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "spall/core/memory.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/problem.hpp"

namespace spall::fuzz {
namespace {

namespace fs = std::filesystem;

const fs::path source_dir = SPALL_SOURCE_DIR;

std::string file_text(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

// The files under `folder`, sorted; with `decks_only`, the `.k` files only.
std::vector<fs::path> files_under(const fs::path& folder, bool decks_only) {
  std::vector<fs::path> files;
  if (!fs::is_directory(folder)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(folder))
    if (entry.is_regular_file() && (!decks_only || entry.path().extension() == ".k")) files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  return files;
}

// Where the line holding position `at` starts.
std::size_t line_start(const std::string& text, std::size_t at) {
  const std::size_t newline = at == 0 ? std::string::npos : text.rfind('\n', at - 1);
  return newline == std::string::npos ? 0 : newline + 1;
}

enum class Outcome { read, input_error, bug };

// What the fuzz target makes of `input`, and then the problem's set-up as `spall check` builds it
// (every formulation's, rigid body's and contact's; the libFuzzer target stops at the reader's
// checks); `what` says why for an error.
Outcome check(const std::string& input, std::string& what) {
  try {
    check_deck_text(input);
    log::set_quiet(true);  // the set-up's notes, thousands of times
    solver::build_problem(io::keyword::read_deck_text(input, "fuzz.k"));
    return Outcome::read;
  } catch (const InputError& error) {
    what = error.what();
    // The promise is one line, `file:line: *KEYWORD: what is wrong`.
    return what.find('\n') == std::string::npos ? Outcome::input_error : Outcome::bug;
  } catch (const std::exception& error) {
    what = std::string("not an InputError: ") + error.what();
  } catch (...) {
    what = "not an InputError: an exception of another type";
  }
  return Outcome::bug;
}

// The input for a failure message: its first 400 bytes, control characters escaped.
std::string shown(const std::string& input) {
  std::string text;
  for (char c : input.substr(0, 400)) {
    constexpr const char* hex = "0123456789abcdef";
    const auto byte = static_cast<unsigned char>(c);
    if (c == '\n') text += "\\n";
    else if (byte < 32 || byte > 126) text += std::string{'\\', 'x', hex[byte / 16], hex[byte % 16]};
    else text += c;
  }
  return text + (input.size() > 400 ? "..." : "");
}

// The libFuzzer dictionary's tokens: lines `name="value"` with \xNN escapes.
std::vector<std::string> dictionary_tokens() {
  std::vector<std::string> tokens;
  std::ifstream in(source_dir / "fuzz/keywords.dict");
  for (std::string line; std::getline(in, line);) {
    const std::size_t open = line.find('"');
    if (line.empty() || line[0] == '#' || open == std::string::npos || line.back() != '"') continue;
    std::string token;
    for (std::size_t i = open + 1; i + 1 < line.size(); ++i) {
      if (line[i] == '\\' && i + 3 < line.size() && line[i + 1] == 'x') {
        token += static_cast<char>(std::stoi(line.substr(i + 2, 2), nullptr, 16));
        i += 3;
      } else if (line[i] == '\\' && i + 2 < line.size()) {
        token += line[++i];
      } else {
        token += line[i];
      }
    }
    tokens.push_back(token);
  }
  return tokens;
}

// Each test runs in an empty folder of its own, as the fuzzer does: a fuzzed *INCLUDE then finds
// nothing, and the same memory budget as the fuzz target refuses large generations fast.
class KeywordFuzz : public ::testing::Test {
 protected:
  void SetUp() override {
    previous_ = fs::current_path();
    folder_ = fs::path(::testing::TempDir()) / ("spall_keyword_fuzz_" + std::to_string(::getpid()));
    fs::remove_all(folder_);
    fs::create_directories(folder_);
    fs::current_path(folder_);
    memory::set_limit(16'000'000);
  }
  void TearDown() override {
    memory::set_limit(0);
    fs::current_path(previous_);
    fs::remove_all(folder_);
  }

  // Every deck of the repository (and of the shared decks beside it) and fuzz/seeds.
  static std::vector<fs::path> seed_files() {
    std::vector<fs::path> files;
    for (const fs::path& folder : {source_dir / "examples", source_dir / "bench", source_dir / "tests",
                                   fs::path(SPALL_SHARED_DIR) / "decks"}) {
      const auto decks = files_under(folder, true);
      files.insert(files.end(), decks.begin(), decks.end());
    }
    const auto seeds = files_under(source_dir / "fuzz/seeds", false);
    files.insert(files.end(), seeds.begin(), seeds.end());
    return files;
  }

 private:
  fs::path previous_;
  fs::path folder_;
};

TEST_F(KeywordFuzz, EverySeedAndCorpusInputReadsOrFailsWithOneLine) {
  std::vector<fs::path> files = seed_files();
  const auto corpus = files_under(source_dir / "fuzz/corpus", false);
  files.insert(files.end(), corpus.begin(), corpus.end());
  ASSERT_GE(files.size(), 15u);  // the examples and fuzz/seeds at least, in a clone without ../shared
  for (const fs::path& file : files) {
    std::string what;
    EXPECT_NE(check(file_text(file), what), Outcome::bug) << file << ": " << what;
  }
}

// Each was a crash, a hang or a giant allocation before its fix; each is bad input.
TEST_F(KeywordFuzz, EveryRegressionFailsWithInputError) {
  const auto files = files_under(source_dir / "fuzz/regressions", false);
  ASSERT_GE(files.size(), 10u);
  for (const fs::path& file : files) {
    std::string what;
    EXPECT_EQ(check(file_text(file), what), Outcome::input_error) << file << ": " << what;
    EXPECT_EQ(what.rfind("fuzz.k", 0), 0u) << file << ": " << what;
  }
}

// A short, fixed-seed run of the kinds of mutation libFuzzer makes (bit flips, inserted and erased
// bytes, dictionary tokens, lines spliced from other seeds, extreme numbers) over the seeds cut to
// the fuzz run's 4096 bytes. The same inputs every time, so a failure here can be replayed.
TEST_F(KeywordFuzz, TwentyThousandMutatedDecksReadOrFailWithOneLine) {
  constexpr std::size_t max_length = 4096;
  std::vector<std::string> seeds;
  std::vector<std::string> lines;
  for (const fs::path& file : seed_files()) {
    std::string text = file_text(file);
    if (text.size() > max_length) text.resize(text.rfind('\n', max_length) + 1);
    for (std::size_t start = 0, end; start < text.size(); start = end + 1) {
      end = std::min(text.find('\n', start), text.size());
      lines.push_back(text.substr(start, end - start + 1));
    }
    seeds.push_back(std::move(text));
  }
  const std::vector<std::string> tokens = dictionary_tokens();
  ASSERT_GT(tokens.size(), 80u);
  const std::vector<std::string> extremes = {"0",     "-1",   "1e308", "1e400",  "-1e308", "9223372036854775807",
                                             "-inf",  "nan",  "1.5",   "1e-320", "2147483648", "&x",
                                             "-&x",   ",",    "$",     "*END",   "+",    "          "};
  std::mt19937_64 random(36);  // issue 36
  const auto pick = [&](std::size_t n) { return std::uniform_int_distribution<std::size_t>(0, n - 1)(random); };

  int read = 0;
  int refused = 0;
  for (int n = 0; n < 20'000; ++n) {
    std::string input = seeds[pick(seeds.size())];
    const std::size_t mutations = 1 + pick(4);
    for (std::size_t m = 0; m < mutations; ++m) {
      const std::size_t at = input.empty() ? 0 : pick(input.size() + 1);
      switch (pick(7)) {
        case 0:
          if (!input.empty()) input[std::min(at, input.size() - 1)] ^= static_cast<char>(1 << pick(8));
          break;
        case 1: input.insert(at, 1, static_cast<char>(pick(256))); break;
        case 2: input.erase(std::min(at, input.size()), 1 + pick(16)); break;
        case 3: input.insert(at, tokens[pick(tokens.size())]); break;
        case 4: input.insert(line_start(input, at), lines[pick(lines.size())]); break;
        case 5: {  // a number or blank field becomes an extreme value
          const std::size_t field = at - at % 10;
          input.replace(std::min(field, input.size()), 10, extremes[pick(extremes.size())]);
          break;
        }
        case 6: {  // a line of another seed replaces one
          const std::size_t start = line_start(input, at);
          const std::size_t end = std::min(input.find('\n', at), input.size());
          input.replace(start, end - start + (end < input.size()), lines[pick(lines.size())]);
          break;
        }
      }
    }
    if (input.size() > max_length) input.resize(max_length);
    std::string what;
    const Outcome outcome = check(input, what);
    ASSERT_NE(outcome, Outcome::bug) << "input " << n << ": " << what << "\n" << shown(input);
    (outcome == Outcome::read ? read : refused)++;
  }
  // Both answers must occur, or the run tests nothing: mutated decks that still read, and refusals.
  EXPECT_GT(read, 100);
  EXPECT_GT(refused, 1000);
}

}  // namespace
}  // namespace spall::fuzz
