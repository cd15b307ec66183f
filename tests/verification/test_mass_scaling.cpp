// *CONTROL_TIMESTEP DT2MS < 0, LS-DYNA's conventional mass scaling (issue 34; fem-contact.md §1.10,
// §2.10: TSSFAC x |DT2MS| is the resulting step, mass is added only to the elements whose step is
// below it). An element's stable step is proportional to 1 / c = sqrt(rho / K), so raising its step
// by a factor k takes k^2 times its mass; a free-free bar whose mass is scaled by f everywhere rings
// with the sound speed c / sqrt(f), so its quarter period L / (2c) (Graff, Wave Motion in Elastic
// Solids, §2.1) grows by sqrt(f). Checked for FEM and SPG bars, with and without MS1ST; on a mesh
// of two element sizes, only the small elements take mass; ENDMAS stops the run.
#include <gtest/gtest.h>

#include <array>
#include <cmath>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "support/contact_decks.hpp"
#include "support/spg_bar.hpp"

using namespace spall;
using namespace spall::test_support;

namespace {

constexpr Real tssfac = 0.9;

struct Scaled {
  Real first_step = 0;     // the run's first step
  Real mass_factor = 0;    // 1 + added mass / mass
  Real quarter = 0;        // the measured quarter period
};

// The bar run with DT2MS = -target (0: none) to 3 quarter periods of the unscaled bar.
Scaled ring(const SpgBlock& b, Real target, int ms1st) {
  const Real quarter = bar_quarter_period(b);
  const auto run = run_spg_bar(b, (target > 0 ? 3 : 1.5) * quarter, tssfac, [&](model::Model& m) {
    m.timestep.dt2ms = -target;
    m.timestep.ms1st = ms1st;
  });
  const Real mass = b.density * b.size.prod();
  const Real added = run.summary.energies.value(discretization::EnergyLedger::added_mass);
  return {run.dt.front(), 1 + added / mass, first_minimum(run.time, run.kinetic)};
}

void check_bar(const SpgBlock& b, const char* name) {
  const Scaled plain = ring(b, 0, 0);
  // The bar's elements (particles) all have one step, so each takes 4 times its mass.
  const Real element_step = plain.first_step / tssfac;
  for (int ms1st : {0, 1}) {
    const Scaled scaled = ring(b, 2 * element_step, ms1st);
    const Real period_ratio = scaled.quarter / plain.quarter;
    std::printf("%s MS1ST %d: step %.6g (target %.6g), mass x %.5f, quarter period x %.4f (sqrt of the mass "
                "factor %.4f)\n", name, ms1st, scaled.first_step, 2 * plain.first_step, scaled.mass_factor,
                period_ratio, std::sqrt(scaled.mass_factor));
    EXPECT_NEAR(scaled.first_step / (2 * plain.first_step), 1.0, 1e-9);
    EXPECT_NEAR(scaled.mass_factor, 4.0, 4.0 * 0.005);
    EXPECT_NEAR(period_ratio / std::sqrt(scaled.mass_factor), 1.0, 0.01);
  }
}

}  // namespace

TEST(MassScaling, FemBarRingsWithTheScaledMass) {
  log::set_quiet(true);
  auto b = spg_bar(20);
  b.fem = FiniteElements{2, {}};
  check_bar(b, "FEM");
}

TEST(MassScaling, SpgBarRingsWithTheScaledMass) {
  log::set_quiet(true);
  check_bar(spg_bar(20), "SPG");
}

namespace {

// A bar at rest, 0.1 x 0.01 x 0.01 m: 10 hexahedra 0.005 m long (part 1), then 5 that are 0.01 m
// long (part 2), read as a user writes it, with the *CONTROL_TIMESTEP card `timestep` and ENDMAS,
// and the parts' energies and masses (*DATABASE_MATSUM) at the end.
constexpr Real coarse = 0.01, fine = 0.005, density = 7850;

std::string graded_bar(const std::string& timestep, Real endmas, Real end_time) {
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time), "0", "0.0", "0.0", number(endmas)}) +
                     "*CONTROL_TIMESTEP\n" + timestep + "*DATABASE_MATSUM\n" + row({number(end_time)});
  for (Id pid : {1, 2}) deck += deformable_part(Body::fem, pid, density, 200e9, 0.3);
  const auto part_of = [](int i, int, int) -> Id { return i < 10 ? 1 : 2; };
  deck += hex_lattice(part_of, {15, 1, 1}, 1, 1, [](int i, int j, int k) {
    const Real x = i <= 10 ? fine * i : 10 * fine + coarse * (i - 10);
    return Vec3(x, coarse * j, coarse * k);
  });
  return deck + "*END\n";
}

