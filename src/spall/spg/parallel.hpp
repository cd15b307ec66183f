#pragma once
// When an SPG loop over particles runs on threads. Below a few thousand particles a loop is cheaper
// than waking the threads (and on a busy machine a barrier can cost milliseconds), so small parts
// run their loops on the calling thread. Results never depend on it: every loop writes per
// particle and every sum has a fixed order.
#include "spall/core/parallel.hpp"

namespace spall::spg {

inline constexpr Index parallel_threshold = 2048;
inline constexpr parallel::Schedule particle_loops{.serial_below = parallel_threshold + 1};

}  // namespace spall::spg
