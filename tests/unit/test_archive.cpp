// The checkpoint's archive (core/archive.hpp) written into a stream as it fills and read back from
// one as it goes (a restart file is never held whole): the bytes are those of the archive held in
// memory, across several flushes and refills, and a stream cut short is refused with a message.
#include <gtest/gtest.h>

#include <memory>
#include <numeric>
#include <sstream>
#include <string>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/error.hpp"

namespace spall {
namespace {

// A header, then more numbers than three flushes' worth, then a trailer.
void fill(Archive& a, std::string& header, std::vector<double>& numbers, std::int64_t& trailer) {
  a.section("test archive");
  a(header, numbers, trailer);
}

TEST(Archive, StreamedBothWaysAcrossFlushesIsTheArchiveInMemory) {
  std::string header = "spall";
  std::vector<double> numbers(3 * Archive::flush_bytes / sizeof(double) + 7);
  std::iota(numbers.begin(), numbers.end(), 0.25);
  std::int64_t trailer = -42;

  Archive whole = Archive::for_writing();
  fill(whole, header, numbers, trailer);
  std::ostringstream out;
  Archive streamed = Archive::for_writing_to(out);
  fill(streamed, header, numbers, trailer);
  EXPECT_LT(streamed.bytes().size(), Archive::flush_bytes);  // held at most a flush's worth
  streamed.flush();
  ASSERT_EQ(out.str(), whole.bytes());

  Archive read = Archive::for_reading_from(std::make_shared<std::istringstream>(out.str()), out.str().size(), "file");
  std::string header_read;
  std::vector<double> numbers_read;
  std::int64_t trailer_read = 0;
  fill(read, header_read, numbers_read, trailer_read);
  EXPECT_TRUE(read.at_end());
  EXPECT_EQ(header_read, header);
  EXPECT_EQ(numbers_read, numbers);
  EXPECT_EQ(trailer_read, trailer);
}

TEST(Archive, AStreamCutShortIsRefused) {
  std::string header = "spall";
  std::vector<double> numbers(2 * Archive::flush_bytes / sizeof(double));
  std::int64_t trailer = 1;
  Archive whole = Archive::for_writing();
  fill(whole, header, numbers, trailer);
  const std::string cut = whole.bytes().substr(0, whole.bytes().size() - 3);
  Archive read = Archive::for_reading_from(std::make_shared<std::istringstream>(cut), cut.size(), "file");
  try {
    fill(read, header, numbers, trailer);
    FAIL() << "an archive cut short was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("file: the checkpoint ends early"), std::string::npos) << e.what();
  }
  // A stream shorter than the length it was said to have: the read fails, not garbage.
  Archive lying = Archive::for_reading_from(std::make_shared<std::istringstream>(cut), whole.bytes().size(), "file");
  try {
    fill(lying, header, numbers, trailer);
    FAIL() << "a stream shorter than its length was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("file: cannot read the checkpoint"), std::string::npos) << e.what();
  }
}

// What is discarded leaves nothing, and costs no memory.
TEST(Archive, DiscardingKeepsNothing) {
  std::string header = "spall";
  std::vector<double> numbers(1000, 1.0);
  std::int64_t trailer = 3;
  Archive a = Archive::discarding();
  fill(a, header, numbers, trailer);
  EXPECT_TRUE(a.bytes().empty());
  EXPECT_FALSE(a.reading());
}

}  // namespace
}  // namespace spall
