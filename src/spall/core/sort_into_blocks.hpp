#pragma once
// A sort over the ranks of items of which each rank holds a share: every rank ends with its block
// of the sorted whole, the blocks of block_begin. For the node order of a deck whose cards every
// rank holds a share of (docs/SCALING.md §5 step 4 f3): the spatial order is a sort over the ranks
// of (cell key, ordinal), after which each rank holds the cards of its block of the order, as the
// set-up in blocks needs them.
#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <span>
#include <type_traits>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/types.hpp"

namespace spall::parallel {

// Collective: the items spread over the ranks in any amounts, each with a key that no other item
// on any rank has, come back as this rank's block of them all in ascending key, items
// [block_begin(n, rank, size), block_begin(n, rank + 1, size)) of the sorted whole (n the count over
// every rank). The keys alone decide: not how the items were spread. T and the key are moved as
// bytes (exchange, all). Memory and time O(n / size) a rank, plus the samples (max(64, size) a rank).
//
// A sample sort, then an exact shift: each rank sorts its own items and takes regular samples of
// their keys, each weighted by the items it stands for, so that a rank with many items weighs as
// much as they do; every rank picks the same splitters from all the samples, at the weighted places
// of the blocks' starts; each item goes to the rank of its splitters' bucket, which merges what it
// receives. The buckets are near the blocks (each end off by at most about n / k, k samples a rank),
// not equal: every rank then knows the place of each of its items in the whole from the ranks'
// counts, and sends each to the rank whose block holds that place.
template <typename T, typename KeyOf>
std::vector<T> sort_into_blocks(std::vector<T> items, KeyOf key_of, const Communicator& ranks) {
  using Key = std::decay_t<std::invoke_result_t<KeyOf&, const T&>>;
  const auto by_key = [&](const T& a, const T& b) { return key_of(a) < key_of(b); };
  std::sort(items.begin(), items.end(), by_key);
  const int size = ranks.size();
  if (size == 1) return items;

  // Sample j stands for this rank's items [j * m / k, (j + 1) * m / k): its key is their first.
  // As many samples a rank as ranks (64 at least) keep a bucket within about twice a block.
  struct Sample {
    Key key;
    Index weight;
  };
  const Index m = static_cast<Index>(items.size());
  const Index k = std::min<Index>(m, std::max(64, size));
  std::vector<Sample> mine(k);
  for (Index j = 0; j < k; ++j) {
    const Index first = static_cast<Index>(std::int64_t(j) * m / k);
    const Index end = static_cast<Index>(std::int64_t(j + 1) * m / k);
    mine[j] = {key_of(items[first]), end - first};
  }
  std::vector<Sample> samples = ranks.all(std::span<const Sample>(mine));
  if (samples.empty()) return items;  // no items on any rank
  std::sort(samples.begin(), samples.end(), [](const Sample& a, const Sample& b) { return a.key < b.key; });

  // Splitter r (r = 1 .. size - 1) is the sample whose items, in the samples' order, hold place
  // block_begin(n, r) of the whole; bucket r holds the keys from splitter r up to splitter r + 1.
  // Rank r's bucket is items [send[r], send[r + 1]) of this rank's sorted ones.
  Index n = 0;
  for (const Sample& s : samples) n += s.weight;
  std::vector<Index> send(size + 1, 0);
  send[size] = m;
  Index before = 0;
  std::size_t next = 0;
  for (int r = 1; r < size; ++r) {
    const Index target = block_begin(n, r, size);
    while (next + 1 < samples.size() && before + samples[next].weight <= target) before += samples[next++].weight;
    const Key& splitter = samples[next].key;
    send[r] = static_cast<Index>(
        std::lower_bound(items.begin() + send[r - 1], items.end(), splitter,
                         [&](const T& item, const Key& key) { return key_of(item) < key; }) -
        items.begin());
  }
  std::vector<Index> receive = ranks.offsets_in(send);
  std::vector<T> bucket(receive[size]);
  ranks.exchange(std::span<const T>(items), send, std::span<T>(bucket), receive);
  std::vector<T>().swap(items);
  // Each sender's run arrives sorted: merged in pairs, log2(size) passes over the bucket.
  for (int width = 1; width < size; width *= 2)
    for (int r = 0; r + width < size; r += 2 * width)
      std::inplace_merge(bucket.begin() + receive[r], bucket.begin() + receive[r + width],
                         bucket.begin() + receive[std::min(r + 2 * width, size)], by_key);

  // The shift: this rank's items are places [first, first + count) of the whole, and rank r's block
  // starts at block_begin(n, r). The buckets and the blocks both go up the ranks in key order, so
  // the runs come in from the lower ranks first and the block arrives sorted.
  const std::vector<Index> counts = ranks.each(static_cast<Index>(bucket.size()));
  Index first = 0;
  for (int r = 0; r < ranks.rank(); ++r) first += counts[r];
  const Index count = static_cast<Index>(bucket.size());
  for (int r = 0; r <= size; ++r) send[r] = std::clamp(block_begin(n, r, size) - first, Index(0), count);
  receive = ranks.offsets_in(send);
  std::vector<T> block(receive[size]);
  ranks.exchange(std::span<const T>(bucket), send, std::span<T>(block), receive);
  return block;
}

}  // namespace spall::parallel
