#pragma once
// Under MPI, ownership by region (docs/SCALING.md §3, "Ownership by region"): space cut into one
// region a rank by recursive coordinate bisection (RCB; Berger & Bokhari 1987), each cut across the
// longest side of its points' box where the weight on either side is in proportion to the ranks
// that side gets. A node belongs to the rank whose region holds it; the cuts stay until the ranks'
// work drifts apart, and the nodes move between regions as they flow (NodeStore::migrate).
#include <cstdint>
#include <span>
#include <vector>

#include "spall/core/bounding_box.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/types.hpp"

namespace spall::discretization {

class Regions {
 public:
  // The cuts of `ranks` regions for the points x[i] of weight w[i] (finite, at least 0; a point of
  // weight 0 counts for nothing, unless none weighs anything: then each counts as one), every
  // process of `among` holding some of the points (each point on one process). A cut falls between
  // two distinct coordinates, where the weight below it comes closest to its share (the first such
  // from below when two are as near): points of one coordinate are never split, so the regions
  // hold their share to within one plane of a lattice. Weights count in steps of 2^-30 of the
  // heaviest point's. No process sorts or holds more than its own points: each cut is found by
  // multisection, every process counting the weight of its points below 256 trial planes at once,
  // one sum over the processes a round for every split of a level of the tree, at most 9 rounds a
  // search (docs/SCALING.md, "Ownership by region"). The cuts depend on the points and weights
  // alone, not on how the processes share them, and every process gets the same. Collective.
  static Regions cut(std::span<const Vec3> x, std::span<const double> w, int ranks,
                     const parallel::Communicator& among);
  // Every point on this process.
  static Regions cut(std::span<const Vec3> x, std::span<const double> w, int ranks) {
    return cut(x, w, ranks, parallel::Communicator{});
  }

  bool empty() const { return ranks_ == 0; }
  int ranks() const { return ranks_; }
  // The rank whose region holds p: below a cut is its lower side (every point of space has one).
  int rank_of(const Vec3& p) const;
  // The box of rank r's region, closed (its upper faces belong to the next region), its sides
  // infinite where no cut bounds it.
  BoundingBox box(int r) const;
  // Each rank whose region's box grown by `reach` holds p (box(r).grown(reach).contains(p), the
  // same sums and comparisons), ascending: down the tree, so a point far from every cut visits
  // one leaf, not every rank's box.
  template <class Visit>
  void near(const Vec3& p, Real reach, Visit&& visit) const {
    if (!empty()) near(0, p, reach, visit);
  }
  friend bool operator==(const Regions&, const Regions&) = default;

 private:
  // One node of the tree: ranks [first, first + count); a leaf when count is 1, else the points
  // with p[axis] < at go to `low` (the first count / 2 ranks), the others to `high`.
  struct Split {
    int first = 0, count = 1;
    int axis = 0;
    Real at = 0;
    int low = -1, high = -1;
    friend bool operator==(const Split&, const Split&) = default;
  };
  template <class Visit>
  void near(int s, const Vec3& p, Real reach, Visit& visit) const {
    const Split& split = splits_[s];
    if (split.count == 1) return visit(split.first);
    if (p[split.axis] <= split.at + reach) near(split.low, p, reach, visit);
    if (p[split.axis] >= split.at - reach) near(split.high, p, reach, visit);
  }

  std::vector<Split> splits_;  // splits_[0] is the whole of space
  int ranks_ = 0;
};

}  // namespace spall::discretization
