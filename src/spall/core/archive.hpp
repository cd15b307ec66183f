#pragma once
// The bytes of a checkpoint (*DATABASE_BINARY_RUNRSF, `spall run --restart`). Every object that
// carries state from one step to the next lists its members once, in checkpoint(Archive&), and the
// same list writes them and reads them back: a restart then continues bitwise where the run was.
// What an object rebuilds from the deck (settings, materials, meshes' connectivity) is not listed;
// what it derives from its state at every step may be left out too, but any cache whose contents
// can differ from a fresh build (neighbour lists, sorted orders, multipliers that start the next
// solve) must be listed, or the continued run drifts by round-off.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <istream>
#include <memory>
#include <optional>
#include <ostream>
#include <stdexcept>
#include <string>
#include <string_view>
#include <type_traits>
#include <utility>
#include <vector>

#include "spall/core/error.hpp"
#include "spall/core/types.hpp"

namespace spall {

class Archive;

// Types copied as their bytes: trivially copyable ones, fixed-size Eigen matrices, and aggregates
// of those that opt in by specializing this (an aggregate holding an Eigen matrix is not trivially
// copyable by the standard's rule, though its bytes are all there is to it).
template <class T>
inline constexpr bool archived_as_bytes = std::is_trivially_copyable_v<T>;
template <class S, int R, int C, int O, int MR, int MC>
inline constexpr bool archived_as_bytes<Eigen::Matrix<S, R, C, O, MR, MC>> = (R > 0 && C > 0);

template <class T>
concept HasCheckpoint = requires(T& t, Archive& a) { t.checkpoint(a); };

class Archive {
 public:
  // An archive to write into; bytes() holds what was written.
  static Archive for_writing() { return Archive(); }
  // An archive that writes into `out` as it goes, so that a checkpoint of any size holds at most
  // flush_bytes of it in memory; flush() writes what is left. `file`, when given, is what `out`
  // writes (a restart file's temporary): under MPI the other ranks write their pieces into it at
  // their places (core/pieces.hpp), where this archive leaves gaps for them (leave_gap).
  static Archive for_writing_to(std::ostream& out, std::filesystem::path file = {}) {
    Archive a;
    a.out_ = &out;
    a.pieces_file_ = std::move(file);
    return a;
  }
  // An archive that keeps nothing: under MPI the ranks that do not write the restart file make
  // the same checkpoint calls as rank 0; their pieces go into `pieces_into` (rank 0's file, see
  // for_writing_to), or, without one, to rank 0 through its collectives (core/pieces.hpp).
  static Archive discarding(std::filesystem::path pieces_into = {}) {
    Archive a;
    a.discarding_ = true;
    a.pieces_file_ = std::move(pieces_into);
    return a;
  }
  static constexpr std::size_t flush_bytes = std::size_t(1) << 20;
  // An archive that reads `bytes` back; `source` names them in messages (the restart file).
  static Archive for_reading(std::string bytes, std::string source) {
    Archive a;
    a.size_ = bytes.size();
    a.bytes_ = std::move(bytes);
    a.reading_ = true;
    a.source_ = std::move(source);
    return a;
  }
  // An archive that reads the `size` bytes of `in` back as it goes, flush_bytes at a time (a
  // restart file of any size is not held whole).
  static Archive for_reading_from(std::shared_ptr<std::istream> in, std::uint64_t size, std::string source) {
    Archive a = for_reading({}, std::move(source));
    a.in_ = std::move(in);
    a.size_ = size;
    return a;
  }

  bool reading() const { return reading_; }
  // What is read, for messages.
  const std::string& source() const { return source_; }
  void flush() {
    if (!out_) return;
    out_->write(bytes_.data(), static_cast<std::streamsize>(bytes_.size()));
    flushed_ += bytes_.size();
    bytes_.clear();
  }
  // The file every rank writes its pieces into (empty when the pieces go through rank 0).
  const std::filesystem::path& pieces_file() const { return pieces_file_; }
  // Writing: the bytes written so far, flushed or not.
  std::uint64_t position() const { return flushed_ + bytes_.size(); }
  // Writing into a stream: n bytes passed over, which the other ranks write (their pieces).
  void leave_gap(std::uint64_t n) {
    if (!out_) throw std::logic_error("Archive::leave_gap: only an archive writing into a stream leaves gaps");
    flush();
    out_->seekp(static_cast<std::streamoff>(n), std::ios::cur);
    flushed_ += n;
  }
  const std::string& bytes() const { return bytes_; }
  bool at_end() const { return offset_ + position_ == size_; }

  // Each item written, or read back into the same variables.
  template <class... T>
  void operator()(T&... items) {
    (item(items), ...);
  }

