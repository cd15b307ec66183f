// A checkpoint's items in pieces (core/pieces.hpp), run as 1, 2 and 3 ranks: every rank's items,
// each in ascending place, written into rank 0's archive, read back from a stream by each rank for
// its block of the places: the block's items come back, each once, and a rank reads the block's
// share of the file and the stretches around it, not the whole file (a restart of a large run read
// on many ranks, docs/SCALING.md §3); an item of no place in the deck reaches the first or the last
// rank. An array whose places are its indices, read into a stretch, reads that stretch's values
// alone. Written into a file, each rank writes its own items at their place: the file is the
// archive rank 0 writes in memory, and a rank that cannot write stops every rank alike.
#include <gtest/gtest.h>

#include <unistd.h>

#include <cstdint>
#include <filesystem>
#include <fstream>
#include <ios>
#include <iterator>
#include <istream>
#include <memory>
#include <span>
#include <sstream>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "spall/core/archive.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/core/pieces.hpp"
#include "spall/core/range_array.hpp"

namespace spall::parallel {
namespace {

struct Item {
  std::int64_t place;
  std::int64_t value;
};

// A file read from memory that counts the bytes it hands over.
class CountingBuffer : public std::stringbuf {
 public:
  explicit CountingBuffer(const std::string& bytes) : std::stringbuf(bytes, std::ios::in) {}
  std::streamsize delivered = 0;

