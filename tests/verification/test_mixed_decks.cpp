// Every pair of formulations in one deck (SPH solid, SPH fluid, SPG, solid finite elements): the
// deck builds, runs, and writes one VTU whose point fields are merged by name (the elements'
// fields are cell data of their own cells). Each body is a free bar of 30 x 4 x 4 nodes
// started in its first longitudinal mode, v_x = V cos(pi x / L) (as
// tests/verification/test_sph_elastic_bar.cpp and test_spg_elastic_bar.cpp), which turns kinetic
// energy into strain energy and back over a period 2L/c (c = sqrt(E / rho); Graff, Wave Motion in
// Elastic Solids, §2.1). The bodies lie side by side, far apart, and without contact do not act on
// each other (docs/THEORY.md §1, "Formulations in one deck"). The checks, after one period of the
// solid bars: energy is conserved, |E_total / (E_0 + W_ext) - 1| < 1 % (the bound of those two
// single-formulation tests), with every formulation's terms booked into one ledger, and each body
// alone meets the same bound; the solid bars did store energy (at least a quarter of the kinetic
// energy at some output: all of it at a quarter period in the exact mode). Also refused at the
// card: a node shared by an SPH particle and an SPG element.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <filesystem>
#include <fmt/format.h>
#include <optional>
#include <set>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/io/output/vtu.hpp"
#include "spall/solver/field_output.hpp"
#include "spall/solver/simulation.hpp"
#include "unit/keyword_test_decks.hpp"

using namespace spall;
using test::DeckFolder;
using test::row;

