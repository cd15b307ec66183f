#pragma once
// A formulation's per-particle arrays in a checkpoint, each particle's values as the rank that
// computes it holds them (core/pieces.hpp): under MPI with replicated storage every rank writes its
// own particles' values into the restart file at their place, so that no rank gathers another's
// state, and every rank reads every particle's back. An array the options switched off (empty) is
// written as such.
#include <algorithm>
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/pieces.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/discretization/particle_share.hpp"

namespace spall::discretization {

// `node[p]`: particle p's node as the formulation names it (NodeStore::node_place: its row, or its
// place in the node order where the rows are every node or a window of them); `share`: which
// particles this rank computes; each array a std::vector or a RangeArray that holds at least this
// rank's own particles. Read back, a std::vector is every particle's, a RangeArray holds the
// particles `keep` alone (under MPI a rank's own: no rank holds every particle's state then),
// whichever rows the store holds. Collective. A particle that is not this deck's or one missing
// stops every rank alike (`what` names the particles in the message).
template <typename... Array>
void archive_particle_pieces(Archive& a, const char* what, std::span<const Index> node, const ParticleShare& share,
                             const NodeStore& nodes, parallel::Range keep, Array&... arrays) {
  const parallel::Communicator& ranks = parallel::world();
  const Index n = static_cast<Index>(node.size());
  if (!a.reading()) {
    // (place in the deck's node order, particle), ascending; rank 0's every particle before the
    // ranks share the particles out (a checkpoint of the set-up's state).
    std::vector<std::pair<Index, Index>> own;
    for (Index p = 0; p < n; ++p)
      if (share.across() ? share.owns(node[p]) : ranks.rank() == 0) own.emplace_back(nodes.node_place(node[p]), p);
    std::sort(own.begin(), own.end());
    const Index count = static_cast<Index>(own.size());
    const auto place = [&](Index k) { return own[k].first; };
    parallel::write_pieces<Index>(a, count, place, place, ranks);
    const auto write = [&](const auto& array) {
      parallel::write_array_pieces(a, array, count, [&](Index k) { return own[k].second; }, place, ranks);
    };
    (write(arrays), ...);
    return;
  }
  // Every particle by its node's place, whichever rows the store holds (every node, or a rank's
  // window of them where the set-up built its block).
  std::vector<std::pair<Index, Index>> by_place(n);
  for (Index p = 0; p < n; ++p) by_place[p] = {nodes.node_place(node[p]), p};
  std::sort(by_place.begin(), by_place.end());
  std::vector<Index> particle;  // each item's, in the file's order (-1: not this deck's)
  std::vector<std::uint8_t> filled(n, 0);
  Index mismatch = -1;
  parallel::read_pieces<Index>(a, [&](Index place) {
    const auto at = std::lower_bound(by_place.begin(), by_place.end(), std::pair<Index, Index>{place, -1});
    const Index p = at != by_place.end() && at->first == place ? at->second : -1;
    if ((p < 0 || filled[p]) && mismatch < 0) mismatch = place;
    if (p >= 0) filled[p] = 1;
    particle.push_back(p);
  });
  Index missing = -1;
  for (Index p = 0; p < n && missing < 0; ++p)
    if (!filled[p]) missing = nodes.node_place(node[p]);
  parallel::check_read(a, what, mismatch, missing, nullptr);
  // The places of the particles kept: a stretch of them reads those stretches of each piece alone.
  parallel::Range places{0, 0};
  for (Index p = keep.begin; p < keep.end; ++p) {
    const Index place = nodes.node_place(node[p]);
    places = parallel::hull(places, {place, place + 1});
  }
  const auto read = [&](auto& array) {
    parallel::read_array_pieces(a, array, n, keep, [&](Index k) { return particle[k]; }, places);
  };
  (read(arrays), ...);
}

}  // namespace spall::discretization
