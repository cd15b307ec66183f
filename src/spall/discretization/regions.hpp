#pragma once
// Under MPI, ownership by region (docs/SCALING.md §3, "Ownership by region"): space cut into one
// region a rank by recursive coordinate bisection (RCB; Berger & Bokhari 1987), each cut across the
// longest side of its points' box where the weight on either side is in proportion to the ranks
// that side gets. A node belongs to the rank whose region holds it; the cuts stay until the ranks'
// work drifts apart, and the nodes move between regions as they flow (NodeStore::migrate).
#include <span>
#include <vector>

#include "spall/core/bounding_box.hpp"
#include "spall/core/types.hpp"

namespace spall::discretization {

class Regions {
 public:
  // The cuts of `ranks` regions for the points x[i] of weight w[i] (at least 0; a point of weight
  // 0 counts for nothing, unless none weighs anything: then each counts as one). A cut falls between two distinct coordinates, where the weight below it
  // comes closest to its share: points of one coordinate are never split, so the regions hold their
  // share to within one plane of a lattice. The same points give the same cuts on every rank.
  static Regions cut(std::span<const Vec3> x, std::span<const double> w, int ranks);

  bool empty() const { return ranks_ == 0; }
  int ranks() const { return ranks_; }
  // The rank whose region holds p: below a cut is its lower side (every point of space has one).
  int rank_of(const Vec3& p) const;
  // The box of rank r's region, closed (its upper faces belong to the next region), its sides
  // infinite where no cut bounds it.
  BoundingBox box(int r) const;

 private:
  // One node of the tree: ranks [first, first + count); a leaf when count is 1, else the points
  // with p[axis] < at go to `low` (the first count / 2 ranks), the others to `high`.
  struct Split {
    int first = 0, count = 1;
    int axis = 0;
    Real at = 0;
    int low = -1, high = -1;
  };
  int add(std::span<const Vec3> x, std::span<const double> w, std::span<Index> points, int first, int count);

  std::vector<Split> splits_;  // splits_[0] is the whole of space
  int ranks_ = 0;
};

}  // namespace spall::discretization