namespace {

enum class Body { sph_solid, sph_fluid, spg, fem };

constexpr int nx = 30, ny = 4, nz = 4;  // nodes along and across the bar
constexpr double dx = 1e-3;             // m
constexpr double speed = 0.3;           // m/s: V, at the ends
constexpr double length = (nx - 1) * dx;
// One period 2L/c of the steel bars' first mode, c = sqrt(2e11 / 7850).
const double period = 2 * length / std::sqrt(2.0e11 / 7850.0);

int node_id(int first, int i, int j, int k) { return first + i + nx * (j + ny * k); }

// Nodes of the bar's lattice from `first`, offset by `y0` across, each with the mode's velocity.
std::string lattice(int first, double y0, std::string& velocities) {
  std::string nodes = "*NODE\n";
  velocities += "*INITIAL_VELOCITY_NODE\n";
  for (int k = 0; k < nz; ++k)
    for (int j = 0; j < ny; ++j)
      for (int i = 0; i < nx; ++i) {
        const std::string id = std::to_string(node_id(first, i, j, k));
        const double x = i * dx, y = y0 + j * dx, z = k * dx;
        nodes += row({id, fmt::format("{:.8g}", x), fmt::format("{:.8g}", y), fmt::format("{:.8g}", z)}, {8, 16, 16, 16});
        velocities += row({id, fmt::format("{:.6f}", speed * std::cos(std::numbers::pi * x / length)), "0.0", "0.0"});
      }
  return nodes;
}

// One body as part `pid` (section and material of the same number), its nodes from pid * 1000.
std::string body(Body kind, int pid, double origin) {
  const int first = pid * 1000;
  std::string velocities;
  std::string deck = lattice(first, origin, velocities) + velocities;
  const std::string id = std::to_string(pid);
  // A fluid part names its equation of state (EOSID).
  deck += "*PART\nbody " + id + "\n" + (kind == Body::sph_fluid ? row({id, id, id, id}) : row({id, id, id}));
  if (kind == Body::spg || kind == Body::fem) {
    deck += kind == Body::fem ? "*SECTION_SOLID\n" + row({id, "1"})  // one-point hexahedra, IHQ 0 -> 2
                              : "*SECTION_SOLID_SPG\n" + row({id, "47", "0"}) +
                                    row({"1.5", "1.5", "1.5", "0", "1", "", "15"}) +
                                    // IDAM 1, FS 10: bonds would fail at an effective plastic strain
                                    // an elastic body never has.
                                    row({"1", "10.0"});
    deck += "*MAT_ELASTIC\n" + row({id, "7850.0", "2.0e11", "0.3"}) + "*ELEMENT_SOLID\n";
    for (int k = 0; k + 1 < nz; ++k)
      for (int j = 0; j + 1 < ny; ++j)
        for (int i = 0; i + 1 < nx; ++i) {
          const auto node = [&](int a, int b, int c) { return std::to_string(node_id(first, i + a, j + b, k + c)); };
          deck += row({std::to_string(node_id(first, i, j, k)), id, node(0, 0, 0), node(1, 0, 0), node(1, 1, 0),
                       node(0, 1, 0), node(0, 0, 1), node(1, 0, 1), node(1, 1, 1), node(0, 1, 1)},
                      {8, 8, 8, 8, 8, 8, 8, 8, 8, 8});
        }
    return deck;
  }
  // The fluid keeps h constant: HMIN = HMAX = 1.
  deck += "*SECTION_SPH\n" + (kind == Body::sph_fluid ? row({id, "1.2", "1.0", "1.0"}) : row({id, "1.2"}));
  const double density = kind == Body::sph_fluid ? 1000.0 : 7850.0;
  if (kind == Body::sph_fluid)
    deck += "*MAT_NULL\n" + row({id, "1000.0", "-1.0e20", "1.0e-3"}) + "*EOS_MURNAGHAN\n" + row({id, "7.0", "3.0e8"});
  else
    deck += "*MAT_ELASTIC\n" + row({id, "7850.0", "2.0e11", "0.3"});
  deck += "*ELEMENT_SPH\n";
  const std::string mass = fmt::format("{:.8g}", density * dx * dx * dx);
  for (int p = 0; p < nx * ny * nz; ++p) deck += row({std::to_string(first + p), id, mass}, {8, 8, 16});
  return deck;
}

// The bars 20 mm apart across (y), as parts 1, 2, ...
std::string deck_of(const std::vector<Body>& bodies) {
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({fmt::format("{:.4e}", period)}) +
                     "*DATABASE_GLSTAT\n" + row({fmt::format("{:.4e}", period / 40)});
  for (std::size_t k = 0; k < bodies.size(); ++k) deck += body(bodies[k], static_cast<int>(k + 1), 0.02 * k);
  return deck + "*END\n";
}

const char* name(Body b) {
  return b == Body::sph_solid ? "SPH solid" : b == Body::sph_fluid ? "SPH fluid" : b == Body::spg ? "SPG" : "FEM";
}

// One body alone (b absent) or two.
void run_bodies(Body a, std::optional<Body> b = std::nullopt) {
  log::set_quiet(true);
  DeckFolder folder;
  const auto bodies = b ? std::vector<Body>{a, *b} : std::vector<Body>{a};
  const model::Model model = io::keyword::read_deck(folder.write("mixed.k", deck_of(bodies)));
  solver::Problem problem = solver::build_problem(model);
  const std::string label = b ? fmt::format("{} + {}", name(a), name(*b)) : name(a);
  ASSERT_EQ(problem.formulations.size(), bodies.size()) << label;
  std::vector<std::string> terms;
  double stored = 0;
  solver::Observer observer;
  observer.on_history = [&](const solver::StepInfo&, const discretization::EnergyLedger& e) {
    stored = std::max(stored, e.internal());
    terms.clear();
    for (const auto& t : e.terms()) terms.push_back(t.name);
  };
  const auto summary = solver::run(problem, observer);
  const auto& e = summary.energies;
  std::printf("%s: %lld steps, energy %.4g J at the start, largest internal %.4g J, ratio after a period %.6f\n",
              label.c_str(), summary.steps, e.initial_total(), stored, e.ratio());
  EXPECT_NEAR(e.ratio(), 1.0, 0.01) << label;
  if (a != Body::sph_fluid || b) {
    EXPECT_GT(stored, 0.25 * e.initial_total()) << label << ": the bars must store energy";
  }
  const bool fem = a == Body::fem || b == Body::fem;
  std::vector<std::string> expected = {"kinetic_energy", "internal_energy", "artificial_viscosity_energy"};
  if (fem) expected.push_back("hourglass_energy");
  expected.push_back("external_work");
  EXPECT_EQ(terms, expected);

  // One snapshot with each name once, written as one VTU.
  const auto snap = solver::snapshot_fields(problem);
  std::set<std::string> names;
  for (const auto& f : snap.fields) EXPECT_TRUE(names.insert(f.name).second) << f.name << " twice";
  const auto field = [&](const std::string& field_name) -> const discretization::Field* {
    for (const auto& f : snap.fields)
      if (f.name == field_name) return &f;
    return nullptr;
  };
  const auto* part_id = field("part_id");
  const auto& parts = std::get<std::vector<std::int64_t>>(part_id->values);
  // Every particle formulation writes pressure and density: finite on each of its points. The
  // elements write theirs on their cells, one block, finite on every cell.
  const int fem_part = a == Body::fem ? 1 : b == Body::fem ? 2 : 0;
  if (!fem || b) {
    for (const char* shared : {"pressure", "density"}) {
      const auto* f = field(shared);
      ASSERT_NE(f, nullptr) << shared;
      const auto& values = std::get<std::vector<double>>(f->values);
      for (std::size_t i = 0; i < values.size(); ++i)
        if (parts[i] != fem_part) {
          ASSERT_TRUE(std::isfinite(values[i])) << shared;
        }
    }
  }
  ASSERT_EQ(snap.cell_blocks.size(), fem ? 1u : 0u) << label;
  if (fem) {
    for (const auto& f : snap.cell_blocks[0].fields) {
      if (f.name != "pressure" && f.name != "stress") continue;
      for (double value : std::get<std::vector<double>>(f.values)) ASSERT_TRUE(std::isfinite(value)) << f.name;
    }
  }
  // A field of one formulation has the fill value on the other's points.
  const char* own = b == Body::spg ? "bond_count" : a == Body::sph_solid ? "effective_plastic_strain" : nullptr;
  if (b && own) {
    const auto* f = field(own);
    ASSERT_NE(f, nullptr) << own;
    std::visit(
        [&](const auto& values) {
          for (std::size_t i = 0; i < values.size(); ++i) {
            const bool owner = (b == Body::spg) == (parts[i] == 2);
            const double value = static_cast<double>(values[i]);
            if (owner)
              EXPECT_TRUE(std::isfinite(value) && value >= 0) << own << " at point " << i;
            else if constexpr (std::is_same_v<typename std::decay_t<decltype(values)>::value_type, double>)
              EXPECT_TRUE(std::isnan(value)) << own << " at point " << i;
            else
              EXPECT_EQ(values[i], discretization::integer_fill) << own << " at point " << i;
          }
        },
        f->values);
  }
  EXPECT_NO_THROW(io::output::write_vtu(folder.path() / "mixed.vtu", snap.points, snap.fields, snap.cell_blocks));
}

}  // namespace

