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

class ResidualStressReport {
 public:
  // A new residual.csv, or with `resume_at` the one a checkpoint had, cut to that many bytes.
  ResidualStressReport(const std::filesystem::path& path, const sph::SolidFormulation& solid,
                       const model::SphResidualStress& options, std::optional<std::uint64_t> resume_at = {});
  // Appends the rows of the current state at `time`.
  void write(double time);
  // The last rows in one line, for the log.
  std::string summary() const;
  std::uint64_t bytes() const { return csv_.bytes(); }

 private:
  const sph::SolidFormulation& solid_;
  sph::ResidualStressCriterion criterion_;
  io::output::CsvHistory csv_;
  std::vector<sph::ResidualStressRow> last_;
};

}  // namespace spall::cli
