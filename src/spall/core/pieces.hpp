#pragma once
// A checkpoint's items of which each rank holds a share (the rows and particles of a fluid dealt by
// region, docs/SCALING.md §3): rank 0 writes every rank's in the ranks' order, each brought to it in
// turn in stretches of at most stretch_bytes, so that writing a restart file holds no more on rank 0
// than one stretch of another's; read back item by item on every rank, whatever the number of
// ranks that wrote them.
#include <algorithm>
#include <numeric>
#include <span>
#include <string_view>
#include <vector>

#include <fmt/format.h>

#include "spall/core/archive.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"

namespace spall::parallel {

inline constexpr std::size_t stretch_bytes = std::size_t(8) << 20;

// Collective: every rank's `count` items, made one after the other by next() (so that no rank
// holds a copy of its own), into rank 0's archive (every other rank's keeps nothing,
// Archive::discarding), as one count and the items in the ranks' order.
template <class T, class Next>
void write_pieces(Archive& a, Index count, Next&& next, const Communicator& ranks) {
  static_assert(archived_as_bytes<T>);
  const std::vector<Index> counts = ranks.each(count);
  a.count(static_cast<std::size_t>(std::accumulate(counts.begin(), counts.end(), Index(0))));
  if (ranks.rank() == 0)
    for (Index k = 0; k < count; ++k) {
      T item = next();
      a(item);
    }
  const Index stretch = std::max<Index>(1, static_cast<Index>(stretch_bytes / sizeof(T)));
  std::vector<Index> send(ranks.size() + 1), receive(ranks.size() + 1);
  std::vector<T> out, in;
  for (int r = 1; r < ranks.size(); ++r)
    for (Index begin = 0; begin < counts[r]; begin += stretch) {
      // Rank r sends its items [begin, begin + n) to rank 0, no other rank anything.
      const Index n = std::min(stretch, counts[r] - begin);
      for (int k = 0; k <= ranks.size(); ++k) {
        send[k] = ranks.rank() == r && k > 0 ? n : 0;
        receive[k] = ranks.rank() == 0 && k > r ? n : 0;
      }
      out.clear();
      if (ranks.rank() == r)
        for (Index k = 0; k < n; ++k) out.push_back(next());
      in.resize(receive.back());
      ranks.exchange(std::span<const T>(out), send, std::span<T>(in), receive);
      if (ranks.rank() == 0)
        for (T& item : in) a(item);
    }
}

// After read_pieces into a deck's nodes or particles: the first item that was not this deck's
// (`mismatch`: the place in the node order of its node) or else the first this rank has room for
// that none filled (`missing`), -1 for none, each the lowest over the ranks when each rank read
// its own share (`across`), stops every rank alike naming `what` sat on that node.
inline void check_read(const Archive& a, std::string_view what, Index mismatch, Index missing,
                       const Communicator* across) {
  if (across) {
    mismatch = across->lowest(mismatch);
    missing = across->lowest(missing);
  }
  if (mismatch >= 0 || missing >= 0)
    throw InputError(fmt::format("{}: the checkpoint does not match this deck (the {} at place {} of the node order {})",
                                 a.source(), what, mismatch >= 0 ? mismatch : missing,
                                 mismatch >= 0 ? "is not this deck's" : "is missing"));
}

// Every piece's items, to visit(item) one by one.
template <class T, class Visit>
void read_pieces(Archive& a, Visit&& visit) {
  static_assert(archived_as_bytes<T>);
  const std::size_t n = a.count(0);
  for (std::size_t k = 0; k < n; ++k) {
    T item;
    a(item);
    visit(item);
  }
}

}  // namespace spall::parallel
