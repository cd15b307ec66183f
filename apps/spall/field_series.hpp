#pragma once
// The d3plot series of a run: a .vtu per output time, listed in d3plot.pvd. Under MPI every rank
// writes its piece of each output time (its own nodes, solver::snapshot_fields) as
// d3plot_NNNNN/d3plot_NNNNN_R.vtu, and rank 0 the d3plot_NNNNN.pvtu that joins them and the .pvd
// that lists it, so that ParaView opens one dataset per time either way.
#include <filesystem>

#include "spall/core/archive.hpp"
#include "spall/io/output/vtu.hpp"
#include "spall/solver/simulation.hpp"

namespace spall::cli {

class FieldSeries {
 public:
  // The series in the run's folder `out` (which rank 0 creates; the pieces' folders each rank).
  explicit FieldSeries(const std::filesystem::path& out);

  // The problem's state as the series' next output time. Every rank calls it at the same step.
  void write(const solver::StepInfo& step, const solver::Problem& problem);
  // The last file written (rank 0: the .vtu, or the .pvtu under MPI).
  std::filesystem::path last_file() const;

  // The series' entries and count; read back, rank 0 writes the .pvd over to list what they list.
  void checkpoint(Archive& a);

 private:
  std::filesystem::path out_;
  io::output::PvdSeries pvd_;
  int count_ = 0;
};

}  // namespace spall::cli
