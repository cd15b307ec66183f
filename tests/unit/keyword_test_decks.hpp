#pragma once
// Small decks written to a fresh temporary folder per test, for the keyword reader's tests.
#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <string>
#include <vector>

#include "spall/core/error.hpp"
#include "spall/io/keyword/reader.hpp"

namespace spall::test {

class DeckFolder {
 public:
  DeckFolder() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    folder_ = std::filesystem::path(::testing::TempDir()) /
              ("spall_keyword_" + std::string(info->test_suite_name()) + "_" + info->name() + "_" +
               std::to_string(::getpid()));
    std::filesystem::remove_all(folder_);
    std::filesystem::create_directories(folder_);
  }
  ~DeckFolder() { std::filesystem::remove_all(folder_); }

  std::filesystem::path write(const std::string& name, const std::string& text) const {
    const auto path = folder_ / name;
    std::filesystem::create_directories(path.parent_path());
    std::ofstream(path, std::ios::binary) << text;
    return path;
  }
  const std::filesystem::path& path() const { return folder_; }

 private:
  std::filesystem::path folder_;
};

// One fixed-format card: each value right-justified in its field (10 characters unless given).
inline std::string row(std::initializer_list<std::string> values,
                       std::initializer_list<int> widths = {}) {
  std::string line;
  auto width = widths.begin();
  for (const auto& value : values) {
    const std::size_t w = width != widths.end() ? static_cast<std::size_t>(*width++) : 10;
    line += std::string(w > value.size() ? w - value.size() : 0, ' ') + value;
  }
  return line + "\n";
}

// *SET_NODE_LIST `sid` with the nodes `ids`, eight to a line.
inline std::string node_list(Id sid, const std::vector<Id>& ids) {
  std::string text = "*SET_NODE_LIST\n" + row({std::to_string(sid)});
  for (std::size_t k = 0; k < ids.size(); k += 8) {
    std::string line;
    for (std::size_t j = k; j < std::min(k + 8, ids.size()); ++j) {
      const std::string id = std::to_string(ids[j]);
      line += std::string(10 - std::min<std::size_t>(10, id.size()), ' ') + id;
    }
    text += line + "\n";
  }
  return text;
}

// The message of the InputError that `action` throws ("" if it throws none).
template <class Action>
std::string input_error_of(Action&& action) {
  try {
    action();
  } catch (const InputError& error) {
    return error.what();
  }
  return "";
}

// The start of an error message at `line` of the folder's bad.k: "path:line: *KEYWORD: ".
inline std::string prefix(const DeckFolder& folder, int line, const std::string& keyword) {
  return (folder.path() / "bad.k").lexically_normal().string() + ":" + std::to_string(line) + ": " + keyword + ": ";
}

// The InputError message of reading `text` as bad.k, and of validating what it reads.
inline std::string read_error(const DeckFolder& folder, const std::string& text) {
  const auto path = folder.write("bad.k", text);
  return input_error_of([&] { io::keyword::read_deck(path); });
}
inline std::string validate_error(const DeckFolder& folder, const std::string& text) {
  const auto model = io::keyword::read_deck(folder.write("bad.k", text));
  return input_error_of([&] { io::keyword::validate(model); });
}

}  // namespace spall::test
