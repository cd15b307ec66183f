#include "run_command.hpp"

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <functional>
#include <fmt/format.h>
#include <map>
#include <optional>
#include <string.h>

#include "field_series.hpp"
#include "interrupt.hpp"
#include "progress.hpp"
#include "restart_file.hpp"
#include "run_outputs.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "spall/core/memory.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/version.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/io/keyword/unsupported.hpp"
#include "spall/io/output/run_info.hpp"
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
    log::warning(fmt::format("{}: {}: not supported by Spall, skipped{}{}", to_string(where), keyword,
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
  log::warning(fmt::format("{}: {}: {} not used: no thermal solution is requested (*CONTROL_SOLUTION SOLN 0), "
                           "Spall runs the structural analysis",
                           to_string(first.where), first.keyword,
                           count > 1 ? fmt::format("this and {} more thermal materials are", count - 1)
                                     : std::string("thermal material ") + std::to_string(first.id) + " is"));
}

// Under MPI (`cards` dealing them) each rank keeps a share of the node and particle cards, and a
// deck that is not set up in blocks then gathers them whole on every rank before the checks.
model::Model read_and_check(const std::string& deck, const std::vector<std::string>& skip,
                            model::CardShare cards = {}) {
  if (!fs::exists(deck)) throw InputError(fmt::format("{}: no such deck file", deck));
  model::Model model = io::keyword::read_deck(deck, cards);
  io::keyword::refuse_unsupported_physics(model, skip);
  warn_unsupported(model);
  if (!model.cards.whole() && !solver::sets_up_in_blocks(model)) model.gather_cards();
  io::keyword::validate(model);
  warn_thermal_unused(model);
  return model;
}

// A deck whose parts give no particle, element or rigid body has nothing to run.
solver::Problem build_something(const model::Model& model, const std::string& deck,
                                solver::SetUp set_up = solver::SetUp::whole) {
  solver::Problem problem = solver::build_problem(model, set_up);
  if (problem.formulations.empty() && problem.rigid_bodies.empty())
    throw InputError(fmt::format("{}: nothing to simulate: no part has particles or elements that Spall runs", deck));
  return problem;
}

// The nodes that carry mass: the particles of SPH and SPG parts and the nodes of finite elements,
// over every rank's rows when the set-up built a block of the nodes on each (collective then).
long long moving_node_count(const solver::Problem& problem) {
  std::int64_t n = 0;
  for (Real m : problem.nodes.mass) n += m > 0;
  if (problem.nodes.holds_a_block()) parallel::world().sum({&n, 1});
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
  // Several ranks (mpirun -np N): each reads the deck; a deck of fluid alone is built in blocks of
  // the nodes, dealt by region, and each rank then keeps its region's rows; the others are built whole
  // on every rank, which computes a block of the nodes (docs/SCALING.md); each rank writes its piece
  // of each field output, rank 0 every other file.
  const parallel::Communicator& ranks = parallel::world();
  const int launched = parallel::launched_ranks();
  if (launched > 1 && ranks.size() == 1)
    throw InputError(fmt::format("spall run was started as one of {} MPI ranks (mpirun -np {}), but this spall was "
                                 "built without MPI (SPALL_MPI=OFF): run it as one process",
                                 launched, launched));
  const bool writes = ranks.rank() == 0;
  if (!writes) log::set_quiet(true);
  // A restart reads the deck the run copied into its folder, and continues in that folder.
  std::optional<Restart> restart;
  if (!options.restart_dir.empty()) restart.emplace(read_newest_restart(options.restart_dir));
  const std::string deck =
      restart ? (fs::path(options.restart_dir) / "deck" / restart->header.deck).string() : options.deck;
  const std::vector<std::string>& skip = restart ? restart->header.skip : options.skip;
  model::Model model = read_and_check(deck, skip, model::CardShare{ranks.rank(), ranks.size()});
  // Set up in blocks where the deck allows (a restart file is then read into each rank's block).
  solver::Problem problem = build_something(model, deck, solver::SetUp::in_blocks_where_possible);
  model.release_mesh();

  const fs::path out = restart                      ? fs::path(options.restart_dir)
                       : options.output_dir.empty() ? fs::current_path() / (fs::path(deck).stem().string() + ".out")
                                                    : fs::path(options.output_dir);
  if (writes) {
    // A folder that cannot be made (a path through a file, no permission, a full disk) is the
    // user's output error, not Spall's: exit 4 with the reason, the job ended at once.
    try {
      fs::create_directories(out);
      if (!restart) copy_deck(model, deck, out);
    } catch (const fs::filesystem_error& e) {
      throw OutputError(fmt::format("cannot write the output folder {}: {}", out.string(), e.code().message()));
    }
  }

  const long long nodes = moving_node_count(problem);
  log::info(fmt::format("spall {}: {} with {} nodes (particles and element nodes) on {}{} threads, to {}", version,
                        deck, nodes, ranks.size() > 1 ? fmt::format("{} MPI ranks x ", ranks.size()) : "",
                        parallel::thread_count(), out.string()));

  std::optional<RunOutputs> outputs;
  std::optional<FieldSeries> pieces;  // the other ranks' pieces of the field outputs
  // The residual stress's statistics are taken over the ranks: the others take part where rank 0
  // writes them.
  std::optional<ResidualStressReport> residual_elsewhere;
  if (writes) {
    outputs.emplace(out, problem, model, restart.has_value());
  } else {
    pieces.emplace(out);
    if (problem.sph_solid)
      residual_elsewhere.emplace(*problem.sph_solid, model.sph_residual_stress.value_or(model::SphResidualStress{}));
  }
  const auto write_fields = [&](const solver::StepInfo& step) {
    if (writes) {
      outputs->write_fields(step, problem);
      return;
    }
    pieces->write(step, problem);
    if (residual_elsewhere) residual_elsewhere->at_field_output(step.time);
  };
  Progress progress(problem.controls.end_time, nodes);
  solver::StepInfo last_step;
  solver::Observer observer = writes ? outputs->observer() : solver::Observer{};
  if (!writes) observer.on_field_output = [&](const solver::StepInfo& step, const solver::Problem&) { write_fields(step); };
  observer.on_step = [&](const solver::StepInfo& step) {
    last_step = step;
    if (writes) progress.update(step);
  };
  solver::TimeLoop loop(problem, observer, {options.balance_every, options.balance_threshold});

  // The run's state between two steps: the loop's (the problem's: whole on rank 0, or each rank's
  // own rows and particles in turn when dealt by region), the wall time so far, the field series
  // (every rank's, of its pieces), then the histories rank 0 writes. Rank 0 writes it; under MPI
  // every rank reads it back, whatever the ranks that wrote it.
  double wall_seconds_before = 0;  // of the runs this one continues
  FieldSeries& series = writes ? outputs->field_series() : *pieces;
  const auto state = [&](Archive& a) {
    loop.checkpoint(a);
    a.section("run");
    double wall_seconds = wall_seconds_before + progress.elapsed_seconds();
    a(wall_seconds, last_step);
    if (a.reading()) wall_seconds_before = wall_seconds;
    a.section("field output");
    series.checkpoint(a);
    if (writes) outputs->checkpoint(a);
  };
  if (restart) {
    state(restart->state);
    // Only rank 0 reads the checkpoint to its end (the histories): it tells the others.
    double whole = !writes || restart->state.at_end() ? 0 : -1;
    ranks.minimum({&whole, 1});
    if (whole < 0)
      throw InputError(fmt::format("{}: the checkpoint is longer than this deck's state", restart->file.string()));
    log::info(fmt::format("continuing from {} at step {}, t = {:g}", restart->file.string(), restart->header.step,
                          restart->header.time));
    progress.continue_from(last_step);
  }

  // Running restart files: every CYCL steps (--checkpoint-every overrides the deck), NR in turn.
  const long long cycles = options.checkpoint_every > 0 ? options.checkpoint_every
                           : model.runrsf              ? model.runrsf->cycles
                                                       : 0;
  RestartFiles restart_files(out, model.runrsf ? model.runrsf->files : 1);
  const auto write_checkpoint = [&](const solver::StepInfo& step) {
    const RestartHeader header{version, fs::path(deck).filename().string(), skip, step.step, step.time};
    loop.complete_state();  // every rank: rank 0 writes the state, whole or in every rank's pieces
    return restart_files.write(header, state, writes);
  };

  io::output::RunInfo info;
  info.version = version;
  info.deck = fs::absolute(deck).string();
  info.threads = parallel::thread_count();
  info.ranks = ranks.size();
  info.nodes = nodes;
  info.initial_mass = loop.initial_mass();
  int code = exit_success;
  const InterruptWatch interrupts;
  try {
    std::optional<solver::StepInfo> stopped;
    int signal = 0;
    const auto summary = loop.run([&](const solver::StepInfo& step) {
      // Every rank stops at the same step, on the signal any of them received.
      double negated_signal = -interrupts.received();
      ranks.minimum({&negated_signal, 1});
      if (negated_signal < 0) {
        stopped = step;
        signal = static_cast<int>(-negated_signal);
        return false;
      }
      if (cycles > 0 && step.step % cycles == 0) write_checkpoint(step);
      return true;
    });
    if (stopped) {
      const fs::path file = write_checkpoint(*stopped);
      write_fields(*stopped);  // after the checkpoint: a restart writes its own
      log::warning(fmt::format("interrupted ({}) at step {}, t = {:g}: the state is in {}; continue with `spall run "
                               "--restart {}`",
                               strsignal(signal), stopped->step, stopped->time, file.string(), out.string()));
      info.steps = stopped->step;
      info.end_time = stopped->time;
      info.status = "interrupted";
      code = 128 + signal;
    } else {
      progress.finish(last_step);
      info.steps = summary.steps;
      info.end_time = summary.end_time;
      info.status = "completed";
      if (writes) {
        if (const auto residual = outputs->finish(summary.end_time)) log::info(*residual);
      } else if (residual_elsewhere) {
        residual_elsewhere->finish(summary.end_time);
      }
      info.energy_ratio = summary.energies.ratio();
      // At rest the ratio is not a number (docs/OUTPUT.md): "n/a", not a quotient of round-off.
      log::info(fmt::format("done: {} steps to t = {:g} in {:.2f} s, {:.3e} node-steps/s, energy ratio {}",
                            summary.steps, summary.end_time, progress.elapsed_seconds(),
                            progress.elapsed_seconds() > 0
                                ? nodes * double(progress.steps_taken(last_step)) / progress.elapsed_seconds()
                                : 0.0,
                            std::isfinite(info.energy_ratio) ? fmt::format("{:.6f}", info.energy_ratio) : "n/a"));
    }
  } catch (const InstabilityError& e) {
    write_fields(last_step);  // the last state, for the post-mortem
    if (writes) {
      log::error(e.what());
      log::error(fmt::format("the last state is in {}", outputs->last_field_file().string()));
    }
    info.steps = last_step.step;
    info.end_time = last_step.time;
    info.status = "unstable";
    code = exit_unstable;
  } catch (const OutputError&) {
    // A full disk: run.json says so if it still fits; the error itself is reported by main().
    info.steps = last_step.step;
    info.end_time = last_step.time;
    info.status = "output_failed";
    try {
      if (writes) io::output::write_run_json(out / "run.json", info);
    } catch (const OutputError&) {
    }
    throw;
  }
  // The bytes each rank received a step of this process's run and its seconds in the collectives,
  // mean and largest over the ranks (collective: every rank is here).
  if (const long long steps = progress.steps_taken(last_step); ranks.size() > 1 && steps > 0) {
    std::int64_t bytes = ranks.received_bytes();
    const double seconds = ranks.communicating_seconds();
    double largest[2] = {-static_cast<double>(bytes), -seconds};
    ExactSum seconds_sum;
    seconds_sum.add(seconds);
    ranks.sum({&bytes, 1});
    ranks.sum({&seconds_sum, 1});
    ranks.minimum(largest);
    info.received_bytes_mean = static_cast<double>(bytes) / ranks.size() / static_cast<double>(steps);
    info.received_bytes_max = -largest[0] / static_cast<double>(steps);
    info.communicating_seconds_mean = seconds_sum.value() / ranks.size();
    info.communicating_seconds_max = -largest[1];
  }
  // The rows each rank holds now and its largest resident set so far (collective).
  std::int64_t totals[2] = {problem.nodes.size(), static_cast<std::int64_t>(memory::peak_resident_bytes())};
  double most[2] = {-static_cast<double>(totals[0]), -static_cast<double>(totals[1])};
  ranks.sum(totals);
  ranks.minimum(most);
  info.node_rows_mean = static_cast<double>(totals[0]) / ranks.size();
  info.node_rows_max = static_cast<long long>(-most[0]);
  info.peak_resident_bytes_mean = static_cast<double>(totals[1]) / ranks.size();
  info.peak_resident_bytes_max = static_cast<long long>(-most[1]);
  if (!writes) return code;
  info.wall_seconds = wall_seconds_before + progress.elapsed_seconds();
  info.rebalances = loop.rebalances();
  if (ranks.size() > 1) info.halo = loop.velocities_by_reach() ? "by reach" : "every node";
  info.masses = outputs->masses();
  for (int p = 0; p < static_cast<int>(solver::Phase::count); ++p) {
    const auto phase = static_cast<solver::Phase>(p);
    info.phases.emplace_back(solver::phase_name(phase), loop.phases()[phase]);
  }
  log::info(where_the_time_went(loop.phases()));
  const double peak = static_cast<double>(info.peak_resident_bytes_max);
  log::info(ranks.size() > 1 ? fmt::format("memory: largest resident set {} a rank, {} in all", memory::human_bytes(peak),
                                           memory::human_bytes(info.peak_resident_bytes_mean * ranks.size()))
            : nodes > 0      ? fmt::format("memory: largest resident set {} ({:.0f} B a node)", memory::human_bytes(peak),
                                           peak / static_cast<double>(nodes))
                             : fmt::format("memory: largest resident set {}", memory::human_bytes(peak)));
  io::output::write_run_json(out / "run.json", info);
  if (code == exit_success)
    log::info(fmt::format("results: {} (open d3plot.pvd in ParaView; energies in glstat.csv)", out.string()));
  return code;
}

}  // namespace spall::cli
