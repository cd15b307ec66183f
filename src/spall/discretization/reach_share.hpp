#pragma once
// Under MPI with replicated storage (docs/SCALING.md §3, "The halo by reach"): each step, only the
// other ranks' particles that this rank's passes read come in, from the ranks that compute them.
// A formulation marks what its rows read (plan, at each neighbour-list build and each new deal of
// the nodes); the ranks then tell each other which of their particles they want, by the node's
// place in the deck (each rank may store its particles, and its nodes, in an order of its own), and
// each step's share sends just those. The rest of the other ranks' particles go stale until the
// formulation completes its state (ParticleShare, whole), or are not held (a rank's
// own rows, dealt by region).
#include <algorithm>
#include <cstddef>
#include <cstring>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/stretch_view.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/particle_share.hpp"

namespace spall::discretization {

class ReachShare {
 public:
  // The particles [first, end) of a formulation's, as plan takes them.
  struct Stretch {
    Index first = 0, end = 0;
  };
  // `reads[a]` is 1 where this rank's passes read particle a (its own particles are skipped);
  // `node[a]` names a's node in `nodes` (NodeStore::node_place), whose rank `share` knows.
  // Collective: every rank plans at once.
  // `within`: a stretch of the particles that holds every one read and this rank's own (the others
  // are then not looked at: under MPI a rank's passes stay off the rest).
  void plan(std::span<const std::uint8_t> reads, std::span<const Index> node, const ParticleShare& share,
            const NodeStore& nodes, Stretch within) {
    plan_by_place(reads, node, share, [&](Index a) { return nodes.node_place(node[a]); }, within);
  }
  // The same where particles share a node (a mesh's elements, each computed by the rank of its
  // first node, `node[a]`): every rank names particle a by place(a), which no other particle has.
  template <typename Place>
  void plan_by_place(std::span<const std::uint8_t> reads, std::span<const Index> node, const ParticleShare& share,
                     Place&& place, Stretch within) {
    std::vector<std::vector<Index>> wanted(parallel::world().size());  // by the rank that computes them
    std::vector<std::pair<Index, Index>> own;                          // (place, particle)
    for (Index a = within.first; a < within.end; ++a) {
      if (share.owns(node[a]))
        own.emplace_back(place(a), a);
      else if (reads[a])
        wanted[share.rank_of(node[a])].push_back(a);
    }
    std::vector<Index> wanted_places;
    for (const auto& particles : wanted)
      for (const Index a : particles) wanted_places.push_back(place(a));
    ask(wanted, wanted_places, std::move(own));
  }
  void plan(std::span<const std::uint8_t> reads, std::span<const Index> node, const ParticleShare& share,
            const NodeStore& nodes) {
    plan(reads, node, share, nodes, {0, static_cast<Index>(node.size())});
  }
  // The same for passes over rows in compressed form (a neighbour list, SPG's bonds): the rank
  // reads every row it computes (`computes(a)`, in `rows`, which holds its own particles; the
  // entries of those rows held in `entries`) and each particle in it. Returns those reads.
  template <typename Computes>
  std::vector<std::uint8_t> plan_rows(std::span<const Index> offsets, StretchView<Index> entries,
                                      Computes&& computes, std::span<const Index> node, const ParticleShare& share,
                                      const NodeStore& nodes, Stretch rows) {
    std::vector<std::uint8_t> reads(node.size(), 0);
    Stretch read{rows.first, rows.end};  // holds the rows, so also the rank's own particles
    for (Index a = rows.first; a < rows.end; ++a) {
      if (!computes(a)) continue;
      reads[a] = 1;
      for (Index k = offsets[a]; k < offsets[a + 1]; ++k) {
        const Index b = entries[k];
        reads[b] = 1;
        read.first = std::min(read.first, b);
        read.end = std::max(read.end, b + 1);
      }
    }
    plan(reads, node, share, nodes, read);
    return reads;
  }
  template <typename Computes>
  std::vector<std::uint8_t> plan_rows(std::span<const Index> offsets, StretchView<Index> entries,
                                      Computes&& computes, std::span<const Index> node, const ParticleShare& share,
                                      const NodeStore& nodes) {
    return plan_rows(offsets, entries, computes, node, share, nodes, {0, static_cast<Index>(node.size())});
  }
  // The particles whose nodes `nodes` holds rows of (every node unless a window:
  // NodeStore::holds_place), each from the rank that computed it (`share`: the deal it was computed
  // in). Collective.
  void plan_held(std::span<const Index> node, const ParticleShare& share, const NodeStore& nodes);
  bool planned() const { return !receive_offsets_.empty(); }
  // Particles this rank sends and receives a step.
  Index sent() const { return static_cast<Index>(send_.size()); }
  Index received() const { return static_cast<Index>(receive_.size()); }

