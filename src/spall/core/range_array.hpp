#pragma once
// A per-particle array that holds the values of one contiguous range of particles, indexed by the
// particle's index as a whole array would be: under MPI a formulation keeps the state that only a
// particle's own rank reads (its material point, its energy) for the particles of its own block
// of the node order alone (docs/SCALING.md §3, "Own state held by its rank"), and the neighbour list
// its positions at the build of a rank's own. An array that the options switch off is empty; one
// that is on but holds no particle (a rank without any) is not. view() reads it as a StretchView.
#include <algorithm>
#include <cstddef>
#include <utility>
#include <vector>

#include "spall/core/stretch_view.hpp"
#include "spall/core/types.hpp"

namespace spall {

template <typename T>
class RangeArray {
 public:
  using value_type = T;

  // On, holding particles [0, n) with `value` (the set-up's state, every particle's alike).
  void assign(Index n, const T& value) {
    first_ = 0;
    on_ = true;
    values_.assign(static_cast<std::size_t>(n), value);
  }
  // On, holding particles [0, values.size()) with `values` (the set-up's, each its own).
  void assign(std::vector<T> values) {
    first_ = 0;
    on_ = true;
    values_ = std::move(values);
    values_.shrink_to_fit();
  }
  void resize(Index n) {
    first_ = 0;
    on_ = true;
    values_.resize(static_cast<std::size_t>(n));
  }
  void clear() {  // off
    first_ = 0;
    on_ = false;
    values_ = {};
  }
  bool empty() const { return !on_; }

  // Holds particles [begin, end) from now on: those it held already keep their values, the others
  // start value-initialized (the caller brings theirs in), or as `fresh`.
  void hold(Index begin, Index end) {
    hold_with(begin, end, [](std::size_t n) { return std::vector<T>(n); });
  }
  void hold(Index begin, Index end, const T& fresh) {
    hold_with(begin, end, [&](std::size_t n) { return std::vector<T>(n, fresh); });
  }

  // On, holding particles [begin, end), every one afresh (value-initialized, or `fresh`): what it
  // held before is dropped (scratch that a pass fills anew).
  void hold_afresh(Index begin, Index end) {
    first_ = begin;
    on_ = true;
    values_ = std::vector<T>(count(begin, end));
  }
  void hold_afresh(Index begin, Index end, const T& fresh) {
    first_ = begin;
    on_ = true;
    values_ = std::vector<T>(count(begin, end), fresh);
  }

  // The particles it holds: [held_begin(), held_end()).
  Index held_begin() const { return first_; }
  Index held_end() const { return last(); }

  T& operator[](Index p) { return values_[static_cast<std::size_t>(p - first_)]; }
  const T& operator[](Index p) const { return values_[static_cast<std::size_t>(p - first_)]; }
  // The values held, from the first particle held on: particle p's is data()[p - held_begin()].
  T* data() { return values_.data(); }
  const T* data() const { return values_.data(); }
  void fill(const T& value) { std::fill(values_.begin(), values_.end(), value); }
  void swap(RangeArray& other) noexcept {
    std::swap(first_, other.first_);
    std::swap(on_, other.on_);
    values_.swap(other.values_);
  }
  std::size_t capacity_bytes() const { return values_.capacity() * sizeof(T); }
  // The values held, read-only, of `count` particles in all.
  StretchView<T> view(Index count) const { return {values_.data(), first_, last() - first_, count}; }

 private:
  Index last() const { return first_ + static_cast<Index>(values_.size()); }
  static std::size_t count(Index begin, Index end) { return static_cast<std::size_t>(std::max(begin, end) - begin); }
  template <typename Make>
  void hold_with(Index begin, Index end, Make&& make) {
    end = std::max(begin, end);
    if (!on_ || (begin == first_ && end == last())) return;
    std::vector<T> held = make(static_cast<std::size_t>(end - begin));
    for (Index p = std::max(begin, first_); p < std::min(end, last()); ++p) held[p - begin] = values_[p - first_];
    first_ = begin;
    values_ = std::move(held);
  }

  Index first_ = 0;
  bool on_ = false;
  std::vector<T> values_;
};

}  // namespace spall
