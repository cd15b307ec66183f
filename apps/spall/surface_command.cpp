#include "surface_command.hpp"

#include <algorithm>
#include <filesystem>
#include <variant>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/global_control.h>

#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "spall/core/parallel.hpp"
#include "spall/io/input/vtu_read.hpp"
#include "spall/io/output/ply.hpp"
#include "spall/io/output/vtp.hpp"
#include "spall/surface/reconstruct.hpp"
#include "spall/surface/vertex_fields.hpp"

namespace spall::cli {

namespace fs = std::filesystem;

namespace {

// The entry of the series at `time`, or the last one before it; the last entry without a time.
std::size_t pick_snapshot(const std::vector<io::input::SeriesEntry>& series, const fs::path& pvd,
                          const std::optional<double>& time) {
  if (series.empty()) throw InputError(fmt::format("{}: the series lists no snapshot", pvd.string()));
  if (!time) return series.size() - 1;
  std::optional<std::size_t> picked;
  for (std::size_t k = 0; k < series.size(); ++k)
    if (series[k].time <= *time && (!picked || series[k].time >= series[*picked].time)) picked = k;
  if (!picked)
    throw InputError(fmt::format("{}: no snapshot at or before time {:g} (the first is at {:g})",
                                 pvd.string(), *time, series.front().time));
  return *picked;
}

const std::vector<double>& real_field(const io::input::VtuSnapshot& snap, const fs::path& vtu,
                                      std::string_view name) {
  const auto* field = snap.field(name);
  if (!field)
    throw InputError(fmt::format("{}: no point field '{}' (the surface needs mass, density and "
                                 "smoothing_length of SPH particles)",
                                 vtu.string(), name));
  const auto* values = std::get_if<std::vector<double>>(&field->values);
  if (!values || field->components != 1)
    throw InputError(fmt::format("{}: point field '{}' is not one real per point", vtu.string(), name));
  return *values;
}

// The values of `field` at the points `keep` selects, in order.
discretization::Field gathered(const discretization::Field& field, const std::vector<Index>& keep) {
  discretization::Field out{field.name, field.components, {}, field.component_names};
  std::visit(
      [&](const auto& values) {
        std::decay_t<decltype(values)> kept;
        kept.reserve(keep.size() * field.components);
        for (Index i : keep)
          for (int c = 0; c < field.components; ++c) kept.push_back(values[std::size_t(i) * field.components + c]);
        out.values = std::move(kept);
      },
      field.values);
  return out;
}

// surface_NNNNN for d3plot_NNNNN.vtu, so that the two files of one time sort side by side.
std::string surface_stem(const std::string& vtu_file, std::size_t position) {
  const std::string stem = fs::path(vtu_file).stem().string();
  if (stem.starts_with("d3plot_")) return "surface_" + stem.substr(7);
  return fmt::format("surface_{:05d}", position);
}

}  // namespace

int reconstruct_surface(const SurfaceOptions& options) {
  const fs::path dir(options.output_dir);
  const fs::path pvd = dir / "d3plot.pvd";
  if (!fs::is_regular_file(pvd))
    throw InputError(fmt::format("{}: no such file (give the output folder of `spall run`)", pvd.string()));
  if (!(options.iso > 0)) throw InputError(fmt::format("--iso {:g}: must be positive", options.iso));
  if (!(options.cell >= 0)) throw InputError(fmt::format("--cell {:g}: must be positive", options.cell));

  const auto series = io::input::read_pvd(pvd);
  const std::size_t k = pick_snapshot(series, pvd, options.time);
  const fs::path vtu = dir / series[k].file;
  const io::input::VtuSnapshot snap = io::input::read_vtu(vtu);
  const auto& mass = real_field(snap, vtu, "mass");
  const auto& density = real_field(snap, vtu, "density");
  const auto& smoothing_length = real_field(snap, vtu, "smoothing_length");

  // SPH particles are the points with a smoothing length; other nodes (elements, rigid bodies)
  // have none and no volume to add to the colour field. --part keeps those of the parts named
  // (the water of a tank without its wall particles).
  const std::vector<std::int64_t>* part_id = nullptr;
  if (!options.parts.empty()) {
    const auto* field = snap.field("part_id");
    if (!field || field->components != 1 || !std::holds_alternative<std::vector<std::int64_t>>(field->values))
      throw InputError(fmt::format("--part: {} has no integer point field 'part_id'", vtu.string()));
    part_id = &std::get<std::vector<std::int64_t>>(field->values);
  }
  std::vector<Index> sph;
  for (std::size_t i = 0; i < snap.points.size(); ++i) {
    if (!(smoothing_length[i] > 0)) continue;
    if (part_id && std::find(options.parts.begin(), options.parts.end(), (*part_id)[i]) == options.parts.end()) continue;
    sph.push_back(static_cast<Index>(i));
  }
  // In node ID order where the file has the IDs: the surface is then the same however the points
  // were split into pieces (an MPI run's ranks each write the nodes they computed).
  if (const auto* node_id = snap.field("node_id");
      node_id && node_id->components == 1 && std::holds_alternative<std::vector<std::int64_t>>(node_id->values)) {
    const auto& id = std::get<std::vector<std::int64_t>>(node_id->values);
    std::stable_sort(sph.begin(), sph.end(), [&](Index a, Index b) { return id[a] < id[b]; });
  }
  if (sph.empty())
    throw InputError(fmt::format("{}: no SPH particle (no point with smoothing_length > 0{})", vtu.string(),
                                 part_id ? fmt::format(" in part {}", fmt::join(options.parts, ", ")) : ""));
  std::vector<Vec3> x;
  std::vector<Real> volume, h;
  Real z_low = snap.points[sph.front()].z(), z_high = z_low;
  for (Index i : sph) {
    if (!(mass[i] > 0) || !(density[i] > 0))
      throw InputError(fmt::format("{}: point {} has mass {:g} and density {:g}; both must be positive",
                                   vtu.string(), i, mass[i], density[i]));
    x.push_back(snap.points[i]);
    volume.push_back(mass[i] / density[i]);
    h.push_back(smoothing_length[i]);
    z_low = std::min(z_low, snap.points[i].z());
    z_high = std::max(z_high, snap.points[i].z());
  }
  if (sph.size() > 1 && z_low == z_high)
    throw InputError(fmt::format("{}: every particle lies in the plane z = {:g}; the surface of a "
                                 "2D run is a curve, which `spall surface` does not extract",
                                 vtu.string(), z_low));

  std::vector<discretization::Field> particle_fields;
  if (options.fields.empty()) {
    for (const auto& f : snap.fields) particle_fields.push_back(gathered(f, sph));
  } else {
    for (const auto& name : options.fields) {
      const auto* f = snap.field(name);
      if (!f) throw InputError(fmt::format("--field {}: {} has no such point field", name, vtu.string()));
      particle_fields.push_back(gathered(*f, sph));
    }
  }

  // OpenVDB's mesher runs on TBB: as many threads as OpenMP gets (--threads).
  const tbb::global_control threads(tbb::global_control::max_allowed_parallelism,
                                    static_cast<std::size_t>(parallel::thread_count()));
  const surface::SurfaceParticles particles{x, volume, h};
  const surface::SurfaceSettings settings{.iso = options.iso, .cell = options.cell};
  const Real cell = options.cell > 0 ? options.cell : surface::default_cell(h);
  const surface::TriangleMesh mesh = surface::reconstruct_surface(particles, settings);
  const auto fields = surface::vertex_fields(particles, particle_fields, mesh.vertices);

  const std::string stem = surface_stem(series[k].file, k);
  io::output::write_vtp(dir / (stem + ".vtp"), mesh.vertices, mesh.triangles, fields);
  io::output::write_ply(dir / (stem + ".ply"), mesh.vertices, mesh.triangles);

  if (mesh.triangles.empty())
    log::warning(fmt::format("no surface at iso {:g}: the colour field stays below it everywhere (inside a "
                             "body it is about 1)", options.iso));
  const auto topology = surface::edge_topology(mesh);
  log::info(fmt::format("{}: time {:g}, {} SPH particles, cell {:g}, iso {:g}", vtu.string(), series[k].time,
                        sph.size(), cell, options.iso));
  log::info(fmt::format(
      "{}.vtp and .ply: {} vertices, {} triangles, area {:.6g}, enclosed volume {:.6g}, {}", (dir / stem).string(),
      mesh.vertices.size(), mesh.triangles.size(), surface::area(mesh), surface::enclosed_volume(mesh),
      topology.closed() ? fmt::format("closed (Euler characteristic {})", topology.euler_characteristic)
                        : fmt::format("not closed ({} boundary, {} non-manifold edges)", topology.boundary_edges,
                                      topology.non_manifold_edges + topology.misoriented_edges)));
  return exit_success;
}

}  // namespace spall::cli
