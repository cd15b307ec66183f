#pragma once
// A checkpoint's items of which each rank holds a share (the rows and particles of a fluid dealt by
// region, docs/SCALING.md §3), in one file: the ranks' counts, then each rank's items in the ranks'
// order. Written into a restart file, each rank writes its own items at their place in the file
// (rank 0 the rest), so that no rank's share passes through another; into an archive in memory,
// each rank's come to rank 0 in turn in stretches of at most stretch_bytes. Each rank's items go
// in ascending order of their places in the deck's node order, and the file keeps every
// fence_every-th item's place (the fences), so that a rank reading back the items of its block of
// the node order reads those stretches of each piece alone and seeks past the rest, whatever the
// number of ranks that wrote them.
#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <limits>
#include <numeric>
#include <span>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include <fmt/format.h>

#include "spall/core/archive.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/core/parallel.hpp"

namespace spall::parallel {

inline constexpr std::size_t stretch_bytes = std::size_t(8) << 20;
inline constexpr Index fence_every = 4096;

// write_pieces on ranks other than 0: rank r's items, made in stretches of Archive::flush_bytes,
// into the archive's file at their place after rank 0's (the place rank 0 has reached, which it
// tells every rank), where rank 0 leaves a gap for them. A rank that cannot write its items stops
// every rank alike (OutputError, its own message where it failed).
template <class T, class Item>
void write_in_place(Archive& a, const std::vector<Index>& counts, Item& item, const Communicator& ranks) {
  const std::uint64_t start = static_cast<std::uint64_t>(ranks.each(static_cast<Index>(a.position()))[0]);
  std::uint64_t before = 0, after = 0;
  for (int r = 1; r < ranks.size(); ++r) (r < ranks.rank() ? before : after) += counts[r] * sizeof(T);
  std::string failure;
  if (ranks.rank() == 0) {
    a.leave_gap(after);
  } else if (const Index count = counts[ranks.rank()]; count > 0) {
    std::ofstream out(a.pieces_file(), std::ios::binary | std::ios::in | std::ios::out);
    out.seekp(static_cast<std::streamoff>(start + before));
    const Index stretch = std::max<Index>(1, static_cast<Index>(Archive::flush_bytes / sizeof(T)));
    std::vector<T> made;
    for (Index begin = 0; begin < count && out; begin += stretch) {
      made.clear();
      for (Index k = begin; k < std::min(count, begin + stretch); ++k) made.push_back(item(k));
      out.write(reinterpret_cast<const char*>(made.data()), static_cast<std::streamsize>(made.size() * sizeof(T)));
    }
    out.close();
    if (!out) failure = fmt::format("cannot write {}: {}", a.pieces_file().string(), std::strerror(errno));
  }
  double written = failure.empty() ? 0 : -1;
  ranks.minimum({&written, 1});
  if (written < 0)
    throw OutputError(
        failure.empty() ? fmt::format("cannot write {}: another rank could not write its piece", a.pieces_file().string())
                        : failure,
        true);
}

// write_pieces on ranks other than 0 without a file to write into: each rank's items to rank 0 in
// turn, in stretches of at most stretch_bytes, which rank 0 writes as they come.
template <class T, class Item>
void send_to_first_rank(Archive& a, const std::vector<Index>& counts, Item& item, const Communicator& ranks) {
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
        for (Index k = begin; k < begin + n; ++k) out.push_back(item(k));
      in.resize(receive.back());
      ranks.exchange(std::span<const T>(out), send, std::span<T>(in), receive);
      if (ranks.rank() == 0)
        for (T& received : in) a(received);
    }
}

