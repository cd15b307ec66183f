#include "run_command.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fmt/format.h>
#include <map>
#include <optional>

#include "progress.hpp"
#include "residual_report.hpp"
#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/version.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/io/keyword/unsupported.hpp"
#include "spall/io/output/history.hpp"
#include "spall/io/output/run_info.hpp"
#include "spall/io/output/vtu.hpp"
#include "spall/solver/field_output.hpp"
#include "spall/solver/simulation.hpp"

namespace spall::cli {

namespace fs = std::filesystem;

namespace {

// Each unsupported keyword once: where it first appears and how often it does. A physics keyword
// reaches this only when the user skipped it (--skip): then the physics is incomplete, and the
// warning says so.
void warn_unsupported(const model::Model& model) {
  std::map<std::string, std::pair<SourceLocation, int>> seen;
  for (const auto& u : model.unsupported) {
    auto [it, inserted] = seen.try_emplace(u.keyword, u.where, 0);
    ++it->second.second;
  }
  for (const auto& [keyword, first] : seen) {
    const auto& [where, count] = first;
    log::warning(fmt::format("{}:{}: {}: not supported by Spall, skipped{}{}", where.file, where.line, keyword,
                             count > 1 ? fmt::format(" ({} occurrences)", count) : std::string(),
                             io::keyword::defines_physics(keyword)
                                 ? " on request (--skip): the physics of this run is incomplete"
                                 : std::string()));
  }
}

// Thermal materials are read for *PART TMID only: a deck that asks for a thermal solution is refused
// at its *CONTROL_SOLUTION, so here they are unused. Once, naming the first.
void warn_thermal_unused(const model::Model& model) {
  if (model.thermal_materials.empty()) return;
  const auto& first = model.thermal_materials.begin()->second;
  const std::size_t count = model.thermal_materials.size();
  log::warning(fmt::format("{}:{}: {}: {} not used: no thermal solution is requested (*CONTROL_SOLUTION SOLN 0), "
                           "Spall runs the structural analysis",
                           first.where.file, first.where.line, first.keyword,
                           count > 1 ? fmt::format("this and {} more thermal materials are", count - 1)
                                     : std::string("thermal material ") + std::to_string(first.id) + " is"));
}

model::Model read_and_check(const std::string& deck, const std::vector<std::string>& skip) {
  if (!fs::exists(deck)) throw InputError(fmt::format("{}: no such deck file", deck));
  model::Model model = io::keyword::read_deck(deck);
  io::keyword::refuse_unsupported_physics(model, skip);
  warn_unsupported(model);
  io::keyword::validate(model);
  warn_thermal_unused(model);
  return model;
}

// A deck whose parts give no particle, element or rigid body has nothing to run.
solver::Problem build_something(const model::Model& model, const std::string& deck) {
  solver::Problem problem = solver::build_problem(model);
  if (problem.formulations.empty() && problem.rigid_bodies.empty())
    throw InputError(fmt::format("{}: nothing to simulate: no part has particles or elements that Spall runs", deck));
  return problem;
}

// The nodes that carry mass: the particles of SPH and SPG parts and the nodes of finite elements.
long long moving_node_count(const solver::Problem& problem) {
  long long n = 0;
  for (Real m : problem.nodes.mass) n += m > 0;
  return n;
}

// A copy of every file the deck read, so that the output folder describes the run on its own.
void copy_deck(const model::Model& model, const fs::path& deck, const fs::path& out) {
  const fs::path base = fs::absolute(deck).parent_path();
  for (const auto& file : model.files) {
    fs::path relative = fs::absolute(file).lexically_relative(base);
    if (relative.empty() || *relative.begin() == "..") relative = fs::path(file).filename();
    const fs::path target = out / "deck" / relative;
    fs::create_directories(target.parent_path());
    fs::copy_file(file, target, fs::copy_options::overwrite_existing);
  }
}

// "time: internal_forces 91.2 %, energies 3.1 %, ...": the phases that took at least 0.1 % of the
// step, largest first.
std::string where_the_time_went(const solver::PhaseTimes& phases) {
  std::vector<std::pair<double, std::string_view>> shares;
  const double total = phases.total();
  for (int p = 0; p < static_cast<int>(solver::Phase::count); ++p) {
    const auto phase = static_cast<solver::Phase>(p);
    if (total > 0 && phases[phase] >= 1e-3 * total) shares.emplace_back(phases[phase] / total, solver::phase_name(phase));
  }
  std::sort(shares.begin(), shares.end(), std::greater<>());
  std::string line = fmt::format("time in the step ({:.2f} s):", total);
  for (const auto& [share, name] : shares) line += fmt::format(" {} {:.1f} %,", name, 100 * share);
  line.pop_back();
  return line;
}

}  // namespace

int check_deck(const std::string& deck, const std::vector<std::string>& skip) {
  const model::Model model = read_and_check(deck, skip);
  const solver::Problem problem = build_something(model, deck);
  fmt::print("{}: {} nodes, {} parts, {} SPH particles, {} solid elements, {} rigid bodies, {} contacts; end time {:g}; "
             "OK\n",
             deck, model.nodes.size(), model.parts.size(), model.sph_elements.size(), model.solid_elements.size(),
             problem.rigid_bodies.bodies().size(), problem.contacts.size(), problem.controls.end_time);
  return exit_success;
}

int run_deck(const RunOptions& options) {
  const model::Model model = read_and_check(options.deck, options.skip);
  solver::Problem problem = build_something(model, options.deck);

  const fs::path out = options.output_dir.empty()
                           ? fs::current_path() / (fs::path(options.deck).stem().string() + ".out")
                           : fs::path(options.output_dir);
  fs::create_directories(out);
  copy_deck(model, options.deck, out);

  const long long nodes = moving_node_count(problem);
  log::info(fmt::format("spall {}: {} with {} nodes (particles and element nodes) on {} threads, to {}", version,
                        options.deck, nodes, parallel::thread_count(), out.string()));

  io::output::PvdSeries series(out / "d3plot.pvd");
  // glstat.csv: time, dt, the energy ledger's terms (whoever produces a term registers it in the
  // first step, before the first row), the total and the energy ratio.
  std::optional<io::output::CsvHistory> glstat;
  std::vector<std::pair<std::string, double>> reported;  // the masses of glstat's last row, for run.json
  // Forces on the rigid walls, one row per wall and output time; only when the deck has walls.
  std::optional<io::output::CsvHistory> rwforc;
  if (!problem.rigid_walls.empty())
    rwforc.emplace(out / "rwforc.csv",
                   std::vector<io::output::Column>{{"time", "time"}, {"wall", ""}, {"normal_force", "force"},
                                                   {"fx", "force"}, {"fy", "force"}, {"fz", "force"}});
  // Forces of the penalty contacts on each side (1: SURFA, 2: SURFB), with their moments about the
  // *DATABASE_RCFORC_MOMENT node, or the side's rigid-body centre, or the origin; only with contacts.
  std::optional<io::output::CsvHistory> rcforc;
  if (!problem.contacts.empty()) {
    std::vector<io::output::Column> columns{{"time", "time"}, {"contact", ""}, {"side", ""}};
    for (const char* name : {"fx", "fy", "fz"}) columns.push_back({name, "force"});
    for (const char* name : {"mx", "my", "mz"}) columns.push_back({name, "force*length"});
    for (const char* name : {"px", "py", "pz"}) columns.push_back({name, "length"});
    rcforc.emplace(out / "rcforc.csv", std::move(columns));
  }
  // Residual stress of the SPH solids per part and category (seed 000), at the end of the run and,
  // on request, at every field output.
  const sph::SolidFormulation* solid = nullptr;
  for (const auto& f : problem.formulations)
    if (const auto* s = dynamic_cast<const sph::SolidFormulation*>(f.get())) solid = s;
  const model::SphResidualStress residual_options = model.sph_residual_stress.value_or(model::SphResidualStress{});
  std::optional<ResidualStressReport> residual;
  if (solid) residual.emplace(out / "residual.csv", *solid, residual_options);
  // The rigid bodies' motion and the forces on them, at the RBDOUT interval (GLSTAT's without the
  // card); only with bodies.
  std::optional<io::output::CsvHistory> rbdout;
  if (!problem.rigid_bodies.empty()) {
    std::vector<io::output::Column> columns{{"time", "time"}, {"part", ""}};
    for (const char* name : {"x", "y", "z"}) columns.push_back({name, "length"});
    for (const char* name : {"vx", "vy", "vz"}) columns.push_back({name, "velocity"});
    for (const char* name : {"wx", "wy", "wz"}) columns.push_back({name, "1/time"});
    for (const char* name : {"fx", "fy", "fz"}) columns.push_back({name, "force"});
    for (const char* name : {"mx", "my", "mz"}) columns.push_back({name, "force*length"});
    rbdout.emplace(out / "rbdout.csv", std::move(columns));
  }

  int field_count = 0;
  auto write_fields = [&](const solver::StepInfo& step, const solver::Problem& p) {
    const auto snap = solver::snapshot_fields(p);
    const std::string name = fmt::format("d3plot_{:05d}.vtu", field_count++);
    io::output::write_vtu(out / name, snap.points, snap.fields, snap.cell_blocks);
    series.add(step.time, name);
    if (residual && residual_options.at_output == 1) residual->write(step.time);
  };

  Progress progress(problem.controls.end_time, nodes);
  solver::StepInfo last_step;
  solver::Observer observer;
  observer.on_field_output = write_fields;
  observer.on_history = [&](const solver::StepInfo& step, const discretization::EnergyLedger& e) {
    if (!glstat) {
      std::vector<io::output::Column> columns{{"time", "time"}, {"dt", "time"}};
      for (const auto& term : e.terms())
        columns.push_back({term.name, term.role == discretization::EnergyLedger::Role::reported ? "mass" : "energy"});
      columns.push_back({"total_energy", "energy"});
      columns.push_back({"energy_ratio", ""});
      glstat.emplace(out / "glstat.csv", std::move(columns));
    }
    std::vector<double> row{step.time, step.dt};
    for (const auto& term : e.terms()) row.push_back(term.value);
    reported.clear();
    for (const auto& term : e.terms())
      if (term.role == discretization::EnergyLedger::Role::reported) reported.emplace_back(term.name, term.value);
    row.push_back(e.total());
    row.push_back(e.ratio());
    glstat->append(row);
  };
  observer.on_rigid_bodies = [&](const solver::StepInfo& step, const rigid::RigidBodies& bodies) {
    for (const auto& body : bodies.bodies()) {
      std::vector<double> r{step.time, static_cast<double>(body.part_id)};
      for (const Vec3* v : {&body.step_centre, &body.velocity, &body.angular_velocity, &body.force, &body.moment})
        r.insert(r.end(), v->data(), v->data() + 3);
      rbdout->append(r);
    }
  };
  observer.on_rigid_wall_forces = [&](const solver::StepInfo& step,
                                      const std::vector<contact::RigidWall>& walls) {
    for (const auto& wall : walls) {
      const Vec3& f = wall.force();
      const double row[] = {step.time, static_cast<double>(wall.definition().id), wall.normal_force(),
                            f.x(), f.y(), f.z()};
      rwforc->append(row);
    }
  };
  observer.on_contact_forces = [&](const solver::StepInfo& step, const std::vector<contact::PenaltyContact>& contacts) {
    for (const auto& c : contacts)
      for (int side = 0; side < 2; ++side) {
        const auto& r = side == 0 ? c.side_a() : c.side_b();
        const std::int32_t body = c.definition().side_body[side];
        const Index node = c.definition().moment_node[side];
        const Vec3 p = node >= 0   ? problem.nodes.x[node]
                       : body >= 0 ? problem.rigid_bodies.bodies()[body].step_centre
                                   : Vec3::Zero();
        const Vec3 m = r.moment - p.cross(r.force);
        std::vector<double> row{step.time, static_cast<double>(c.definition().id), double(side + 1)};
        for (const Vec3* v : {&r.force, &m, &p}) row.insert(row.end(), v->data(), v->data() + 3);
        rcforc->append(row);
      }
  };
  observer.on_step = [&](const solver::StepInfo& step) {
    last_step = step;
    progress.update(step);
  };

  io::output::RunInfo info;
  info.version = version;
  info.deck = fs::absolute(options.deck).string();
  info.threads = parallel::thread_count();
  info.nodes = nodes;
  for (Real m : problem.nodes.mass) info.initial_mass += m;
  int code = exit_success;
  solver::TimeLoop loop(problem, observer);
  try {
    const auto summary = loop.run();
    progress.finish(last_step);
    info.steps = summary.steps;
    info.end_time = summary.end_time;
    info.status = "completed";
    if (residual) {
      if (residual_options.at_output != 1) residual->write(summary.end_time);
      log::info(residual->summary());
    }
    info.energy_ratio = summary.energies.ratio();
    // At rest the ratio is not a number (docs/OUTPUT.md): "n/a", not a quotient of round-off.
    log::info(fmt::format("done: {} steps to t = {:g} in {:.2f} s, {:.3e} node-steps/s, energy ratio {}",
                          summary.steps, summary.end_time, progress.elapsed_seconds(),
                          progress.elapsed_seconds() > 0
                              ? nodes * double(summary.steps) / progress.elapsed_seconds()
                              : 0.0,
                          std::isfinite(info.energy_ratio) ? fmt::format("{:.6f}", info.energy_ratio) : "n/a"));
  } catch (const InstabilityError& e) {
    write_fields(last_step, problem);  // the last state, for the post-mortem
    log::error(e.what());
    log::error(fmt::format("the last state is in {}", (out / fmt::format("d3plot_{:05d}.vtu", field_count - 1)).string()));
    info.steps = last_step.step;
    info.end_time = last_step.time;
    info.status = "unstable";
    code = exit_unstable;
  }
  info.wall_seconds = progress.elapsed_seconds();
  info.masses = std::move(reported);
  for (int p = 0; p < static_cast<int>(solver::Phase::count); ++p) {
    const auto phase = static_cast<solver::Phase>(p);
    info.phases.emplace_back(solver::phase_name(phase), loop.phases()[phase]);
  }
  log::info(where_the_time_went(loop.phases()));
  io::output::write_run_json(out / "run.json", info);
  if (code == exit_success)
    log::info(fmt::format("results: {} (open d3plot.pvd in ParaView; energies in glstat.csv)", out.string()));
  return code;
}

}  // namespace spall::cli
