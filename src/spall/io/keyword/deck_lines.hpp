#pragma once
// Reading one deck file into keyword blocks: a keyword line (`*` in column 1) and the data lines
// that follow it up to the next keyword. `$` lines are comments; `*END` ends the file.
#include <filesystem>
#include <string>
#include <string_view>
#include <vector>

#include "spall/core/error.hpp"

namespace spall::io::keyword {

// One data line of a keyword block, as a view into the file's text (no trailing CR/LF).
struct DataLine {
  std::string_view text;
  int line = 0;
};

// Field width a keyword line asks for: a `+` after the name forces 20-character fields, a `-`
// forces the standard width, whatever *KEYWORD LONG= said.
enum class WidthOverride { none, long_fields, standard_fields };

struct KeywordBlock {
  std::string name;             // upper case, without `*`, without a `+`/`-` suffix or trailing text
  std::string_view trailing;    // text after the name on the keyword line (e.g. `LONG=Y`)
  WidthOverride width = WidthOverride::none;
  FileName file;  // the file as named in messages
  int line = 0;
  std::vector<DataLine> data;
};

// A deck file read into memory; the blocks' views point into it, so it must outlive them.
class DeckFile {
 public:
  // Returns false when the file cannot be read.
  bool load(const std::filesystem::path& path);
  // Takes `text` as the content of the file at `path` (which need not exist): a deck held in memory.
  void assign(std::string text, const std::filesystem::path& path);

  const std::string& name() const { return name_.str(); }
  const std::filesystem::path& path() const { return path_; }
  // Where the first NUL byte is, std::string::npos if none: a keyword file is text, so a NUL
  // says the file is something else (an executable, a d3plot, an archive).
  std::size_t first_nul() const { return text_.find('\0'); }

  // Calls `on_block(const KeywordBlock&)` for each keyword block in order, up to `*END`. Lines
  // before the first keyword are ignored, as LS-DYNA ignores them. The block is reused between
  // calls, so that its data vector keeps its capacity.
  template <class OnBlock>
  void for_each_block(OnBlock&& on_block) const;

 private:
  static void start_block(std::string_view keyword_line, KeywordBlock& block);

  std::filesystem::path path_;
  FileName name_;
  std::string text_;
};

template <class OnBlock>
void DeckFile::for_each_block(OnBlock&& on_block) const {
  KeywordBlock block;
  block.file = name_;
  bool in_block = false;
  std::string_view rest = text_;
  int line_number = 0;
  while (!rest.empty()) {
    const std::size_t end = rest.find('\n');
    std::string_view line = rest.substr(0, end);
    rest = end == std::string_view::npos ? std::string_view{} : rest.substr(end + 1);
    ++line_number;
    if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
    if (!line.empty() && line.front() == '$') continue;
    if (!line.empty() && line.front() == '*') {
      if (in_block) on_block(static_cast<const KeywordBlock&>(block));
      start_block(line, block);
      block.line = line_number;
      block.data.clear();
      if (block.name == "END") return;
      in_block = true;
      continue;
    }
    if (in_block) block.data.push_back({line, line_number});
  }
  if (in_block) on_block(static_cast<const KeywordBlock&>(block));
}

}  // namespace spall::io::keyword
