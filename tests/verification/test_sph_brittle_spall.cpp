// A brittle bar broken by a stress pulse: the coarse version of examples/brittle_spall
// (tools/make_brittle_deck.py --across 4 --treat 0). A glass-like bar 100 x 10 x 10 mm (40 x 4 x 4
// particles), *MAT_JOHNSON_COOK elastic (A 4 GPa is never reached) with the spall model SPALL 2
// (a particle fails when its largest principal stress reaches sigma_s = -PC), is driven at x = 0
// by a triangular velocity pulse (0 -> V0 in TR, back to 0 over TD, then released). 1D wave theory
// of a free bar (Kolsky, Stress Waves in Solids, 1953; Rinehart, J. Appl. Phys. 22, 555, 1951:
// scabbing): the pulse, peak sigma0 = rho c0 V0 and tail lambda = c0 TD, reflects at the free end
// as tension, and the net tension 2 sigma0 y / lambda at the returning peak's distance y from the
// end reaches sigma0 at most, so
//   - the bar holds when sigma0 < sigma_s and breaks when sigma0 > sigma_s (here 0.9 and 1.1
//     sigma_s: tolerance 10 %);
//   - the first scab is delta = sigma_s lambda / (2 sigma0) long (tolerance 1.5 spacings: the
//     failed particles form a layer, not a plane) and leaves at (2 sigma0 - sigma_s) / (rho c0)
//     (tolerance 10 %);
//   - floor(sigma0 / sigma_s) scabs come off (two at sigma0 = 2 sigma_s);
//   - the momentum of all pieces is the impulse rho c0 A integral(V dt) = rho c0 A V0 (TR + TD) / 2
//     that the driven end put in (tolerance 2 %: the pulse's dispersion in the 3D bar).
// Fragments: particles joined by chains of links shorter than 1.5 initial spacings
// (tools/count_fragments.py does the same on output files).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "spall/sph/solid.hpp"
#include "unit/keyword_test_decks.hpp"

using namespace spall;
using test::DeckFolder;
using test::row;

namespace {

// kg, mm, ms: stress GPa, speed m/s. Soda-lime glass elastic constants (handbook).
constexpr Real rho = 2.5e-6, E = 70.0, nu = 0.22, spall_strength = 0.15;
constexpr Real length = 100.0, width = 10.0;
constexpr int across = 4, along = 40;
constexpr Real dx = width / across;
constexpr Real rise = 3e-3;  // TR, ms
const Real c0 = std::sqrt(E / rho);
const Real decay = 0.6 * length / c0;  // TD: a tail of 60 mm

std::string number(Real value) {
  char text[24];
  std::snprintf(text, sizeof text, "%.6g", value);  // fits a 10-column field
  return text;
}

std::string bar_deck(Real speed, Real end_time) {
  const Real pulse_end = rise + decay;
  std::string set;
  for (int k = 0; k < across; ++k)
    for (int j = 0; j < across; ++j) set += row({std::to_string(1 + along * (j + across * k))});
  return "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)}) + "*CONTROL_TIMESTEP\n" +
         row({"0.0", "0.9"}) + "*PART\nbar\n" + row({"1", "1", "1"}) + "*SECTION_SPH\n" +
         row({"1", "1.2", "0.2", "2.0"}) + "*MAT_JOHNSON_COOK\n" +
         row({"1", number(rho), number(E / (2 * (1 + nu))), number(E), number(nu)}) +
         row({"4.0", "0.0", "0.0", "0.0", "1.0", "1000.0", "293.0", "1.0"}) +
         row({"840.0", number(-spall_strength), "2"}) + "*DEFINE_SPH_MESH_BOX\n" +
         row({number(-dx / 2), "0.0", "0.0", number(length), number(width), number(width)}) +
         row({"1", std::to_string(along), std::to_string(across), std::to_string(across)}) +
         "*SET_NODE_LIST\n" + row({"1"}) + set + "*BOUNDARY_PRESCRIBED_MOTION_SET\n" +
         row({"1", "1", "0", "1", number(speed), "0", number(pulse_end), "0.0"}) +
         "*DEFINE_CURVE\n" + row({"1"}) + row({"0.0", "0.0"}, {20, 20}) +
         row({number(rise), "1.0"}, {20, 20}) + row({number(pulse_end), "0.0"}, {20, 20}) +
         row({number(10 * pulse_end), "0.0"}, {20, 20}) + "*END\n";
}

struct Piece {
  Index particles = 0;
  Real mass = 0;
  Vec3 momentum = Vec3::Zero();
  Real x0_min = 0, x0_max = 0;  // extent along the bar in the initial configuration
  Real velocity() const { return momentum.x() / mass; }
};

struct Outcome {
  Index failed = 0;
  std::vector<Piece> pieces;  // the piece holding the free end first, then by falling x
  Vec3 momentum = Vec3::Zero();
};

Index root(std::vector<Index>& parent, Index i) {
  while (parent[i] != i) i = parent[i] = parent[parent[i]];
  return i;
}

Outcome break_bar(Real stress_ratio, Real end_time) {
  const Real speed = stress_ratio * spall_strength / (rho * c0);  // sigma0 = rho c0 V0
  DeckFolder folder;
  const model::Model model = io::keyword::read_deck(folder.write("bar.k", bar_deck(speed, end_time)));
  solver::Problem problem = solver::build_problem(model);
  solver::run(problem, {});
  const auto& sph = dynamic_cast<const sph::SolidFormulation&>(*problem.formulations.front());
  discretization::FieldSet field_set(problem.nodes.size());
  sph.write_fields(field_set, problem.nodes);
  const auto& fields = field_set.node_fields();
  const auto& failed = std::get<std::vector<std::int64_t>>(
      std::find_if(fields.begin(), fields.end(), [](const auto& f) { return f.name == "failed"; })->values);

  const auto& nodes = problem.nodes;
  const Index n = nodes.size();
  Outcome outcome;
  std::vector<Index> parent(n);
  std::iota(parent.begin(), parent.end(), 0);
  const Real link = 1.5 * dx;
  for (Index a = 0; a < n; ++a) {
    outcome.failed += failed[a];
    outcome.momentum += nodes.mass[a] * nodes.v[a];
    for (Index b = a + 1; b < n; ++b)
      if ((nodes.x[a] - nodes.x[b]).squaredNorm() < link * link) parent[root(parent, a)] = root(parent, b);
  }
  std::vector<Index> piece_of(n, -1);
  for (Index a = 0; a < n; ++a) {
    const Index r = root(parent, a);
    if (piece_of[r] < 0) {
      piece_of[r] = static_cast<Index>(outcome.pieces.size());
      outcome.pieces.push_back({0, 0, Vec3::Zero(), nodes.x0[a].x(), nodes.x0[a].x()});
    }
    Piece& p = outcome.pieces[piece_of[r]];
    ++p.particles;
    p.mass += nodes.mass[a];
    p.momentum += nodes.mass[a] * nodes.v[a];
    p.x0_min = std::min(p.x0_min, nodes.x0[a].x());
    p.x0_max = std::max(p.x0_max, nodes.x0[a].x());
  }
  std::sort(outcome.pieces.begin(), outcome.pieces.end(),
            [](const Piece& a, const Piece& b) { return a.x0_max > b.x0_max; });
  std::printf("sigma0/sigma_s %.2f: %lld failed particles, %zu pieces:", stress_ratio,
              static_cast<long long>(outcome.failed), outcome.pieces.size());
  for (const Piece& p : outcome.pieces)
    std::printf(" [%lld particles, x0 %.2f..%.2f mm, %.3f m/s]", static_cast<long long>(p.particles),
                p.x0_min, p.x0_max, p.velocity());
  std::printf("\n");
  return outcome;
}

// rho c0 A V0 (TR + TD) / 2: the momentum a triangular velocity pulse puts into a bar end.
Real pulse_impulse(Real stress_ratio) {
  return stress_ratio * spall_strength * width * width * (rise + decay) / 2;
}

}  // namespace

