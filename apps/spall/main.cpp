// spall: the command line. `spall run DECK`, `spall check DECK`, `spall surface OUTDIR`.
// Exit codes: 0 success, 1 internal error, 2 bad input, 3 numerical instability, 4 an output file
// could not be written, 128 + the signal's number when a run was interrupted (130 SIGINT, 143
// SIGTERM).
#include <CLI/CLI.hpp>
#include <fmt/core.h>

#include "run_command.hpp"
#include "surface_command.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "spall/core/memory.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/version.hpp"

namespace {

// A number above (or, with `zero_allowed`, at least) zero, with a message that says so (CLI11's
// own names the whole range of a double).
CLI::Validator sign_check(bool zero_allowed) {
  return CLI::Validator(
      [zero_allowed](std::string& input) -> std::string {
        double value = 0;
        if (!CLI::detail::lexical_cast(input, value)) return "not a number: " + input;
        if (value > 0 || (zero_allowed && value == 0)) return {};
        return (zero_allowed ? "must be zero or more, got " : "must be more than zero, got ") + input;
      },
      zero_allowed ? "NONNEGATIVE" : "POSITIVE");
}
const CLI::Validator positive = sign_check(false);
const CLI::Validator non_negative = sign_check(true);

}  // namespace

int main(int argc, char** argv) {
  const spall::parallel::Session mpi;
  CLI::App app{"Spall: meshfree explicit dynamics for solids and fluids (LS-DYNA keyword input)"};
  app.set_version_flag("--version", std::string("spall ") + spall::version +
                                        (spall::parallel::built_with_mpi() ? " (MPI)" : ""));
  app.require_subcommand(1);

  spall::cli::RunOptions options;
  auto* run = app.add_subcommand("run", "Run a keyword deck and write ParaView output");
  auto* deck_option = run->add_option("deck", options.deck, "LS-DYNA keyword deck (.k)");
  auto* restart = run->add_option("--restart", options.restart_dir,
                                  "Continue the run whose output folder this is, from its newest restart file "
                                  "(runrsf), in that folder");
  deck_option->excludes(restart);
  double memory_limit_gb = 0;
  run->add_option("--memory-limit", memory_limit_gb,
                  "Refuse a deck whose particles would need more than this many GB (default: the memory available)")
      ->check(positive);
  run->add_option("--checkpoint-every", options.checkpoint_every,
                  "Write a restart file every N steps (overrides *DATABASE_BINARY_RUNRSF's CYCL)")
      ->check(positive);
  auto* output = run->add_option("-o,--output", options.output_dir,
                                 "Output folder (default: the deck's name with .out, in the working folder)");
  output->excludes(restart);
  run->add_option("--threads", options.threads, "OpenMP threads (default: all cores)")
      ->check(positive);
  run->add_option("--balance-every", options.balance_every,
                  "Under mpirun: compare the ranks' work every N steps (default 100; the first checks come sooner, "
                  "after 10, 20, 40, ... steps while below N)")
      ->check(positive);
  run->add_option("--balance-threshold", options.balance_threshold,
                  "Under mpirun: deal the nodes out anew when the busiest rank works this fraction more than the "
                  "mean (default 0.1: 10 %; 0: at every check)")
      ->check(non_negative);

  run->add_option("--skip", options.skip,
                  "Run without this unsupported physics keyword (e.g. CONTACT_AUTOMATIC_SINGLE_SURFACE, or CONTACT for "
                  "every *CONTACT_...); repeat for more. The physics is then incomplete");
  std::string check_deck;
  std::vector<std::string> check_skip;
  auto* check = app.add_subcommand("check", "Read and check a deck without running it");
  check->add_option("deck", check_deck, "LS-DYNA keyword deck (.k)")->required();
  check->add_option("--skip", check_skip, "As for run: check without this unsupported physics keyword");
  check->add_option("--memory-limit", memory_limit_gb, "As for run")->check(positive);

  spall::cli::SurfaceOptions surface_options;
  int surface_threads = 0;
  auto* surface = app.add_subcommand(
      "surface", "Reconstruct the surface of a run's SPH particles (colour field = iso) as .vtp and .ply");
  surface->add_option("outdir", surface_options.output_dir, "Output folder of `spall run` (with d3plot.pvd)")
      ->required();
  surface->add_option("--time", surface_options.time,
                      "Snapshot at this time, or the last before it (default: the last snapshot)");
  surface->add_option("--iso", surface_options.iso,
                      "Colour-field value on the surface (default 0.5: half the interior colour)")
      ->check(positive);
  surface->add_option("--cell", surface_options.cell,
                      "Grid spacing in the deck's length unit (default: half the median smoothing length)")
      ->check(positive);
  // One name per --field, so that a field name is never taken for the folder.
  surface->add_option("--field", surface_options.fields,
                      "Point field to carry onto the surface's vertices; repeat --field for more (default: every field)")
      ->allow_extra_args(false);
  surface->add_option("--part", surface_options.parts,
                      "Only the particles of this part (PID); repeat --part for more (default: every SPH particle)")
      ->allow_extra_args(false);
  surface->add_option("--threads", surface_threads, "Threads (default: all cores)")->check(positive);

  try {
    app.parse(argc, argv);
    if (*run && options.deck.empty() && options.restart_dir.empty())
      throw CLI::RequiredError("run: a deck, or --restart with an output folder,");
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return spall::exit_bad_input;
  }

  if (memory_limit_gb > 0) spall::memory::set_limit(static_cast<std::uint64_t>(memory_limit_gb * 1e9));
  if (options.threads > 0) spall::parallel::set_thread_count(options.threads);
  if (surface_threads > 0) spall::parallel::set_thread_count(surface_threads);
  try {
    if (*check) return spall::cli::check_deck(check_deck, check_skip);
    if (*surface) return spall::cli::reconstruct_surface(surface_options);
    return spall::cli::run_deck(options);
  } catch (const spall::InputError& e) {
    // Every MPI rank reads the same deck and finds the same error: one line, from rank 0.
    if (spall::parallel::world().rank() == 0) spall::log::error(e.what());
    return spall::exit_bad_input;
  } catch (const spall::OutputError& e) {
    // A full disk or a folder without write permission: what was written before is whole.
    spall::log::error(fmt::format("{} (the files written before it are complete; d3plot.pvd lists the states on disk)",
                                  e.what()));
    if (!e.every_rank()) spall::parallel::world().abort(spall::exit_output);
    return spall::exit_output;
  } catch (const std::exception& e) {
    spall::log::error(fmt::format("internal error (please report it with the deck): {}", e.what()));
    spall::parallel::world().abort(spall::exit_internal);
    return spall::exit_internal;
  }
}