// Each body alone first: the same bound holds for each formulation on its own.
TEST(MixedDecks, SphSolidAlone) { run_bodies(Body::sph_solid); }
TEST(MixedDecks, SphFluidAlone) { run_bodies(Body::sph_fluid); }
TEST(MixedDecks, SpgAlone) { run_bodies(Body::spg); }
TEST(MixedDecks, SphSolidAndSphFluid) { run_bodies(Body::sph_solid, Body::sph_fluid); }
TEST(MixedDecks, SphSolidAndSpg) { run_bodies(Body::sph_solid, Body::spg); }
TEST(MixedDecks, SphFluidAndSpg) { run_bodies(Body::sph_fluid, Body::spg); }
TEST(MixedDecks, FemAlone) { run_bodies(Body::fem); }
TEST(MixedDecks, SphSolidAndFem) { run_bodies(Body::sph_solid, Body::fem); }
TEST(MixedDecks, SphFluidAndFem) { run_bodies(Body::sph_fluid, Body::fem); }
TEST(MixedDecks, SpgAndFem) { run_bodies(Body::spg, Body::fem); }

TEST(MixedDecks, NodeSharedBySphParticleAndSpgElementIsRefused) {
  log::set_quiet(true);
  DeckFolder folder;
  std::string deck = deck_of({Body::sph_solid, Body::spg});
  // Particle 1000 of part 1 moves onto the SPG mesh's first node.
  const auto at = deck.find(row({"1000", "1", fmt::format("{:.8g}", 7850.0 * dx * dx * dx)}, {8, 8, 16}));
  ASSERT_NE(at, std::string::npos);
  deck.replace(at, 8, row({"2000"}, {8}).substr(0, 8));
  const auto path = folder.write("shared.k", deck);
  const std::string error = test::input_error_of([&] { solver::build_problem(io::keyword::read_deck(path)); });
  EXPECT_NE(error.find("share nodes"), std::string::npos) << error;
}
