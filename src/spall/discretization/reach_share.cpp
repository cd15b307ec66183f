#include "spall/discretization/reach_share.hpp"

namespace spall::discretization {

// What this rank reads of each other rank's particles, in particle order, is what it asks of that
// rank: first how many (one number to each rank), then which (their indices). What each rank is
// asked is what it sends, in the asker's order.
void ReachShare::plan(std::span<const std::uint8_t> reads, std::span<const Index> node, const ParticleShare& share) {
  const parallel::Communicator& ranks = parallel::world();
  const int size = ranks.size();
  std::vector<std::vector<Index>> wanted(size);
  for (Index a = 0; a < static_cast<Index>(reads.size()); ++a)
    if (reads[a] && !share.owns(node[a])) wanted[share.rank_of(node[a])].push_back(a);
  receive_.clear();
  receive_offsets_.assign(size + 1, 0);
  for (int r = 0; r < size; ++r) {
    receive_offsets_[r] = static_cast<Index>(receive_.size());
    receive_.insert(receive_.end(), wanted[r].begin(), wanted[r].end());
  }
  receive_offsets_[size] = static_cast<Index>(receive_.size());
  std::vector<Index> one_each(size + 1), asked(size), wanted_count(size);
  for (int r = 0; r <= size; ++r) one_each[r] = r;
  for (int r = 0; r < size; ++r) wanted_count[r] = receive_offsets_[r + 1] - receive_offsets_[r];
  ranks.exchange(std::span<const Index>(wanted_count), one_each, std::span(asked), one_each);
  send_offsets_.assign(size + 1, 0);
  for (int r = 0; r < size; ++r) send_offsets_[r + 1] = send_offsets_[r] + asked[r];
  send_.resize(send_offsets_[size]);
  ranks.exchange(std::span<const Index>(receive_), receive_offsets_, std::span(send_), send_offsets_);
}

}  // namespace spall::discretization