// Collective: every rank's `count` items, item(k) for k = 0, 1, ... made one after the other (so that
// no rank holds a copy of its own), in ascending place(k) (the place in the deck's node order of
// the item's node), into rank 0's archive: the ranks' counts, their fences, then the items in the
// ranks' order. Each rank writes its own items into the archive's file at their place, where it
// has one (Archive::pieces_file: a restart file's), else rank 0 writes them as they come to it in
// turn (every other rank's archive keeps nothing, Archive::discarding).
template <class T, class Item, class Place>
void write_pieces(Archive& a, Index count, Item&& item, Place&& place, const Communicator& ranks) {
  static_assert(archived_as_bytes<T>);
  std::vector<Index> counts = ranks.each(count);
  std::vector<Index> fences;
  for (Index k = 0; k < count; k += fence_every) fences.push_back(place(k));
  fences = ranks.all(std::span<const Index>(fences));
  a(counts, fences);
  if (ranks.rank() == 0)
    for (Index k = 0; k < count; ++k) {
      T made = item(k);
      a(made);
    }
  if (ranks.size() == 1) return;
  if (!a.pieces_file().empty())
    write_in_place<T>(a, counts, item, ranks);
  else
    send_to_first_rank<T>(a, counts, item, ranks);
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

// The items whose places may lie in [first, end), piece by piece, to visit(item) one by one (the
// caller passes over the others), or to visit(item, k) with k the item's place in the file's
// order (0 for the first piece's first): the stretches between the fences around them are read,
// the rest of each piece is skipped. A rank reading its share of the items (`across`) reads every
// place below the first rank's and above the last rank's too, so that an item of no place in the
// deck is seen (check_read).
template <class T, class Visit>
void read_pieces(Archive& a, Visit&& visit, Index first = std::numeric_limits<Index>::min(),
                 Index end = std::numeric_limits<Index>::max(), const Communicator* across = nullptr) {
  static_assert(archived_as_bytes<T>);
  if (across && across->rank() == 0) first = std::numeric_limits<Index>::min();
  if (across && across->rank() + 1 == across->size()) end = std::numeric_limits<Index>::max();
  std::vector<Index> counts, fences;
  a(counts, fences);
  std::size_t fenced = 0;
  for (const Index n : counts) fenced += static_cast<std::size_t>((std::max<Index>(n, 0) + fence_every - 1) / fence_every);
  if (fenced != fences.size() || std::any_of(counts.begin(), counts.end(), [](Index n) { return n < 0; }))
    throw InputError(a.source() + ": the checkpoint is corrupt (its pieces' counts and fences do not match)");
  auto piece_fences = fences.begin();
  Index before = 0;  // the items of the pieces before
  for (const Index n : counts) {
    const auto fence_end = piece_fences + (n + fence_every - 1) / fence_every;
    // Stretch j holds the places from its fence to the next; those before a fence below `first`
    // lie below it, and from the first fence at or above `end` on all do.
    const Index from = std::max<Index>(0, std::lower_bound(piece_fences, fence_end, first) - piece_fences - 1);
    const Index to = first < end ? std::lower_bound(piece_fences, fence_end, end) - piece_fences : from;
    const Index begin = std::min(n, from * fence_every), stop = std::min(n, to * fence_every);
    a.skip(static_cast<std::uint64_t>(begin) * sizeof(T));
    for (Index k = begin; k < stop; ++k) {
      T item{};  // read into below (initialized: GCC 12 takes the archive's writing branch for a read of it)
      a(item);
      if constexpr (std::is_invocable_v<Visit, const T&, Index>)
        visit(item, before + k);
      else
        visit(item);
    }
    a.skip(static_cast<std::uint64_t>(n - std::max(begin, stop)) * sizeof(T));
    piece_fences = fence_end;
    before += n;
  }
}

// An array the options may switch off (empty) in pieces: whether it holds values, then where it
// does the values of this rank's `count` items, item k's array[at(k)], in ascending place(k).
// Collective.
template <class Array, class At, class Place>
void write_array_pieces(Archive& a, const Array& array, Index count, At&& at, Place&& place, const Communicator& ranks) {
  bool present = !array.empty();
  a(present);
  using Value = typename std::remove_cvref_t<Array>::value_type;
  if (present) write_pieces<Value>(a, count, [&](Index k) { return array[at(k)]; }, place, ranks);
}

// Such an array read back: one written off is cleared; else the k-th value in the file goes to
// array[at(k)] (at(k) < 0: an item of no place here), a std::vector being `size` long, a
// RangeArray holding `keep` alone (the values outside it are passed over). A RangeArray whose
// values in `keep` were written with places in `places` reads those stretches of each piece
// alone, seeking past the rest (read_pieces).
template <class Array, class At>
void read_array_pieces(Archive& a, Array& array, Index size, Range keep, At&& at,
                       Range places = {std::numeric_limits<Index>::min(), std::numeric_limits<Index>::max()}) {
  bool present = false;
  a(present);
  if (!present) {
    array.clear();
    return;
  }
  using Value = typename std::remove_cvref_t<Array>::value_type;
  constexpr bool stretch = requires { array.hold(keep.begin, keep.end); };
  array.resize(stretch ? 0 : size);
  if constexpr (stretch) array.hold(keep.begin, keep.end);
  const auto visit = [&](const Value& value, Index k) {
    if (const Index i = at(k); i >= 0 && (!stretch || (i >= keep.begin && i < keep.end))) array[i] = value;
  };
  if (stretch)
    read_pieces<Value>(a, visit, places.begin, places.end);
  else
    read_pieces<Value>(a, visit);
}

}  // namespace spall::parallel
