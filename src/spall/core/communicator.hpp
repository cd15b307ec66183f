#pragma once
// The processes of one run (MPI ranks) and the collective operations the step needs from them
// (docs/SCALING.md). Physics never names MPI: it asks the communicator for a global minimum or an
// exact sum, and a run of one process gets the same answers without MPI. Built with MPI
// (SPALL_MPI, the default), the run's communicator is MPI_COMM_WORLD when an MPI launcher started
// the process as one of several; otherwise it is this process alone.
#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <numeric>
#include <span>
#include <vector>

#include "spall/core/exact_sum.hpp"
#include "spall/core/types.hpp"

namespace spall::parallel {

// How many processes an MPI launcher started this one among (Open MPI's mpirun, and the PMI of
// MPICH, Intel MPI and Slurm's srun, say so in the environment), 1 when none did.
int launched_ranks();

// Whether this build can run as several ranks.
bool built_with_mpi();

// The first of rank `rank`'s items when `count` items are dealt to `ranks` ranks in contiguous
// blocks of sizes differing by at most one (rank == ranks gives count).
inline Index block_begin(Index count, int rank, int ranks) {
  return static_cast<Index>(static_cast<long double>(count) * rank / ranks);
}
// Every rank's first item, and count at the end (ranks + 1 entries).
inline std::vector<Index> block_offsets(Index count, int ranks) {
  std::vector<Index> offsets(ranks + 1);
  for (int r = 0; r <= ranks; ++r) offsets[r] = block_begin(count, r, ranks);
  return offsets;
}

class Communicator {
 public:
  int rank() const { return rank_; }
  int size() const { return size_; }

