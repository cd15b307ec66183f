// Throughput of the keyword reader on the largest public deck (the 1.2 MB bird strike).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "spall/io/keyword/reader.hpp"

namespace {

void read_bird_strike(benchmark::State& state) {
  const std::filesystem::path deck =
      std::filesystem::path(SPALL_SOURCE_DIR) / ".." / "shared" / "decks" / "public" /
      "ansys-example-data_bird_strike.k";
  std::size_t nodes = 0;
  for (auto _ : state) {
    const auto model = spall::io::keyword::read_deck(deck);
    nodes = model.nodes.size();
    benchmark::DoNotOptimize(nodes);
  }
  state.counters["nodes"] = static_cast<double>(nodes);
  state.SetBytesProcessed(static_cast<std::int64_t>(state.iterations()) *
                          static_cast<std::int64_t>(std::filesystem::file_size(deck)));
}
BENCHMARK(read_bird_strike)->Unit(benchmark::kMillisecond);

}  // namespace