  // The planned particles' values of each array (one value a particle, indexed by the particle:
  // a std::vector or a RangeArray holding them; empty arrays are state the options switched off
  // and travel not) from their ranks, in one message per pair of ranks. Values travel as their
  // bytes, as MPI sends them: plain structs and Eigen's fixed-size matrices.
  template <typename... Array>
  void operator()(Array&... values) const {
    arrays([&](auto&& each) { (each(values), ...); });
  }
  // The same for the arrays that for_each_array(each) hands to each(array), always in one order.
  template <typename ForEachArray>
  void arrays(ForEachArray&& for_each_array) const {
    if (!planned()) return;
    std::size_t record = 0;
    for_each_array([&](auto& array) { record += array.empty() ? 0 : sizeof(array[0]); });
    if (record == 0) return;
    std::vector<std::byte> send(send_.size() * record), receive(receive_.size() * record);
    std::size_t at = 0;
    for_each_array([&](auto& array) {
      if (array.empty()) return;
      constexpr std::size_t bytes = sizeof(array[0]);
      parallel::for_each(static_cast<Index>(send_.size()), [&](Index k) {
        std::memcpy(send.data() + k * record + at, &array[send_[k]], bytes);
      });
      at += bytes;
    });
    parallel::world().exchange_records(send, record, send_offsets_, receive, receive_offsets_);
    at = 0;
    for_each_array([&](auto& array) {
      if (array.empty()) return;
      constexpr std::size_t bytes = sizeof(array[0]);
      parallel::for_each(static_cast<Index>(receive_.size()), [&](Index k) {
        std::memcpy(static_cast<void*>(&array[receive_[k]]), receive.data() + k * record + at, bytes);
      });
      at += bytes;
    });
  }

  // The same for arrays of rows of different lengths (compressed rows, the SPG bonds): particle a's
  // entries are [row_offsets[a], row_offsets[a + 1]), the same offsets on every rank, so each rank
  // knows how many entries of a particle come in; an array indexed by entry (a std::vector, or a
  // RangeArray holding the entries of the rows sent and received). Empty arrays travel not.
  template <typename... Array>
  void rows(std::span<const Index> row_offsets, Array&... values) const {
    if (!planned()) return;
    const std::size_t record = ((values.empty() ? 0 : sizeof(typename Array::value_type)) + ... + 0);  // bytes an entry
    if (record == 0) return;
    // Each particle's first entry in the message, and each rank's.
    const auto places = [&](const std::vector<Index>& particles, const std::vector<Index>& by_rank,
                            std::vector<Index>& first, std::vector<Index>& rank_first) {
      first.assign(particles.size() + 1, 0);
      for (std::size_t k = 0; k < particles.size(); ++k)
        first[k + 1] = first[k] + row_offsets[particles[k] + 1] - row_offsets[particles[k]];
      rank_first.resize(by_rank.size());
      for (std::size_t r = 0; r < by_rank.size(); ++r) rank_first[r] = first[by_rank[r]];
    };
    std::vector<Index> send_first, send_offsets, receive_first, receive_offsets;
    places(send_, send_offsets_, send_first, send_offsets);
    places(receive_, receive_offsets_, receive_first, receive_offsets);
    std::vector<std::byte> send(send_first.back() * record), receive(receive_first.back() * record);
    // A particle's entries of each array one after the other, in the order of the arrays.
    const auto copy_rows = [&](const std::vector<Index>& particles, const std::vector<Index>& first,
                               std::vector<std::byte>& message, bool packing) {
      parallel::for_each(static_cast<Index>(particles.size()), [&](Index k) {
        const Index a = particles[k], count = row_offsets[a + 1] - row_offsets[a];
        std::byte* at = message.data() + first[k] * record;
        const auto copy = [&](auto& array) {
          if (array.empty() || count == 0) return;
          const std::size_t bytes = count * sizeof(array[0]);
          void* entries = &array[row_offsets[a]];
          if (packing)
            std::memcpy(at, entries, bytes);
          else
            std::memcpy(entries, at, bytes);
          at += bytes;
        };
        (copy(values), ...);
      });
    };
    copy_rows(send_, send_first, send, true);
    parallel::world().exchange_records(send, record, send_offsets, receive, receive_offsets);
    copy_rows(receive_, receive_first, receive, false);
  }

  // The same for state that is not one array a particle (a velocity stored by node): `pack(a)`
  // makes the record of this rank's particle a, `unpack(a, record)` stores another rank's.
  template <typename Record, typename Pack, typename Unpack>
  void records(Pack&& pack, Unpack&& unpack) const {
    if (!planned()) return;
    std::vector<Record> send(send_.size()), receive(receive_.size());
    parallel::for_each(sent(), [&](Index k) { send[k] = pack(send_[k]); });
    parallel::world().exchange(std::span<const Record>(send), send_offsets_, std::span(receive), receive_offsets_);
    parallel::for_each(received(), [&](Index k) { unpack(receive_[k], receive[k]); });
  }

 private:
  // Receives `wanted` (by rank, the particles' places in that order) and tells each rank which of
  // `own`'s it sends.
  void ask(const std::vector<std::vector<Index>>& wanted, std::span<const Index> wanted_places,
           std::vector<std::pair<Index, Index>> own);

  std::vector<Index> send_, send_offsets_;        // this rank's particles each other rank reads
  std::vector<Index> receive_, receive_offsets_;  // the other ranks' particles this rank reads
};

}  // namespace spall::discretization
