#pragma once
// residual.csv: von Mises statistics per SPH part and colour-field category, and the particles
// that carry residual stress (seed 000; *SPALL_RESIDUAL_STRESS), with a one-line log summary.
#include <cstdint>
#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include "spall/io/output/history.hpp"
#include "spall/model/model.hpp"
#include "spall/sph/solid.hpp"

namespace spall::cli {

// The statistics are taken over the ranks, each of which holds its own particles' state
// (SolidFormulation::residual_stress, collective): every rank keeps a report, rank 0 with the file.
class ResidualStressReport {
 public:
  // A new residual.csv, or with `resume_at` the one a checkpoint had, cut to that many bytes.
  ResidualStressReport(const std::filesystem::path& path, const sph::SolidFormulation& solid,
                       const model::SphResidualStress& options, std::optional<std::uint64_t> resume_at = {});
  // On a rank that writes no output: takes part in the statistics alone.
  ResidualStressReport(const sph::SolidFormulation& solid, const model::SphResidualStress& options);
  // At a field output: the rows of the current state, when the deck asks for them there (OUTPUT 1).
  void at_field_output(double time);
  // At the end of a completed run: the final rows (unless the last field output wrote them), and
  // their summary for the log.
  std::string finish(double end_time);
  std::uint64_t bytes() const { return csv_ ? csv_->bytes() : 0; }

 private:
  // Appends the rows of the current state at `time`.
  void write(double time);
  std::string summary() const;

  const sph::SolidFormulation& solid_;
  sph::ResidualStressCriterion criterion_;
  bool at_output_ = false;
  std::optional<io::output::CsvHistory> csv_;
  std::vector<sph::ResidualStressRow> last_;
};

}  // namespace spall::cli