  // Ends every rank of the job now with exit code `code` (MPI_Abort): for an error one rank found
  // alone, which the others, waiting in a collective, would never hear of. Nothing on one process.
  void abort(int code) const;
  // In place, element by element: the minimum over the ranks (exact: no rounding). Maxima travel
  // negated and flags as 0 / -1, so one call takes every global decision of a step.
  void minimum(std::span<double> values) const;
  // In place, element by element: the maximum over the ranks (exact), as minimum of the negated.
  void maximum(std::span<double> values) const {
    for (double& v : values) v = -v;
    minimum(values);
    for (double& v : values) v = -v;
  }
  double largest(double value) const {
    maximum({&value, 1});
    return value;
  }
  // Whether any rank says yes.
  bool any(bool mine) const {
    double flag = mine ? -1 : 0;
    minimum({&flag, 1});
    return flag < 0;
  }
  // The lowest of the ranks' item indices, or -1 when every rank has none (-1): the item that every
  // rank then names alike, as when the first failing particle of a step stops the run.
  Index lowest(Index item) const {
    double value = item < 0 ? std::numeric_limits<double>::infinity() : static_cast<double>(item);
    minimum({&value, 1});
    return std::isfinite(value) ? static_cast<Index>(value) : -1;
  }
  // In place, element by element: the sum over the ranks of each rank's partial sums (exact).
  void sum(std::span<ExactSum> sums) const;
  void sum(std::span<std::int64_t> values) const;
  // Every rank's items in, in place: rank r holds items [offsets[r], offsets[r + 1]) of `items`
  // (offsets.size() == size() + 1) and receives everyone else's (MPI_Allgatherv). For state that
  // every rank holds whole while each computes its own share (docs/SCALING.md, "Replicated").
  template <typename T>
  void share(std::span<T> items, std::span<const Index> offsets) const {
    share_bytes(reinterpret_cast<std::byte*>(items.data()), sizeof(T), offsets);
  }
  // Every rank's `mine`, in rank order (MPI_Allgatherv of one item each): the few numbers of every
  // other rank that a decision taken alike on every rank needs (its work, its count, its range).
  template <typename T>
  std::vector<T> each(const T& mine) const {
    std::vector<T> all(size_);
    all[rank_] = mine;
    std::vector<Index> one_each(size_ + 1);
    for (int r = 0; r <= size_; ++r) one_each[r] = r;
    share(std::span(all), one_each);
    return all;
  }
  // Every rank's items one after the other, in rank order (the counts by `each`, then
  // MPI_Allgatherv): lists of different lengths that every rank needs whole (a moving wall's
  // candidates, the nodes that changed rank).
  template <typename T>
  std::vector<T> all(std::span<const T> mine) const {
    const std::vector<Index> counts = each(static_cast<Index>(mine.size()));
    std::vector<Index> offsets(size_ + 1, 0);
    std::partial_sum(counts.begin(), counts.end(), offsets.begin() + 1);
    std::vector<T> items(offsets.back());
    std::copy(mine.begin(), mine.end(), items.begin() + offsets[rank_]);
    share(std::span(items), offsets);
    return items;
  }
  // Where the items from each rank land in an `exchange` in which this rank sends items
  // [offsets_out[r], offsets_out[r + 1]) to rank r: one count to each rank out, one from each in.
  std::vector<Index> offsets_in(std::span<const Index> offsets_out) const {
    std::vector<Index> one_each(size_ + 1), out(size_), in(size_);
    for (int r = 0; r <= size_; ++r) one_each[r] = r;
    for (int r = 0; r < size_; ++r) out[r] = offsets_out[r + 1] - offsets_out[r];
    if (size_ == 1) in = out;  // to itself
    exchange(std::span<const Index>(out), one_each, std::span(in), one_each);
    std::vector<Index> offsets(size_ + 1, 0);
    std::partial_sum(in.begin(), in.end(), offsets.begin() + 1);
    return offsets;
  }
  // Each rank's items for each other rank out, theirs for it in (MPI_Alltoallv): `send` holds the
  // items for rank r at [send_offsets[r], send_offsets[r + 1]), and the items from rank r land at
  // [receive_offsets[r], receive_offsets[r + 1]) of `receive` (size() + 1 offsets each; the counts
  // must match the senders'). For a halo: the state of the particles near another rank's.
  template <typename T>
  void exchange(std::span<const T> send, std::span<const Index> send_offsets, std::span<T> receive,
                std::span<const Index> receive_offsets) const {
    exchange_bytes(reinterpret_cast<const std::byte*>(send.data()), reinterpret_cast<std::byte*>(receive.data()),
                   sizeof(T), send_offsets, receive_offsets);
  }
  // The same for records of `record_bytes` bytes each (several arrays' values packed one after
  // the other), the offsets counting records: a message may pass 2 GiB while its count of records
  // is an Index.
  void exchange_records(std::span<const std::byte> send, std::size_t record_bytes, std::span<const Index> send_offsets,
                        std::span<std::byte> receive, std::span<const Index> receive_offsets) const {
    exchange_bytes(send.data(), receive.data(), record_bytes, send_offsets, receive_offsets);
  }
  // Each rank's lists out, one for each rank, and the lists for this one in: `out[r]` goes to rank
  // r, and what every rank sent this one comes back one sender after another, in rank order (the
  // counts by offsets_in, then exchange). Particles sent to the ranks that need them.
  template <typename T>
  std::vector<T> deliver(const std::vector<std::vector<T>>& out) const {
    if (size_ == 1) return out[0];
    std::vector<Index> send_offsets(size_ + 1, 0);
    std::vector<T> send;
    for (int r = 0; r < size_; ++r) {
      send.insert(send.end(), out[r].begin(), out[r].end());
      send_offsets[r + 1] = static_cast<Index>(send.size());
    }
    const std::vector<Index> receive_offsets = offsets_in(send_offsets);
    std::vector<T> receive(receive_offsets[size_]);
    exchange(std::span<const T>(send), send_offsets, std::span(receive), receive_offsets);
    return receive;
  }
  // Seconds spent in the collectives above so far, waiting for the other ranks included: the rest
  // of a rank's time is its own work, what load balancing evens out.
  double communicating_seconds() const { return communicating_; }
  // Bytes that came in from the other ranks through share and exchange so far: the halo, the
  // completions and the plans (the reductions' few numbers are not counted). run.json reports it
  // a step, the measure of how much of its neighbours' state a rank needs.
  std::int64_t received_bytes() const { return received_bytes_; }

 private:
  friend class Session;
  void share_bytes(std::byte* items, std::size_t item_bytes, std::span<const Index> offsets) const;
  void exchange_bytes(const std::byte* send, std::byte* receive, std::size_t item_bytes,
                      std::span<const Index> send_offsets, std::span<const Index> receive_offsets) const;
  int rank_ = 0;
  int size_ = 1;
  mutable double communicating_ = 0;
  mutable std::int64_t received_bytes_ = 0;
};

// MPI's lifetime: the constructor starts it when the process was launched as one of several ranks
// and Spall was built with it (MPI_THREAD_FUNNELED: only the thread that started MPI calls it,
// outside OpenMP regions), the destructor ends it. One in main, before anything uses world().
class Session {
 public:
  Session();
  ~Session();
  Session(const Session&) = delete;
  Session& operator=(const Session&) = delete;
};

// The run's ranks: every rank while a Session that started MPI lives, this process alone otherwise.
const Communicator& world();

}  // namespace spall::parallel
