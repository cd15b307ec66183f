#include "spall/core/memory.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <string>
#include <sys/resource.h>

namespace spall::memory {

namespace {

// The first number on the line of /proc/meminfo that starts with `key`, in bytes (the file says kB).
std::uint64_t meminfo(const std::string& key) {
  std::ifstream in("/proc/meminfo");
  std::string name;
  std::uint64_t kilobytes = 0;
  std::string unit;
  while (in >> name >> kilobytes >> unit)
    if (name == key) return kilobytes * 1024;
  return std::numeric_limits<std::uint64_t>::max();
}

// A cgroup v2 file holding one number ("max" when unlimited).
std::uint64_t cgroup_value(const char* path) {
  std::ifstream in(path);
  std::string text;
  if (!(in >> text) || text == "max") return std::numeric_limits<std::uint64_t>::max();
  try {
    return std::stoull(text);
  } catch (...) {
    return std::numeric_limits<std::uint64_t>::max();
  }
}

std::uint64_t limit_set = 0;

}  // namespace

void set_limit(std::uint64_t bytes) { limit_set = bytes; }

std::uint64_t available_bytes() {
  std::uint64_t available = meminfo("MemAvailable:");
  if (limit_set > 0) available = std::min(available, limit_set);
  const std::uint64_t limit = cgroup_value("/sys/fs/cgroup/memory.max");
  if (limit != std::numeric_limits<std::uint64_t>::max()) {
    const std::uint64_t used = std::min(limit, cgroup_value("/sys/fs/cgroup/memory.current"));
    available = std::min(available, limit - used);
  }
  return available;
}

std::uint64_t peak_resident_bytes() {
  rusage usage{};
  if (getrusage(RUSAGE_SELF, &usage) != 0) return 0;
  return static_cast<std::uint64_t>(usage.ru_maxrss) * 1024;  // Linux counts kilobytes
}

std::string human_bytes(double bytes) {
  const char* units[] = {"B", "kB", "MB", "GB", "TB", "PB", "EB"};
  int u = 0;
  while (bytes >= 1000 && u < 6) {
    bytes /= 1000;
    ++u;
  }
  return fmt::format("{:.3g} {}", bytes, units[u]);
}

std::string shortfall(double count, double bytes_each, const std::string& what) {
  const double needed = count * bytes_each;
  const double available = static_cast<double>(available_bytes());
  if (needed <= available) return {};
  return fmt::format("{:.4g} {} need about {} ({} each); this machine has {} available", count, what,
                     human_bytes(needed), human_bytes(bytes_each), human_bytes(available));
}

}  // namespace spall::memory
