#include "spall/discretization/reach_share.hpp"

#include <algorithm>
#include <utility>
#include <vector>

namespace spall::discretization {

// What this rank reads of each other rank's particles, in particle order, is what it asks of that
// rank: first how many (one number to each rank), then which, by their places (the node's place in
// the deck: the particles' order may be each rank's own, the fluid's cells near a rank's region,
// and so may the rows of its nodes). What each rank is asked is what it sends, in the asker's order.
void ReachShare::plan_held(std::span<const Index> node, const ParticleShare& share, const NodeStore& nodes) {
  std::vector<std::uint8_t> held(node.size());
  for (std::size_t a = 0; a < node.size(); ++a) held[a] = nodes.holds_place(node[a]);
  plan(held, node, share, nodes);
}

void ReachShare::ask(const std::vector<std::vector<Index>>& wanted, std::span<const Index> wanted_places,
                     std::vector<std::pair<Index, Index>> own) {
  const parallel::Communicator& ranks = parallel::world();
  const int size = ranks.size();
  receive_.clear();
  receive_offsets_.assign(size + 1, 0);
  for (int r = 0; r < size; ++r) {
    receive_offsets_[r] = static_cast<Index>(receive_.size());
    receive_.insert(receive_.end(), wanted[r].begin(), wanted[r].end());
  }
  receive_offsets_[size] = static_cast<Index>(receive_.size());
  send_offsets_ = ranks.offsets_in(receive_offsets_);
  send_.resize(send_offsets_[size]);
  ranks.exchange(wanted_places, receive_offsets_, std::span(send_), send_offsets_);
  // The places asked for, as this rank's particles.
  std::sort(own.begin(), own.end());
  for (Index& k : send_) k = std::lower_bound(own.begin(), own.end(), std::pair(k, Index(0)))->second;
}

}  // namespace spall::discretization
