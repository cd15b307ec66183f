// Field output cost: how fast write_vtu puts particles on disk (bytes/s includes the file system).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <unistd.h>

#include "spall/io/output/vtu.hpp"

namespace {

using spall::Vec3;
using spall::discretization::Field;

void BM_WriteVtu(benchmark::State& state) {
  const auto n = static_cast<std::size_t>(state.range(0));
  std::vector<Vec3> points(n);
  std::vector<double> velocity(3 * n), stress(6 * n), pressure(n);
  std::vector<std::int64_t> category(n);
  for (std::size_t i = 0; i < n; ++i) {
    points[i] = Vec3(double(i % 100), double(i / 100 % 100), double(i / 10000));
    pressure[i] = double(i);
    category[i] = std::int64_t(i % 3);
  }
  const std::vector<Field> fields{
      {"velocity", 3, velocity},
      {"stress", 6, stress, spall::discretization::symmetric_tensor_components},
      {"pressure", 1, pressure},
      {"category", 1, category}};
  const auto path = std::filesystem::temp_directory_path() /
                    ("spall_bench_" + std::to_string(::getpid()) + ".vtu");
  for (auto _ : state) spall::io::output::write_vtu(path, points, fields);
  state.SetBytesProcessed(std::int64_t(state.iterations()) *
                          std::int64_t(std::filesystem::file_size(path)));
  state.counters["particles/s"] =
      benchmark::Counter(double(n) * double(state.iterations()), benchmark::Counter::kIsRate);
  std::filesystem::remove(path);
}
BENCHMARK(BM_WriteVtu)->Arg(10'000)->Arg(1'000'000)->Unit(benchmark::kMillisecond)->UseRealTime();  // the disk counts

}  // namespace
