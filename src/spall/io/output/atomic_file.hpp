#pragma once
// Output files that are either whole or absent: written beside the target under a temporary name
// and renamed over it, so that a reader (ParaView, a post-processing script, a crashed run's
// user) never sees half a file.
#include <filesystem>
#include <functional>
#include <ostream>

namespace spall::io::output {

// The temporary `path` is written as before it is renamed (`path`.tmp).
std::filesystem::path temporary_of(const std::filesystem::path& path);

// Calls write_contents on a binary stream to temporary_of(path), then renames it to `path`.
// Throws OutputError naming `path` if any step fails; the temporary is then removed.
void replace_file_atomically(const std::filesystem::path& path,
                             const std::function<void(std::ostream&)>& write_contents);

}  // namespace spall::io::output