TEST(SphBrittleSpall, HoldsBelowAndBreaksAboveTheSpallStrength) {
  log::set_quiet(true);
  const Outcome below = break_bar(0.9, 0.2);
  EXPECT_EQ(below.failed, 0);
  EXPECT_EQ(below.pieces.size(), 1u);
  const Outcome above = break_bar(1.1, 0.2);
  EXPECT_GT(above.failed, 0);
  EXPECT_EQ(above.pieces.size(), 2u);
}

TEST(SphBrittleSpall, ScabLengthAndSpeed) {
  log::set_quiet(true);
  const Real ratio = 1.2;
  const Outcome outcome = break_bar(ratio, 0.2);
  ASSERT_EQ(outcome.pieces.size(), 2u);
  const Piece& scab = outcome.pieces.front();
  const Real delta = spall_strength * c0 * decay / (2 * ratio * spall_strength);
  const Real scab_length = scab.x0_max - scab.x0_min + dx;  // the particles' cells
  EXPECT_NEAR(scab_length, delta, 1.5 * dx);
  const Real scab_speed = (2 * ratio - 1) * spall_strength / (rho * c0);
  EXPECT_NEAR(scab.velocity(), scab_speed, 0.1 * scab_speed);
  EXPECT_NEAR(outcome.momentum.x(), pulse_impulse(ratio), 0.02 * pulse_impulse(ratio));
}

TEST(SphBrittleSpall, TwoScabsAtTwiceTheSpallStrength) {
  log::set_quiet(true);
  const Real ratio = 2.0;
  const Outcome outcome = break_bar(ratio, 0.2);
  ASSERT_EQ(outcome.pieces.size(), 3u);  // floor(sigma0 / sigma_s) scabs and the rest
  const Real first_speed = (2 * ratio - 1) * spall_strength / (rho * c0);
  EXPECT_NEAR(outcome.pieces[0].velocity(), first_speed, 0.1 * first_speed);
  EXPECT_NEAR(outcome.momentum.x(), pulse_impulse(ratio), 0.02 * pulse_impulse(ratio));
}
