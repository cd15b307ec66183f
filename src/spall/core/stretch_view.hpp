#pragma once
// Read-only per-particle values of one stretch of the particles, [held_begin(), held_end()),
// indexed by the particle's index as an array of every particle's would be (size() counts every
// particle): under MPI a rank keeps the positions of the particles it reads alone
// (docs/SCALING.md §3, "The SPH solid's window of the nodes"). Any contiguous array (a vector, a
// span) is the view of every particle's.
#include <concepts>
#include <ranges>
#include <span>
#include <stdexcept>

#include "spall/core/types.hpp"

namespace spall {

template <typename T>
class StretchView {
 public:
  StretchView() = default;
  // Particles [first, first + held) at `values`, of `count` in all.
  StretchView(const T* values, Index first, Index held, Index count)
      : values_(values), first_(first), held_(held), count_(count) {}
  // Every particle's values.
  template <std::ranges::contiguous_range Range>
    requires std::same_as<std::remove_cv_t<std::ranges::range_value_t<Range>>, T>
  StretchView(const Range& every)  // NOLINT(google-explicit-constructor): a vector or span is a view of all
      : values_(std::ranges::data(every)),
        held_(static_cast<Index>(std::ranges::size(every))),
        count_(static_cast<Index>(std::ranges::size(every))) {}

  const T& operator[](Index p) const { return values_[p - first_]; }
  Index size() const { return count_; }
  Index held_begin() const { return first_; }
  Index held_end() const { return first_ + held_; }
  // Every particle's values, for what reads them all; a view of a stretch has none.
  std::span<const T> every() const {
    if (first_ != 0 || held_ != count_) throw std::logic_error("StretchView: not every particle's values");
    return {values_, static_cast<std::size_t>(count_)};
  }

 private:
  const T* values_ = nullptr;
  Index first_ = 0;
  Index held_ = 0;
  Index count_ = 0;
};

}  // namespace spall
