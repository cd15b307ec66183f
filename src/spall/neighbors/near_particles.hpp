#pragma once
// Under MPI, the particles of other ranks near this rank's own: what a search for the rows of a
// rank's own particles bins when the positions are not every rank's (the SPH solid's list builds,
// SPG's KERNEL 1 bond search).
#include <algorithm>
#include <type_traits>
#include <vector>

#include "spall/core/bounding_box.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/stretch_view.hpp"
#include "spall/core/types.hpp"
#include "spall/neighbors/cell_list.hpp"

namespace spall::neighbors {

// This rank's particles `own` at `x` inside another rank's box near[r] go to that rank as
// record(a) (a record whose `particle` names it); returns those that came in, and `binned`: the
// own particles and those, ascending, which a search bins for the rows near them. Collective.
template <typename Record>
std::vector<std::invoke_result_t<Record&, Index>> near_particles(ParticleRange own, StretchView<Vec3> x,
                                                                 const std::vector<BoundingBox>& near, Record&& record,
                                                                 std::vector<Index>& binned) {
  const parallel::Communicator& ranks = parallel::world();
  const int size = ranks.size(), self = ranks.rank();
  std::vector<std::vector<std::invoke_result_t<Record&, Index>>> to(size);
  // Only the ranks whose boxes meet the box of this rank's particles can take any (each particle
  // tested against every rank's box would be O(ranks) a particle); all where a position is not finite.
  BoundingBox mine;
  for (Index a = own.begin; a < own.end; ++a) mine.include(x[a]);
  std::vector<int> meeting;
  for (int r = 0; r < size; ++r)
    if (r != self && (!mine.finite || near[r].meets(mine))) meeting.push_back(r);
  for (Index a = own.begin; a < own.end; ++a)
    for (const int r : meeting)
      if (near[r].contains(x[a])) to[r].push_back(record(a));
  auto came = ranks.deliver(to);
  binned.clear();
  binned.reserve(own.end - own.begin + came.size());
  for (Index a = own.begin; a < own.end; ++a) binned.push_back(a);
  for (const auto& p : came) binned.push_back(static_cast<Index>(p.particle));
  std::sort(binned.begin(), binned.end());
  return came;
}

}  // namespace spall::neighbors
