#pragma once
// The bytes of a checkpoint (*DATABASE_BINARY_RUNRSF, `spall run --restart`). Every object that
// carries state from one step to the next lists its members once, in checkpoint(Archive&), and the
// same list writes them and reads them back: a restart then continues bitwise where the run was.
// What an object rebuilds from the deck (settings, materials, meshes' connectivity) is not listed;
// what it derives from its state at every step may be left out too, but any cache whose contents
// can differ from a fresh build (neighbour lists, sorted orders, multipliers that start the next
// solve) must be listed, or the continued run drifts by round-off.
#include <cstdint>
#include <cstring>
#include <optional>
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
  // An archive that reads `bytes` back; `source` names them in messages (the restart file).
  static Archive for_reading(std::string bytes, std::string source) {
    Archive a;
    a.bytes_ = std::move(bytes);
    a.reading_ = true;
    a.source_ = std::move(source);
    return a;
  }

  bool reading() const { return reading_; }
  const std::string& bytes() const { return bytes_; }
  bool at_end() const { return position_ == bytes_.size(); }

  // Each item written, or read back into the same variables.
  template <class... T>
  void operator()(T&... items) {
    (item(items), ...);
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

 private:
  Archive() = default;

  void raw(void* data, std::size_t size) {
    if (!reading_) {
      bytes_.append(static_cast<const char*>(data), size);
      return;
    }
    if (size > bytes_.size() - position_)
      throw InputError(source_ + ": the checkpoint ends early (truncated, or not written by this version of Spall)");
    std::memcpy(data, bytes_.data() + position_, size);
    position_ += size;
  }

  std::size_t count(std::size_t n) {
    std::uint64_t stored = n;
    raw(&stored, sizeof stored);
    if (reading_ && stored > bytes_.size())  // a count no checkpoint of this size can hold
      throw InputError(source_ + ": the checkpoint is corrupt (a count of " + std::to_string(stored) + ")");
    return static_cast<std::size_t>(stored);
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
  std::string source_;
};

}  // namespace spall
