#include "spall/sph/force_blocks.hpp"

#include <algorithm>

#include "spall/core/communicator.hpp"

namespace spall::sph {

void ForceBlocks::assign(Index particles, Index count, Index length, std::span<const Index> particle_begin,
                         int rank) {
  particles_ = particles, count_ = count, length_ = length, rank_ = rank;
  ranks_ = particle_begin.empty() ? 1 : static_cast<int>(particle_begin.size()) - 1;
  runner_.clear();
  handoff_ = {}, delivery_ = {};
  for (auto& blocks : run_) blocks.clear();
  if (ranks_ > 1 && count_ > 0) {
    const auto owner = [&](Index a) {
      return static_cast<int>(std::upper_bound(particle_begin.begin(), particle_begin.end(), a) -
                              particle_begin.begin()) - 1;
    };
    runner_.resize(count_);
    for (Index j = 0; j < count_; ++j) runner_[j] = owner((begin(j) + end(j) - 1) / 2);
    // After the even blocks: an odd block j adds to its own particles, whose sums block j - 1
    // began, and to block j + 1's, which that block began.
    std::vector<Transfer> handoff;
    for (Index j = 1; j < count_; j += 2) {
      if (runner_[j - 1] != runner_[j]) handoff.push_back({begin(j), end(j), runner_[j - 1], runner_[j]});
      if (j + 1 < count_ && runner_[j + 1] != runner_[j])
        handoff.push_back({begin(j + 1), end(j + 1), runner_[j + 1], runner_[j]});
    }
    // After the odd blocks: an odd block's particles have their last term from its runner, an even
    // block's from the odd block before it (block 0's from its own runner), and go to their owners.
    std::vector<Transfer> delivery;
    for (Index j = 0; j < count_; ++j) {
      const int last_term = runner_[j % 2 == 1 || j == 0 ? j : j - 1];
      for (Index a = begin(j); a < end(j);) {
        const int r = owner(a);
        const Index run_end = std::min(end(j), particle_begin[r + 1]);
        if (r != last_term) delivery.push_back({a, run_end, last_term, r});
        a = run_end;
      }
    }
    handoff_ = plan(handoff);
    delivery_ = plan(delivery);
  }
  first_row_ = particles_, last_row_ = last_touched_ = 0;
  for (Index j = 0; j < count_; ++j)
    if (runs(j)) {
      run_[j % 2].push_back(j);
      first_row_ = std::min(first_row_, begin(j));
      last_row_ = end(j);
      last_touched_ = end(std::min(count_ - 1, j + 1));
    }
  if (last_row_ == 0) first_row_ = 0;
}

ForceBlocks::Plan ForceBlocks::plan(const std::vector<Transfer>& transfers) const {
  Plan p;
  for (const Transfer& t : transfers) {
    if (t.from == rank_) p.send.push_back(t);
    if (t.to == rank_) p.receive.push_back(t);
  }
  // By rank, each rank's runs in the list's order (stable), as MPI_Alltoallv lays them out.
  std::stable_sort(p.send.begin(), p.send.end(), [](const Transfer& a, const Transfer& b) { return a.to < b.to; });
  std::stable_sort(p.receive.begin(), p.receive.end(),
                   [](const Transfer& a, const Transfer& b) { return a.from < b.from; });
  p.send_offsets.assign(ranks_ + 1, 0);
  p.receive_offsets.assign(ranks_ + 1, 0);
  for (const Transfer& t : p.send) p.send_offsets[t.to + 1] += t.end - t.begin;
  for (const Transfer& t : p.receive) p.receive_offsets[t.from + 1] += t.end - t.begin;
  for (int r = 0; r < ranks_; ++r) {
    p.send_offsets[r + 1] += p.send_offsets[r];
    p.receive_offsets[r + 1] += p.receive_offsets[r];
  }
  return p;
}

void ForceBlocks::move(const Plan& plan, Eigen::Vector4d* sums, Index first) const {
  if (runner_.empty()) return;
  std::vector<Vec3> send(plan.send_offsets.back()), receive(plan.receive_offsets.back());
  Index k = 0;
  for (const Transfer& t : plan.send)
    for (Index a = t.begin; a < t.end; ++a) send[k++] = sums[a - first].head<3>();
  parallel::world().exchange(std::span<const Vec3>(send), plan.send_offsets, std::span(receive), plan.receive_offsets);
  k = 0;
  for (const Transfer& t : plan.receive)
    for (Index a = t.begin; a < t.end; ++a) sums[a - first] = {receive[k].x(), receive[k].y(), receive[k].z(), 0}, ++k;
}

}  // namespace spall::sph
