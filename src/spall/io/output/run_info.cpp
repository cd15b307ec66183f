#include "spall/io/output/run_info.hpp"

#include <cmath>
#include <ostream>
#include <string_view>

#include <fmt/format.h>

#include "spall/io/output/atomic_file.hpp"

namespace spall::io::output {
namespace {

// A JSON string literal (RFC 8259 section 7): quotes, backslashes and control characters escaped;
// other bytes, UTF-8 included, pass through.
std::string json_string(std::string_view text) {
  std::string quoted = "\"";
  for (const char c : text) {
    switch (c) {
      case '"': quoted += "\\\""; break;
      case '\\': quoted += "\\\\"; break;
      case '\b': quoted += "\\b"; break;
      case '\f': quoted += "\\f"; break;
      case '\n': quoted += "\\n"; break;
      case '\r': quoted += "\\r"; break;
      case '\t': quoted += "\\t"; break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          quoted += fmt::format("\\u{:04x}", static_cast<unsigned>(c));
        } else {
          quoted += c;
        }
    }
  }
  return quoted + '"';
}

// JSON has no infinity or NaN; null says "no number" to every reader.
std::string json_number(double value) {
  return std::isfinite(value) ? fmt::format("{:.17g}", value) : "null";
}

}  // namespace

void write_run_json(const std::filesystem::path& path, const RunInfo& info) {
  std::string phases;
  for (const auto& [name, seconds] : info.phases)
    phases += fmt::format("{}{}: {}", phases.empty() ? "" : ", ", json_string(name), json_number(seconds));
  std::string masses = fmt::format("\"initial\": {}", json_number(info.initial_mass));
  for (const auto& [name, value] : info.masses)
    masses += fmt::format(", {}: {}", json_string(name), json_number(value));
  const std::string json = fmt::format(
      "{{\n"
      "  \"version\": {},\n"
      "  \"deck\": {},\n"
      "  \"threads\": {},\n"
      "  \"ranks\": {},\n"
      "  \"rebalances\": {},\n"
      "  \"halo\": {},\n"
      "  \"received_bytes_per_step\": {{\"mean\": {}, \"max\": {}}},\n"
      "  \"communicating_seconds\": {{\"mean\": {}, \"max\": {}}},\n"
      "  \"node_rows\": {{\"mean\": {}, \"max\": {}}},\n"
      "  \"peak_resident_bytes\": {{\"mean\": {}, \"max\": {}}},\n"
      "  \"steps\": {},\n"
      "  \"end_time\": {},\n"
      "  \"wall_seconds\": {},\n"
      "  \"nodes\": {},\n"
      "  \"mass\": {{{}}},\n"
      "  \"phases\": {{{}}},\n"
      "  \"energy_ratio\": {},\n"
      "  \"status\": {}\n"
      "}}\n",
      json_string(info.version), json_string(info.deck), info.threads, info.ranks, info.rebalances,
      json_string(info.halo),
      json_number(info.received_bytes_mean), json_number(info.received_bytes_max),
      json_number(info.communicating_seconds_mean), json_number(info.communicating_seconds_max),
      json_number(info.node_rows_mean), info.node_rows_max, json_number(info.peak_resident_bytes_mean),
      info.peak_resident_bytes_max, info.steps,
      json_number(info.end_time), json_number(info.wall_seconds), info.nodes, masses,
      phases, json_number(info.energy_ratio), json_string(info.status));
  replace_file_atomically(path, [&](std::ostream& out) { out << json; });
}

}  // namespace spall::io::output
