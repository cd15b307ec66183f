#pragma once
// Whether particles that are now close have moved together since an earlier configuration: the
// test behind VerletList::needs_rebuild. OpenMP inside; the answer never depends on the thread
// count (it is made of exact min/max reductions and comparisons only).
#include <span>

#include "spall/core/communicator.hpp"
#include "spall/core/stretch_view.hpp"
#include "spall/core/types.hpp"
#include "spall/neighbors/cell_list.hpp"

namespace spall::neighbors {

// True only when every pair (i, j) now closer than `distance` (> 0) has moved by at most `limit`
// relative to each other since `before`: |d_i - d_j| <= limit with d = x - before. May answer
// false for a motion that satisfies this (the test bounds displacements by boxes); answers false
// for a non-finite position. `before` must be finite and as long as x.
bool close_pairs_moved_together(StretchView<Vec3> x, StretchView<Vec3> before, Real distance, Real limit);

// The same answer over several ranks, each holding current only the positions of its particles
// `own` (the others' may be stale, or not held: `x` and `before` may be stretches that hold
// `own`): every rank reads its own, the boxes are merged over `ranks` (min and max: exact), and
// every rank answers alike, as one process would over all of x.
bool close_pairs_moved_together(StretchView<Vec3> x, StretchView<Vec3> before, Real distance, Real limit,
                                ParticleRange own, const parallel::Communicator& ranks);

}  // namespace spall::neighbors
