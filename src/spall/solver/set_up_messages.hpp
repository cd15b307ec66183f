#pragma once
// What the set-up says of a node card or a particle card it cannot build from, in one text whether
// the nodes are set up whole on every rank (problem.cpp) or in blocks from the ranks' shares of the
// cards (nodes_in_blocks.cpp): the MPI tests compare a run's message with the single process's.
#include <string>

#include <fmt/format.h>

#include "spall/core/types.hpp"

namespace spall::solver::set_up_message {

inline std::string node_defined_twice(Id node) { return fmt::format("node {} is defined twice", node); }
inline std::string no_such_node(Id node) { return fmt::format("node {} does not exist", node); }
inline std::string node_with_two_particles(Id node) { return fmt::format("node {} carries two SPH particles", node); }
inline std::string no_mass(Id node) { return fmt::format("MASS: particle {} has no mass", node); }

}  // namespace spall::solver::set_up_message
