#include "spall/core/memory.hpp"

#include <algorithm>
#include <fmt/format.h>
#include <fstream>
#include <limits>
#include <new>
#include <string>
#include <sys/mman.h>
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

namespace {
constexpr std::size_t huge_page = std::size_t(2) << 20;
// What map_pages maps for `bytes`: from a huge page on, whole huge pages.
std::size_t mapped_size(std::size_t bytes) {
  return bytes >= huge_page ? (bytes + huge_page - 1) / huge_page * huge_page : bytes;
}
}  // namespace

void* map_pages(std::size_t bytes) {
  if (bytes == 0) return nullptr;
  bytes = mapped_size(bytes);
  // From a huge page on, on huge-page boundaries with the advice to back it by huge pages (where
  // the system's transparent huge pages are "madvise" or "always"): a page fault per 2 MiB rather
  // than per 4 KiB. Buffers mapped anew at every list build cost 440 000 faults and 25 % of the
  // Taylor bar's time in 4 KiB pages on this project's virtual machine (18 us a fault).
  const std::size_t slack = bytes >= huge_page ? huge_page : 0;
  void* mapped = mmap(nullptr, bytes + slack, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (mapped == MAP_FAILED) throw std::bad_alloc();
  if (slack == 0) return mapped;
  const auto start = reinterpret_cast<std::uintptr_t>(mapped);
  const std::uintptr_t aligned = (start + huge_page - 1) / huge_page * huge_page;
  if (aligned > start) munmap(mapped, aligned - start);
  if (start + slack > aligned) munmap(reinterpret_cast<void*>(aligned + bytes), start + slack - aligned);
  madvise(reinterpret_cast<void*>(aligned), bytes, MADV_HUGEPAGE);
  return reinterpret_cast<void*>(aligned);
}

void unmap_pages(void* pages, std::size_t bytes) {
  if (pages) munmap(pages, mapped_size(bytes));
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
