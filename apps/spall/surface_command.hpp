#pragma once
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace spall::cli {

struct SurfaceOptions {
  std::string output_dir;           // a run's output folder: d3plot.pvd and its .vtu files
  std::optional<double> time;       // the snapshot at or last before it; none: the last
  double iso = 0.5;                 // colour on the surface
  double cell = 0;                  // grid spacing; 0: half the median smoothing length
  std::vector<std::string> fields;  // point fields carried to the vertices; empty: every one
  std::vector<std::int64_t> parts;  // parts whose particles make the body; empty: every SPH part
};

// Reconstructs the surface of one snapshot's SPH particles and writes surface_NNNNN.vtp and .ply
// beside it. Returns the exit code; throws InputError for a folder or option it cannot use.
int reconstruct_surface(const SurfaceOptions& options);

}  // namespace spall::cli
