#include "residual_report.hpp"

#include <fmt/format.h>

namespace spall::cli {

namespace {
const char* category_name(int category) {
  switch (category) {
    case 0: return "interior";
    case 1: return "inner layer";
    case 2: return "surface";
    default: return "all";
  }
}


std::vector<io::output::Column> columns() {
  return {{"time", "time"},
          {"part", ""},
          {"category", ""},  // -1 all, 0 interior, 1 inner layer, 2 surface
          {"particles", ""},
          {"von_mises_max", "stress"},
          {"von_mises_mean", "stress"},
          {"von_mises_p95", "stress"},
          {"residual_particles", ""}};
}
}  // namespace

ResidualStressReport::ResidualStressReport(const std::filesystem::path& path,
                                           const sph::SolidFormulation& solid,
                                           const model::SphResidualStress& options,
                                           std::optional<std::uint64_t> resume_at)
    : ResidualStressReport(solid, options) {
  csv_.emplace(resume_at ? io::output::CsvHistory(path, columns(), *resume_at) : io::output::CsvHistory(path, columns()));
}

ResidualStressReport::ResidualStressReport(const sph::SolidFormulation& solid, const model::SphResidualStress& options)
    : solid_(solid), criterion_{options.yield_fraction, options.strain_rate}, at_output_(options.at_output == 1) {}

void ResidualStressReport::at_field_output(double time) {
  if (at_output_) write(time);
}

std::string ResidualStressReport::finish(double end_time) {
  if (!at_output_) write(end_time);
  return summary();
}

void ResidualStressReport::write(double time) {
  last_ = solid_.residual_stress(criterion_);
  if (!csv_) return;
  for (const auto& r : last_) {
    const double row[] = {time, static_cast<double>(r.part), static_cast<double>(r.category),
                          static_cast<double>(r.particles), r.von_mises_max, r.von_mises_mean,
                          r.von_mises_p95, static_cast<double>(r.residual)};
    csv_->append(row);
  }
}

std::string ResidualStressReport::summary() const {
  std::string text = fmt::format("residual stress (von Mises > {:g} of yield at near-zero strain rate):",
                                 criterion_.yield_fraction);
  for (const auto& r : last_) {
    if (r.category == -1) {
      text += fmt::format(" part {}: {} of {} particles, largest von Mises {:.4g}", r.part, r.residual,
                          r.particles, r.von_mises_max);
    } else if (r.particles > 0) {
      text += fmt::format(" ({} {})", category_name(r.category), r.residual);
    }
  }
  return text + "; see residual.csv";
}

}  // namespace spall::cli
