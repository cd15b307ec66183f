#pragma once
// The bucket search of a contact pass: a uniform grid of cells over the master segments, each
// segment listed in every cell its box (grown by its release depth) overlaps. A node can only be
// in contact with a segment of its own cell. Rebuilt every step from the current positions: it
// costs a pass over the segments, far less than the slave loop, and no motion can outrun it.
#include <cstdint>
#include <span>
#include <vector>

#include "spall/contact/segment.hpp"
#include "spall/core/types.hpp"

namespace spall::contact {

class SegmentGrid {
 public:
  // Sorts the segments; reach[s] is how far beyond segment s a node may lie and still touch it.
  void build(std::span<const Segment> segments, std::span<const Real> reach, std::span<const Vec3> x);

  // The segments whose cell holds p, in ascending order (empty outside the grid).
  std::span<const Index> candidates(const Vec3& p) const;

  // Whether p lies in segment s's box, grown by its reach: a cheap test before the closest point.
  bool within_reach(Index s, const Vec3& p) const {
    return (p.array() >= box_lo_[s].array()).all() && (p.array() <= box_hi_[s].array()).all();
  }

 private:
  Vec3 lower_ = Vec3::Zero();
  Real inverse_cell_ = 0;
  std::array<Index, 3> dims_{};
  std::vector<Index> first_;     // CSR: the segments of cell c are list_[first_[c] .. first_[c + 1])
  std::vector<Index> list_;
  std::vector<Vec3> box_lo_, box_hi_;
};

}  // namespace spall::contact