 protected:
  std::streamsize xsgetn(char* to, std::streamsize n) override {
    const std::streamsize got = std::stringbuf::xsgetn(to, n);
    delivered += got;
    return got;
  }
};

class CountingStream : public std::istream {
 public:
  explicit CountingStream(const std::string& bytes) : std::istream(nullptr), buffer(bytes) { rdbuf(&buffer); }
  CountingBuffer buffer;
};

TEST(Pieces, EachRankReadsItsBlockAndTheStretchesAroundIt) {
  const Communicator& ranks = world();
  // Two million places dealt among the ranks by a hash, so that every piece spans them all; the
  // last rank's piece also holds a place below every place of the deck and one above.
  const Index places = 2'000'000;
  std::vector<Item> mine;
  const bool last = ranks.rank() + 1 == ranks.size();
  if (last) mine.push_back({-1, 7});
  for (Index p = 0; p < places; ++p)
    if (static_cast<int>((p * 2654435761u) % 1000 % ranks.size()) == ranks.rank()) mine.push_back({p, 3 * p + 1});
  if (last) mine.push_back({places + 7, 8});

  Archive written = ranks.rank() == 0 ? Archive::for_writing() : Archive::discarding();
  write_pieces<Item>(
      written, static_cast<Index>(mine.size()), [&](Index k) { return mine[k]; }, [&](Index k) { return mine[k].place; },
      ranks);
  written.section("after the pieces");
  const std::vector<char> all = ranks.all(std::span<const char>(written.bytes().data(), written.bytes().size()));
  const std::string file(all.begin(), all.end());

  const Index first = block_begin(places, ranks.rank(), ranks.size());
  const Index end = block_begin(places, ranks.rank() + 1, ranks.size());
  auto stream = std::make_shared<CountingStream>(file);
  Archive read = Archive::for_reading_from(stream, file.size(), "file");
  std::vector<int> seen(static_cast<std::size_t>(end - first), 0);
  Index visited = 0;
  bool below = false, above = false;
  read_pieces<Item>(
      read,
      [&](const Item& item) {
        ++visited;
        below |= item.place == -1 && item.value == 7;
        above |= item.place == places + 7 && item.value == 8;
        if (item.place < first || item.place >= end) return;
        EXPECT_EQ(item.value, 3 * item.place + 1);
        ++seen[static_cast<std::size_t>(item.place - first)];
      },
      first, end, &ranks);
  read.section("after the pieces");  // the read ends after the last piece, whatever it skipped
  EXPECT_TRUE(read.at_end());
  for (std::size_t k = 0; k < seen.size(); ++k) ASSERT_EQ(seen[k], 1) << "place " << first + Index(k);
  EXPECT_EQ(below, ranks.rank() == 0);
  EXPECT_EQ(above, last);
  // At most a stretch more than the block's on either side in each piece, and the bytes of those
  // and of the counts and fences, with a refill's worth more at each of the pieces' seeks.
  EXPECT_LE(visited, (end - first) + 2 * ranks.size() * fence_every + 2);
  const auto item_bytes = static_cast<std::streamsize>(sizeof(Item));
  EXPECT_LE(stream->buffer.delivered,
            visited * item_bytes + static_cast<std::streamsize>((ranks.size() + 1) * Archive::flush_bytes) +
                places / fence_every * 8 + 4096);
  if (ranks.size() > 1) {
    EXPECT_LT(stream->buffer.delivered, static_cast<std::streamsize>(file.size()) * 3 / 4);
  }
}

// Reading every place (one process, or a deck set up whole) reads every item of every piece.
TEST(Pieces, EveryPlaceReadsEveryItem) {
  const Communicator& ranks = world();
  std::vector<Item> mine;
  for (Index p = ranks.rank(); p < 10'000; p += ranks.size()) mine.push_back({p, p});
  Archive written = ranks.rank() == 0 ? Archive::for_writing() : Archive::discarding();
  write_pieces<Item>(
      written, static_cast<Index>(mine.size()), [&](Index k) { return mine[k]; }, [&](Index k) { return mine[k].place; },
      ranks);
  const std::vector<char> all = ranks.all(std::span<const char>(written.bytes().data(), written.bytes().size()));
  Archive read = Archive::for_reading(std::string(all.begin(), all.end()), "file");
  std::vector<int> seen(10'000, 0);
  read_pieces<Item>(read, [&](const Item& item) { ++seen[static_cast<std::size_t>(item.place)]; });
  EXPECT_TRUE(read.at_end());
  for (std::size_t p = 0; p < seen.size(); ++p) ASSERT_EQ(seen[p], 1) << "place " << p;
}

// An array in pieces whose places are its indices (the solid elements' state, keyed by element):
// read back into a RangeArray holding a rank's block of the indices, each value lands at the index
// its place in the file's order names, and a rank reads its block's stretches of the pieces, not
// the whole array; an array switched off comes back off.
TEST(Pieces, AnArrayReadIntoAStretchSeeksPastTheRest) {
  const Communicator& ranks = world();
  const Index n = 1'000'000;
  std::vector<std::int64_t> values(n), off;
  std::vector<Index> own;  // this rank's indices, ascending, dealt by a hash: every piece spans them all
  for (Index i = 0; i < n; ++i) {
    values[i] = 5 * std::int64_t(i) + 3;
    if (static_cast<int>((i * 2654435761u) % 1000 % ranks.size()) == ranks.rank()) own.push_back(i);
  }
  const auto index = [&](Index k) { return own[k]; };
  Archive written = ranks.rank() == 0 ? Archive::for_writing() : Archive::discarding();
  const auto count = static_cast<Index>(own.size());
  write_pieces<Index>(written, count, index, index, ranks);
  write_array_pieces(written, values, count, index, index, ranks);
  write_array_pieces(written, off, count, index, index, ranks);
  const std::vector<char> all = ranks.all(std::span<const char>(written.bytes().data(), written.bytes().size()));
  const std::string file(all.begin(), all.end());

  auto stream = std::make_shared<CountingStream>(file);
  Archive read = Archive::for_reading_from(stream, file.size(), "file");
  std::vector<Index> listed;  // the indices in the file's order, read whole
  read_pieces<Index>(read, [&](Index i) { listed.push_back(i); });
  const std::streamsize before = stream->buffer.delivered;
  const Index first = block_begin(n, ranks.rank(), ranks.size()), end = block_begin(n, ranks.rank() + 1, ranks.size());
  RangeArray<std::int64_t> array, absent;
  absent.resize(0);  // on, to be switched off by the read
  read_array_pieces(read, array, n, {first, end}, [&](Index k) { return listed[k]; }, {first, end});
  const std::streamsize array_bytes = stream->buffer.delivered - before;
  read_array_pieces(read, absent, n, {first, end}, [&](Index k) { return listed[k]; }, {first, end});
  EXPECT_TRUE(read.at_end());
  EXPECT_TRUE(absent.empty());
  for (Index i = first; i < end; ++i) ASSERT_EQ(array[i], 5 * std::int64_t(i) + 3) << "index " << i;
  // The block's values and a stretch on either side in each piece, a refill's worth at each seek.
  const auto value_bytes = static_cast<std::streamsize>(sizeof(std::int64_t));
  EXPECT_LE(array_bytes, ((end - first) + 2 * ranks.size() * fence_every) * value_bytes +
                             static_cast<std::streamsize>((ranks.size() + 1) * Archive::flush_bytes) + n / fence_every * 8 + 4096);
  if (ranks.size() > 1) {
    EXPECT_LT(array_bytes, n * value_bytes * 3 / 4);
  }
}

// A header, a piece of every rank's items over more than a stretch, a mark, a second piece, a
// trailer: what a restart file holds, as each rank would have it.
void write_checkpoint(Archive& a, const Communicator& ranks) {
  std::string header = "spall";
  a(header);
  const auto piece = [&](Index places, std::int64_t salt) {
    std::vector<Item> mine;
    for (Index p = ranks.rank(); p < places; p += ranks.size()) mine.push_back({p, salt * p});
    write_pieces<Item>(
        a, static_cast<Index>(mine.size()), [&](Index k) { return mine[k]; }, [&](Index k) { return mine[k].place; },
        ranks);
  };
  piece(1'200'000, 3);
  a.section("between the pieces");
  piece(5'000, 5);
  std::int64_t trailer = -42;
  a(trailer);
}

std::string contents(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), {}};
}

// Written into a file (a restart file's temporary), each rank writes its pieces at their places and
// rank 0 the rest: the file is byte for byte what rank 0 writes in memory as the pieces come to it.
TEST(Pieces, WrittenInPlaceIntoAFileIsTheArchiveInMemory) {
  const Communicator& ranks = world();
  Archive memory = ranks.rank() == 0 ? Archive::for_writing() : Archive::discarding();
  write_checkpoint(memory, ranks);
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() / fmt::format("spall_test_pieces_{}.tmp", ranks.each(Index(::getpid()))[0]);
  std::ofstream out;
  if (ranks.rank() == 0) out.open(file, std::ios::binary | std::ios::trunc);
  ranks.each(0);  // the file is made before any rank writes into it
  Archive a = ranks.rank() == 0 ? Archive::for_writing_to(out, file) : Archive::discarding(file);
  write_checkpoint(a, ranks);
  if (ranks.rank() == 0) {
    a.flush();
    out.close();
    ASSERT_TRUE(out);
  }
  ranks.each(0);  // every rank's pieces are in
  if (ranks.rank() == 0) {
    EXPECT_TRUE(contents(file) == memory.bytes()) << "the file differs from the archive in memory";
    std::filesystem::remove(file);
  }
}

// A rank whose piece cannot be written (a full disk) stops every rank alike, with its message.
TEST(Pieces, ARankThatCannotWriteItsPieceStopsEveryRank) {
  const Communicator& ranks = world();
  if (ranks.size() == 1 || access("/dev/full", W_OK) != 0) GTEST_SKIP() << "needs two ranks and /dev/full";
  std::ofstream out;
  if (ranks.rank() == 0) out.open("/dev/full", std::ios::binary);
  Archive a = ranks.rank() == 0 ? Archive::for_writing_to(out, "/dev/full") : Archive::discarding("/dev/full");
  try {
    write_checkpoint(a, ranks);
    FAIL() << "a piece was written to a full disk";
  } catch (const OutputError& e) {
    EXPECT_TRUE(e.every_rank());
    const std::string expected = ranks.rank() == 0 ? "another rank could not write its piece" : "No space left on device";
    EXPECT_NE(std::string(e.what()).find(expected), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace spall::parallel
