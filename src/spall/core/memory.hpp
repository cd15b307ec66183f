#pragma once
// How much memory this process may still take, so that a deck asking for more (a mesh box or an
// NEND generation of 10^12 particles) is refused with a message before it allocates, instead of
// being killed by the kernel's out-of-memory killer halfway; how much it has held; and pages of
// its own for buffers that must give their memory back when freed (MappedBuffer).
#include <cstddef>
#include <cstdint>
#include <string>

namespace spall::memory {

// Bytes this process can still allocate: the machine's MemAvailable (/proc/meminfo), or less when
// a cgroup (a container, a batch scheduler's job) limits the process (memory.max less
// memory.current, cgroup v2), or set_limit's. The largest uint64 when none is known.
std::uint64_t available_bytes();

// A lower bound of the caller's on available_bytes() (`spall run --memory-limit`); 0: none.
void set_limit(std::uint64_t bytes);

// The most this process has held in memory so far (its peak resident set, getrusage's maxrss).
std::uint64_t peak_resident_bytes();

// `bytes` of anonymous pages of their own (zero, resident only once written; mmap; huge pages from
// 2 MiB on where the system grants them), for MappedBuffer and UninitializedAllocator; throws
// std::bad_alloc when the system refuses. unmap_pages(pages, the same bytes) gives them back.
void* map_pages(std::size_t bytes);
void unmap_pages(void* pages, std::size_t bytes);

// "12.3 GB": bytes for a message, in decimal units.
std::string human_bytes(double bytes);

// Null when `count` items of `bytes_each` fit in available_bytes(); else the reason, for the
// caller's error at its card: "N particles need about X; this machine has Y available".
std::string shortfall(double count, double bytes_each, const std::string& what);

}  // namespace spall::memory
