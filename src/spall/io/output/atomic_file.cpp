#include "spall/io/output/atomic_file.hpp"

#include <cerrno>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "spall/core/error.hpp"

namespace spall::io::output {

std::filesystem::path temporary_of(const std::filesystem::path& path) {
  // Same directory as the target, so that the rename stays on one file system and is atomic.
  std::filesystem::path temporary = path;
  temporary += ".tmp";
  return temporary;
}

void replace_file_atomically(const std::filesystem::path& path,
                             const std::function<void(std::ostream&)>& write_contents) {
  const std::filesystem::path temporary = temporary_of(path);
  const auto fail = [&](const std::string& why) {
    std::error_code ignored;
    std::filesystem::remove(temporary, ignored);
    throw OutputError(fmt::format("cannot write {}: {}", path.string(), why));
  };

  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) fail(std::strerror(errno));
    try {
      write_contents(out);
    } catch (...) {
      out.close();
      std::error_code ignored;
      std::filesystem::remove(temporary, ignored);
      throw;
    }
    out.close();  // flushes: a full disk shows here, errno ENOSPC
    if (!out) fail(std::strerror(errno));
  }

  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) fail(error.message());
}

}  // namespace spall::io::output
