#include "field_series.hpp"

#include <string>
#include <system_error>
#include <vector>

#include <fmt/format.h>

#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/solver/field_output.hpp"

namespace spall::cli {

namespace fs = std::filesystem;

namespace {
std::string stem(int index) { return fmt::format("d3plot_{:05d}", index); }
}  // namespace

FieldSeries::FieldSeries(const fs::path& out) : out_(out), pvd_(out / "d3plot.pvd") {}

void FieldSeries::write(const solver::StepInfo& step, const solver::Problem& problem) {
  const parallel::Communicator& ranks = parallel::world();
  const auto snap = solver::snapshot_fields(problem);
  const std::string name = stem(count_++);
  if (ranks.size() == 1) {
    io::output::write_vtu(out_ / (name + ".vtu"), snap.points, snap.fields, snap.cell_blocks);
    pvd_.add(step.time, name + ".vtu");
    return;
  }
  const auto piece = [&](int rank) { return fmt::format("{}/{}_{}.vtu", name, name, rank); };
  // Every rank's piece is whole before the .pvtu lists it (a run killed in between leaves the
  // series as it was), and a rank that cannot write its piece stops every rank alike.
  std::string failure;
  try {
    std::error_code error;
    fs::create_directories(out_ / name, error);
    if (error) throw OutputError(fmt::format("{}: cannot create the folder: {}", (out_ / name).string(), error.message()));
    io::output::write_vtu(out_ / piece(ranks.rank()), snap.points, snap.fields, snap.cell_blocks);
  } catch (const OutputError& e) {
    failure = e.what();
  }
  double written = failure.empty() ? 0 : -1;
  ranks.minimum({&written, 1});
  if (written < 0)
    throw OutputError(failure.empty() ? fmt::format("{}: another rank could not write its piece", name) : failure,
                      true);
  if (ranks.rank() != 0) return;
  std::vector<std::string> pieces;
  for (int r = 0; r < ranks.size(); ++r) pieces.push_back(piece(r));
  io::output::write_pvtu(out_ / (name + ".pvtu"), pieces, snap.fields, snap.cell_blocks);
  pvd_.add(step.time, name + ".pvtu");
}

fs::path FieldSeries::last_file() const {
  return out_ / (stem(count_ - 1) + (parallel::world().size() == 1 ? ".vtu" : ".pvtu"));
}

void FieldSeries::checkpoint(Archive& a) {
  io::output::PvdSeries::Entries entries = pvd_.entries();
  a(entries, count_);
  // Rank 0 writes the .pvd (and the other ranks never do).
  if (a.reading() && parallel::world().rank() == 0) pvd_.restore(std::move(entries));
}

}  // namespace spall::cli
