#include "spall/core/communicator.hpp"

#include <algorithm>
#include <cstdlib>
#include <stdexcept>
#include <string>
#include <vector>

#ifdef SPALL_WITH_MPI
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#endif

namespace spall::parallel {
namespace {

Communicator& the_world() {
  static Communicator world;
  return world;
}

#ifdef SPALL_WITH_MPI
bool mpi_started = false;

void check(int status, const char* what) {
  if (status != MPI_SUCCESS) throw std::runtime_error(std::string("MPI: ") + what + " failed");
}

// Adds the seconds of its lifetime to `total`: the time a collective spends, waiting included.
class Stopwatch {
 public:
  explicit Stopwatch(double& total) : total_(total), start_(MPI_Wtime()) {}
  ~Stopwatch() { total_ += MPI_Wtime() - start_; }
  Stopwatch(const Stopwatch&) = delete;
  Stopwatch& operator=(const Stopwatch&) = delete;

 private:
  double& total_;
  double start_;
};
#endif

}  // namespace

int launched_ranks() {
  for (const char* name : {"OMPI_COMM_WORLD_SIZE", "PMI_SIZE"})
    if (const char* value = std::getenv(name)) {
      char* end = nullptr;
      const long ranks = std::strtol(value, &end, 10);
      if (end != value && *end == '\0' && ranks > 0 && ranks <= (1L << 30)) return static_cast<int>(ranks);
    }
  return 1;
}

#ifdef SPALL_WITH_MPI

bool built_with_mpi() { return true; }

Session::Session() {
  if (launched_ranks() <= 1) return;
  int provided = 0;
  check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
  mpi_started = true;
  if (provided < MPI_THREAD_FUNNELED) throw std::runtime_error("MPI: the library does not support MPI_THREAD_FUNNELED");
  Communicator& world = the_world();
  check(MPI_Comm_rank(MPI_COMM_WORLD, &world.rank_), "MPI_Comm_rank");
  check(MPI_Comm_size(MPI_COMM_WORLD, &world.size_), "MPI_Comm_size");
}

Session::~Session() {
  if (!mpi_started) return;
  MPI_Finalize();
  mpi_started = false;
  the_world() = Communicator{};
}

void Communicator::abort(int code) const {
  if (size_ > 1) MPI_Abort(MPI_COMM_WORLD, code);
}

void Communicator::minimum(std::span<double> values) const {
  if (size_ == 1 || values.empty()) return;
  const Stopwatch stopwatch(communicating_);
  check(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_DOUBLE, MPI_MIN,
                      MPI_COMM_WORLD),
        "MPI_Allreduce (minimum)");
}

void Communicator::sum(std::span<std::int64_t> values) const {
  if (size_ == 1 || values.empty()) return;
  const Stopwatch stopwatch(communicating_);
  check(MPI_Allreduce(MPI_IN_PLACE, values.data(), static_cast<int>(values.size()), MPI_INT64_T, MPI_SUM,
                      MPI_COMM_WORLD),
        "MPI_Allreduce (sum)");
}

// Each sum's chunks, normalized (each below 2^32 but the signed top one), added as integers: with
// fewer than 2^31 ranks no chunk overflows. The non-finite flags travel in a bitwise or (a sum
// would carry one flag into the next).
void Communicator::sum(std::span<ExactSum> sums) const {
  if (size_ == 1 || sums.empty()) return;
  constexpr int n = ExactSum::chunk_count;
  std::vector<std::int64_t> chunks(sums.size() * n);
  std::vector<std::uint32_t> special(sums.size());
  for (std::size_t s = 0; s < sums.size(); ++s) {
    sums[s].normalize();
    std::copy(sums[s].chunks().begin(), sums[s].chunks().end(), chunks.begin() + s * n);
    special[s] = sums[s].special();
  }
  sum(chunks);
  {
    const Stopwatch stopwatch(communicating_);
    check(MPI_Allreduce(MPI_IN_PLACE, special.data(), static_cast<int>(special.size()), MPI_UINT32_T, MPI_BOR,
                        MPI_COMM_WORLD),
          "MPI_Allreduce (flags)");
  }
  for (std::size_t s = 0; s < sums.size(); ++s) {
    std::copy(chunks.begin() + s * n, chunks.begin() + (s + 1) * n, sums[s].chunks().begin());
    sums[s].special() = special[s];
  }
}

// Counts and displacements in items (Index, as MPI's int), with an item as one contiguous type.
void Communicator::share_bytes(std::byte* items, std::size_t item_bytes, std::span<const Index> offsets) const {
  if (size_ == 1) return;
  const Stopwatch stopwatch(communicating_);
  std::vector<int> counts(size_), displacements(size_);
  for (int r = 0; r < size_; ++r) {
    displacements[r] = offsets[r];
    counts[r] = offsets[r + 1] - offsets[r];
    if (r != rank_) received_bytes_ += std::int64_t(counts[r]) * std::int64_t(item_bytes);
  }
  MPI_Datatype item;
  check(MPI_Type_contiguous(static_cast<int>(item_bytes), MPI_BYTE, &item), "MPI_Type_contiguous");
  check(MPI_Type_commit(&item), "MPI_Type_commit");
  const int status = MPI_Allgatherv(MPI_IN_PLACE, 0, MPI_DATATYPE_NULL, items, counts.data(), displacements.data(),
                                    item, MPI_COMM_WORLD);
  MPI_Type_free(&item);
  check(status, "MPI_Allgatherv");
}

void Communicator::exchange_bytes(const std::byte* send, std::byte* receive, std::size_t item_bytes,
                                  std::span<const Index> send_offsets, std::span<const Index> receive_offsets) const {
  if (size_ == 1) return;
  const Stopwatch stopwatch(communicating_);
  std::vector<int> send_counts(size_), send_displacements(size_), receive_counts(size_), receive_displacements(size_);
  for (int r = 0; r < size_; ++r) {
    send_displacements[r] = send_offsets[r];
    send_counts[r] = send_offsets[r + 1] - send_offsets[r];
    receive_displacements[r] = receive_offsets[r];
    receive_counts[r] = receive_offsets[r + 1] - receive_offsets[r];
    if (r != rank_) received_bytes_ += std::int64_t(receive_counts[r]) * std::int64_t(item_bytes);
  }
  MPI_Datatype item;
  check(MPI_Type_contiguous(static_cast<int>(item_bytes), MPI_BYTE, &item), "MPI_Type_contiguous");
  check(MPI_Type_commit(&item), "MPI_Type_commit");
  const int status = MPI_Alltoallv(send, send_counts.data(), send_displacements.data(), item, receive,
                                   receive_counts.data(), receive_displacements.data(), item, MPI_COMM_WORLD);
  MPI_Type_free(&item);
  check(status, "MPI_Alltoallv");
}

#else

bool built_with_mpi() { return false; }
void Communicator::share_bytes(std::byte*, std::size_t, std::span<const Index>) const {}
void Communicator::exchange_bytes(const std::byte*, std::byte*, std::size_t, std::span<const Index>,
                                  std::span<const Index>) const {}
Session::Session() = default;
Session::~Session() = default;
void Communicator::abort(int) const {}
void Communicator::minimum(std::span<double>) const {}
void Communicator::sum(std::span<std::int64_t>) const {}
void Communicator::sum(std::span<ExactSum>) const {}

#endif

const Communicator& world() { return the_world(); }

}  // namespace spall::parallel