  // Reading: the next n bytes passed over (a stream read from seeks past those beyond what it holds).
  void skip(std::uint64_t n) {
    if (!reading_) throw std::logic_error("Archive::skip: only a reading archive skips");
    if (n > size_ - offset_ - position_)
      throw InputError(source_ + ": the checkpoint ends early (truncated, or not written by this version of Spall)");
    if (n <= bytes_.size() - position_) {
      position_ += static_cast<std::size_t>(n);
      return;
    }
    offset_ += position_ + n;
    bytes_.clear();
    position_ = 0;
    in_->seekg(static_cast<std::streamoff>(offset_));
    if (!*in_) throw InputError(source_ + ": cannot read the checkpoint (the file changed or a read failed)");
  }

  // A named mark. Read back, it must be the same: a checkpoint of another deck, or of another
  // version of Spall, fails here with a message instead of reading garbage.
  void section(std::string_view name) {
    std::string mark(name);
    item(mark);
    if (reading_ && mark != name)
      throw InputError(source_ + ": the checkpoint does not match this deck and version of Spall (expected '" +
                       std::string(name) + "', found '" + mark.substr(0, 64) + "')");
  }

  // A count written, or read back and checked against the one this run has (the particles of a
  // part, the contacts of the deck ...).
  void expect_size(std::string_view what, std::size_t size) {
    std::uint64_t n = size;
    item(n);
    if (reading_ && n != size)
      throw InputError(source_ + ": the checkpoint has " + std::to_string(n) + " " + std::string(what) +
                       ", this deck " + std::to_string(size));
  }

  // The length before a sequence of items: written, or read back (and checked against what an
  // archive of this size can hold).
  std::size_t count(std::size_t n) {
    std::uint64_t stored = n;
    raw(&stored, sizeof stored);
    if (reading_ && stored > size_)  // a count no checkpoint of this size can hold
      throw InputError(source_ + ": the checkpoint is corrupt (a count of " + std::to_string(stored) + ")");
    return static_cast<std::size_t>(stored);
  }

 private:
  Archive() = default;

  void raw(void* data, std::size_t size) {
    if (!reading_) {
      if (discarding_) return;
      bytes_.append(static_cast<const char*>(data), size);
      if (out_ && bytes_.size() >= flush_bytes) flush();
      return;
    }
    if (size > size_ - offset_ - position_)
      throw InputError(source_ + ": the checkpoint ends early (truncated, or not written by this version of Spall)");
    auto* to = static_cast<char*>(data);
    while (size > 0) {
      if (position_ == bytes_.size()) refill();
      const std::size_t n = std::min(size, bytes_.size() - position_);
      std::memcpy(to, bytes_.data() + position_, n);
      position_ += n, to += n, size -= n;
    }
  }

  // The next flush_bytes of the stream read from (the end checked by raw()).
  void refill() {
    offset_ += bytes_.size();
    bytes_.resize(static_cast<std::size_t>(std::min<std::uint64_t>(flush_bytes, size_ - offset_)));
    in_->read(bytes_.data(), static_cast<std::streamsize>(bytes_.size()));
    if (!*in_) throw InputError(source_ + ": cannot read the checkpoint (the file changed or a read failed)");
    position_ = 0;
  }

  template <class T>
  void item(T& value) {
    if constexpr (HasCheckpoint<T>) {
      value.checkpoint(*this);
    } else if constexpr (archived_as_bytes<T>) {
      raw(&value, sizeof(T));
    } else {
      static_assert(sizeof(T) == 0, "no checkpoint for this type: give it checkpoint(Archive&)");
    }
  }

  void item(std::string& value) {
    value.resize(count(value.size()));
    raw(value.data(), value.size());
  }

  template <class T, class A>
  void item(std::vector<T, A>& values) {
    values.resize(count(values.size()));
    if constexpr (archived_as_bytes<T> && !HasCheckpoint<T>) {
      if (!values.empty()) raw(values.data(), values.size() * sizeof(T));
    } else {
      for (auto& v : values) item(v);
    }
  }

  template <class T>
  void item(std::optional<T>& value) {
    bool present = value.has_value();
    raw(&present, sizeof present);
    if (reading_) {
      if (present && !value) value.emplace();
      if (!present) value.reset();
    }
    if (present) item(*value);
  }

  template <class A, class B>
  void item(std::pair<A, B>& value) {
    item(value.first);
    item(value.second);
  }

  std::string bytes_;
  std::size_t position_ = 0;
  bool reading_ = false;
  bool discarding_ = false;
  std::ostream* out_ = nullptr;
  std::uint64_t flushed_ = 0;  // writing into out_: the bytes written into it, gaps included
  std::filesystem::path pieces_file_;
  // Reading: the archive's length, the stream it comes from (none when bytes_ holds it whole) and
  // the place in it of bytes_'s first byte.
  std::uint64_t size_ = 0;
  std::shared_ptr<std::istream> in_;
  std::uint64_t offset_ = 0;
  std::string source_;
};

}  // namespace spall
