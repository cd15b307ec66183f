// spall: the command line. `spall run DECK`, `spall check DECK`.
// Exit codes: 0 success, 2 bad input, 3 numerical instability.
#include <CLI/CLI.hpp>
#include <fmt/core.h>
#include <omp.h>

#include "run_command.hpp"
#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "spall/core/version.hpp"

int main(int argc, char** argv) {
  CLI::App app{"Spall: meshfree explicit dynamics for solids and fluids (LS-DYNA keyword input)"};
  app.set_version_flag("--version", std::string("spall ") + spall::version);
  app.require_subcommand(1);

  spall::cli::RunOptions options;
  auto* run = app.add_subcommand("run", "Run a keyword deck and write ParaView output");
  run->add_option("deck", options.deck, "LS-DYNA keyword deck (.k)")->required();
  run->add_option("-o,--output", options.output_dir,
                  "Output folder (default: the deck's name with .out, in the working folder)");
  run->add_option("--threads", options.threads, "OpenMP threads (default: all cores)")
      ->check(CLI::PositiveNumber);

  std::string check_deck;
  auto* check = app.add_subcommand("check", "Read and check a deck without running it");
  check->add_option("deck", check_deck, "LS-DYNA keyword deck (.k)")->required();

  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    app.exit(e);
    return spall::exit_bad_input;
  }

  if (options.threads > 0) omp_set_num_threads(options.threads);
  try {
    if (*check) return spall::cli::check_deck(check_deck);
    return spall::cli::run_deck(options);
  } catch (const spall::InputError& e) {
    spall::log::error(e.what());
    return spall::exit_bad_input;
  }
}