std::string dt2ms_card(Real dt2ms) { return row({"0.0", number(tssfac), "0", "0.0", number(dt2ms)}); }

struct GradedRun {
  Real first_step = 0, added = 0, end_time = 0;
  std::array<Real, 2> added_to_part{};  // matsum's added_mass of parts 1 and 2 at the end
};

GradedRun run_graded(Real dt2ms, Real endmas, Real end_time) {
  test::DeckFolder folder;
  const model::Model model =
      io::keyword::read_deck(folder.write("bar.k", graded_bar(dt2ms_card(dt2ms), endmas, end_time)));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  GradedRun r;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo& s, const discretization::EnergyLedger&) {
    if (r.first_step == 0) r.first_step = s.dt;
  };
  observer.on_part_summary = [&](const solver::StepInfo&, const discretization::PartSummary& parts) {
    for (std::size_t k = 0; k < 2; ++k) r.added_to_part[k] = parts.value(k, discretization::PartSummary::added_mass);
  };
  const auto summary = solver::run(problem, observer);
  r.added = summary.energies.value(discretization::EnergyLedger::added_mass);
  r.end_time = summary.end_time;
  return r;
}

}  // namespace

TEST(MassScaling, OnlyElementsBelowTheTargetTakeMass) {
  log::set_quiet(true);
  // The fine elements set the step; the coarse ones' own step is about twice theirs.
  const GradedRun plain = run_graded(0, 0, 1e-6);
  const Real fine_step = plain.first_step / tssfac;
  const Real target = -std::stod(number(-1.25 * fine_step));  // as DT2MS's 10 characters hold it
  const GradedRun scaled = run_graded(-target, 0, 1e-6);
  const Real fine_mass = density * 10 * fine * coarse * coarse, k = target / fine_step;
  std::printf("fine elements' step %.6g, target %.6g: added %.6g kg (fine elements %.6g kg x %.4f)\n", fine_step,
              target, scaled.added, fine_mass, k * k - 1);
  EXPECT_NEAR(scaled.first_step / (tssfac * target), 1.0, 1e-9);
  EXPECT_NEAR(scaled.added / (fine_mass * (k * k - 1)), 1.0, 1e-9);
  // Part by part (matsum.csv): all of it on the fine elements' part.
  EXPECT_NEAR(scaled.added_to_part[0] / (fine_mass * (k * k - 1)), 1.0, 1e-9);
  EXPECT_EQ(scaled.added_to_part[1], 0.0);
}

TEST(MassScaling, EndmasStopsTheRun) {
  log::set_quiet(true);
  const GradedRun plain = run_graded(0, 0, 1e-6);
  // 1.5 times the fine elements' step: they take 1.25 times their mass more, 62.5 % of the bar's.
  const Real target = 1.5 * plain.first_step / tssfac;
  const GradedRun limited = run_graded(-target, 50, 1e-6), unlimited = run_graded(-target, 80, 1e-6);
  EXPECT_LT(limited.end_time, 1e-8);
  EXPECT_NEAR(unlimited.end_time, 1e-6, 1e-15);
}

TEST(MassScaling, UnsupportedFieldsAreInputErrors) {
  log::set_quiet(true);
  test::DeckFolder folder;
  const auto error_of = [&](const std::string& card) {
    return test::input_error_of(
        [&] { solver::build_problem(io::keyword::read_deck(folder.write("bad.k", graded_bar(card, 0, 1e-6)))); });
  };
  EXPECT_EQ(error_of(row({"0.0", "0.9", "0", "0.0", "-1e-6", "0", "0", "1"})), "");
  EXPECT_NE(error_of(row({"0.0", "0.9", "0", "0.0", "1e-6"})).find("*CONTROL_TIMESTEP: DT2MS > 0"), std::string::npos);
  EXPECT_NE(error_of(row({"0.0", "0.9", "0", "0.0", "-1e-6", "0", "0", "2"})).find("MS1ST: 2 is not 0 or 1"),
            std::string::npos);
}
