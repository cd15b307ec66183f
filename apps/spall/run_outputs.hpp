#pragma once
// The files rank 0 of a run writes as it goes: the d3plot series (field_series.hpp), glstat.csv,
// and where the deck has them rwforc.csv, rcforc.csv, rbdout.csv, nodout.csv, elout.csv,
// spcforc.csv, bndout.csv, matsum.csv and the SPH solids' residual.csv; and the observer that writes them.
// What they hold so far is part of a checkpoint, so that a restart cuts them back to it and
// carries on.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "field_series.hpp"
#include "residual_report.hpp"
#include "spall/core/archive.hpp"
#include "spall/io/output/history.hpp"
#include "spall/io/output/vtu.hpp"
#include "spall/model/model.hpp"
#include "spall/solver/simulation.hpp"

namespace spall::cli {

class RunOutputs {
 public:
  // The files of `problem` in `out`: created now, or with `resume` left for checkpoint() to take
  // back as a checkpoint had them.
  RunOutputs(const std::filesystem::path& out, const solver::Problem& problem, const model::Model& model, bool resume);

  // Writes the field, energy, force and body histories (on_step is left to the caller).
  solver::Observer observer();
  // A field output of the current state (the series' next file).
  void write_fields(const solver::StepInfo& step, const solver::Problem& problem);
  std::filesystem::path last_field_file() const;
  // At the end of a completed run: residual.csv's final rows, and its summary for the log.
  std::optional<std::string> finish(double end_time);
  // The masses of glstat's last row (eroded_mass, added_mass, ...), for run.json.
  const std::vector<std::pair<std::string, double>>& masses() const { return masses_; }

  // The d3plot series, which every rank has (the others' their pieces'): checkpointed on its own.
  FieldSeries& field_series() { return fields_; }

  // The histories' lengths, written; read back, the files are cut to those lengths and opened to
  // append.
  void checkpoint(Archive& a);

 private:
  struct History {
    std::filesystem::path path;
    std::vector<io::output::Column> columns;  // empty until known (glstat's: at its first row)
    std::optional<io::output::CsvHistory> file;
  };
  void open(History& h) { h.file.emplace(h.path, h.columns); }

  std::filesystem::path out_;
  const solver::Problem& problem_;
  FieldSeries fields_;
  History glstat_, rwforc_, rcforc_, rbdout_, nodout_, elout_, spcforc_, bndout_, matsum_;
  const sph::SolidFormulation* solid_ = nullptr;
  model::SphResidualStress residual_options_;
  std::optional<ResidualStressReport> residual_;
  std::vector<std::pair<std::string, double>> masses_;
};

}  // namespace spall::cli
