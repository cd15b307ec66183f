#include "restart_file.hpp"

#include <fmt/format.h>
#include <fstream>
#include <memory>
#include <optional>
#include <regex>

#include "spall/core/error.hpp"
#include "spall/core/version.hpp"
#include "spall/io/output/atomic_file.hpp"

namespace spall::cli {

namespace fs = std::filesystem;

namespace {
std::string file_name(int count, int k) { return count == 1 ? "runrsf" : fmt::format("runrsf{:02d}", k + 1); }

Archive opened(const fs::path& file) {
  auto in = std::make_shared<std::ifstream>(file, std::ios::binary);
  if (!*in) throw InputError(fmt::format("{}: cannot open the restart file", file.string()));
  return Archive::for_reading_from(std::move(in), fs::file_size(file), file.string());
}
}  // namespace

void RestartHeader::checkpoint(Archive& a) {
  a.section("spall restart file");
  a(version, deck, skip, step, time);
}

RestartFiles::RestartFiles(fs::path folder, int count) : folder_(std::move(folder)), count_(count) {}

fs::path RestartFiles::write(RestartHeader header, const std::function<void(Archive&)>& state, bool writes) {
  const fs::path path = folder_ / file_name(count_, next_);
  next_ = (next_ + 1) % count_;
  if (!writes) {
    Archive archive = Archive::discarding(io::output::temporary_of(path));
    archive(header);
    state(archive);
    return {};
  }
  io::output::replace_file_atomically(path, [&](std::ostream& out) {
    Archive archive = Archive::for_writing_to(out, io::output::temporary_of(path));
    archive(header);
    state(archive);
    archive.flush();
  });
  return path;
}

Restart read_newest_restart(const fs::path& folder) {
  if (!fs::is_directory(folder))
    throw InputError(fmt::format("{}: not a folder (give the output folder of the run to continue)", folder.string()));
  static const std::regex name("runrsf([0-9][0-9])?");
  // Each file's header, then the newest's state as it is read (no file is held whole).
  std::optional<Restart> newest;
  for (const auto& entry : fs::directory_iterator(folder)) {
    if (!entry.is_regular_file() || !std::regex_match(entry.path().filename().string(), name)) continue;
    Restart restart{entry.path(), {}, opened(entry.path())};
    restart.state(restart.header);
    if (!newest || restart.header.step > newest->header.step) newest.emplace(std::move(restart));
  }
  if (!newest)
    throw InputError(fmt::format("{}: no restart file (runrsf): the run wrote none (*DATABASE_BINARY_RUNRSF or "
                                 "--checkpoint-every, or an interrupted run)",
                                 folder.string()));
  if (newest->header.version != version)
    throw InputError(fmt::format("{}: written by spall {}; this is spall {}: continue it with the version that wrote it",
                                 newest->file.string(), newest->header.version, version));
  return std::move(*newest);
}

}  // namespace spall::cli
