#include "spall/core/first_failure.hpp"

#include <cmath>
#include <limits>
#include <span>
#include <string>
#include <vector>

namespace spall::parallel {

void throw_first_failure(std::int64_t position, const std::optional<InputError>& error, const Communicator& ranks) {
  if (ranks.size() == 1) {
    if (error) throw *error;
    return;
  }
  // The lowest position over the ranks, exact as a double below 2^53.
  double first = position < 0 ? std::numeric_limits<double>::infinity() : static_cast<double>(position);
  ranks.minimum({&first, 1});
  if (!std::isfinite(first)) return;
  // The failing rank's error as text (its file's name rather than its number in this process's
  // table), four lines, to every rank.
  std::string mine;
  if (static_cast<double>(position) == first && error) {
    mine = error->where().file.str() + '\n' + std::to_string(error->where().line) + '\n' + error->keyword() + '\n' +
           (error->keyword().empty() ? std::string(error->what()) : error->message());
  }
  const int holder = ranks.lowest(mine.empty() ? -1 : ranks.rank());
  const std::vector<char> text = ranks.all(
      std::span<const char>(ranks.rank() == holder ? mine.data() : nullptr, ranks.rank() == holder ? mine.size() : 0));
  const std::string all(text.begin(), text.end());
  const std::size_t a = all.find('\n'), b = all.find('\n', a + 1), c = all.find('\n', b + 1);
  const std::string file = all.substr(0, a), keyword = all.substr(b + 1, c - b - 1), message = all.substr(c + 1);
  if (keyword.empty()) throw InputError(message);
  throw InputError(SourceLocation{FileName(file), std::stoi(all.substr(a + 1, b - a - 1))}, keyword, message);
}

}  // namespace spall::parallel
