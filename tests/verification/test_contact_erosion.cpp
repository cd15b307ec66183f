// Contact surfaces that follow element erosion (fem-contact.md §1.6: "no contact is assumed after
// erosion of the corresponding element"; EROSOP 1 of the *CONTACT_ERODING_ types keeps the faces
// inside the body, to take part once the element beyond them has eroded). A small rigid cube rests
// under gravity on an elastic FEM slab whose elements under it are deleted at FAILTM
// (*MAT_ADD_EROSION): from then on it falls freely, z = z0 - g (t - FAILTM)^2 / 2 (Galileo), until
// a face meets it again.
// - A plate with one element under the cube: once that element is gone its top face leaves the
//   contact (its corners, shared with the plate, stay), and the cube falls through the hole.
// - Two layers, the top one eroding: *CONTACT_AUTOMATIC_NODES_TO_SURFACE has only the slab's outer
//   faces, and the cube falls through the bottom layer; *CONTACT_ERODING_NODES_TO_SURFACE (EROSOP
//   1) brings in the bottom layer's top faces as the top layer erodes, and the cube lands on them
//   after falling one layer: h = g t^2 / 2, t = sqrt(2 h / g).
// Tolerances: 2 % of the fall at 30 ms (the erosion comes at the first step at or past FAILTM, one
// step of 80 us late at most: 0.3 % of the drop; the contact's sag under the cube's weight, 1e-7 m);
// the landed cube within 5 % of a layer of the exposed face (penalty sag and bounce).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "support/contact_decks.hpp"

using namespace spall;
using namespace spall::test_support;

namespace {

constexpr Real gravity = 9.81;
constexpr Real cell = 0.01;            // m: the slab's element size
constexpr Real cube = 0.006;           // m: the rigid cube's edge, over the middle element
constexpr Real failure_time = 0.02;    // s: FAILTM of part 3

enum class Slab { plate_with_eroding_middle, two_layers_top_eroding };

// The slab (parts 2 and 3, 3 x 3 elements across, bottom held) and the cube (rigid part 1) resting
// on the middle of its top; the contact's SURFB is both slab parts.
std::string deck(Slab slab, const std::string& contact, Real end_time) {
  const int layers = slab == Slab::plate_with_eroding_middle ? 1 : 2;
  const Real top = layers * cell;
  std::string d = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)});
  d += rigid_part(1, 1000, 1e7, 0.3, false) +
       hex_box(1, Vec3(1.5 * cell - cube / 2, 1.5 * cell - cube / 2, top), Vec3(cube, cube, cube), {1, 1, 1}, 1001,
               1001);
  for (Id pid : {2, 3}) d += deformable_part(Body::fem, pid, 1000, 1e7, 0.3);
  d += "*MAT_ADD_EROSION\n" + row({"3"}) + row({"", "", "", "", "", "", "", number(failure_time)});
  std::vector<Id> bottom;
  const auto part_of = [&](int i, int j, int k) -> Id {
    if (slab == Slab::plate_with_eroding_middle) return i == 1 && j == 1 ? 3 : 2;
    return k == 1 ? 3 : 2;
  };
  d += hex_box(part_of, Vec3::Zero(), Vec3(3 * cell, 3 * cell, top), {3, 3, layers}, 1, 1, &bottom);
  d += node_set(1, bottom) + "*BOUNDARY_SPC_SET\n" + row({"1", "0", "1", "1", "1", "1", "1", "1"});
  d += "*SET_PART_LIST\n" + row({"1"}) + row({"2", "3"});
  d += contact + row({"1", "1", "3", "2"}) + row({"0.0", "0.0", "0.0", "0.0", "50.0"}) + row({});
  if (contact.starts_with("*CONTACT_ERODING")) d += row({"0", "1", "0"});  // ISYM EROSOP IADJ
  d += "*DEFINE_CURVE\n" + row({"1"}) + row({"0.0", "1.0"}, {20, 20}) + row({"10.0", "1.0"}, {20, 20});
  d += "*LOAD_BODY_Z\n" + row({"1", number(gravity)});
  return d + "*END\n";
}

// The cube's lowest z at `when` (ascending times) and at the end.
std::vector<Real> cube_heights(const std::string& text, std::vector<Real> when, Real end_time) {
  log::set_quiet(true);
  test::DeckFolder folder;
  const model::Model model = io::keyword::read_deck(folder.write("erosion.k", text));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  const auto lowest = [&] {
    Real z = 1;
    for (Index i = 0; i < problem.nodes.size(); ++i)
      if (problem.nodes.part[i] == 1) z = std::min(z, problem.nodes.x[i].z());
    return z;
  };
  std::vector<Real> heights;
  solver::Observer observer;
  observer.on_step = [&](const solver::StepInfo& step) {
    if (heights.size() < when.size() && step.time >= when[heights.size()]) heights.push_back(lowest());
  };
  solver::run(problem, observer);
  heights.push_back(lowest());
  for (std::size_t k = 0; k < heights.size(); ++k)
    std::printf("t = %.4f s: the cube's lowest z %.6e m\n", k < when.size() ? when[k] : end_time, heights[k]);
  EXPECT_EQ(heights.size(), when.size() + 1);
  heights.resize(when.size() + 1);
  return heights;
}

constexpr Real fall_time = 0.03;  // s after FAILTM
const Real fall = gravity * fall_time * fall_time / 2;  // 4.41 mm, under half a layer

TEST(ContactErosion, ACubeFallsThroughTheHoleOfAnErodedElement) {
  for (const char* contact : {"*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n", "*CONTACT_ERODING_NODES_TO_SURFACE\n"}) {
    // Until FAILTM it rests on the plate (z = cell); 60 ms after it, it has left the plate
    // (g t^2 / 2 = 17.7 mm below its top).
    const Real end = failure_time + 0.06;
    const auto z = cube_heights(deck(Slab::plate_with_eroding_middle, contact, end),
                                {failure_time - 0.001, failure_time + fall_time}, end);
    EXPECT_NEAR(z[0], cell, 1e-5) << contact;
    EXPECT_NEAR((cell - z[1]) / fall, 1.0, 0.02) << contact << "z " << z[1];
    EXPECT_NEAR((cell - z[2]) / (gravity * 0.06 * 0.06 / 2), 1.0, 0.02) << contact << "z " << z[2];
  }
}

TEST(ContactErosion, ErodingContactCatchesTheCubeOnTheFaceErosionExposes) {
  const Real end = failure_time + 0.12;
  // The ordinary contact: the top layer's faces go with it, the faces below were never a surface.
  const auto through = cube_heights(deck(Slab::two_layers_top_eroding, "*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n", end),
                                    {failure_time - 0.001, failure_time + fall_time}, end);
  EXPECT_NEAR(through[0], 2 * cell, 1e-5);
  EXPECT_NEAR((2 * cell - through[1]) / fall, 1.0, 0.02) << through[1];
  EXPECT_LT(through[2], 0.0);  // below the slab
  // EROSOP 1: falls one layer (for sqrt(2 h / g) = 45 ms) and stays on the exposed face.
  const auto caught = cube_heights(deck(Slab::two_layers_top_eroding, "*CONTACT_ERODING_NODES_TO_SURFACE\n", end),
                                   {failure_time - 0.001, failure_time + fall_time}, end);
  EXPECT_NEAR(caught[0], 2 * cell, 1e-5);
  EXPECT_NEAR((2 * cell - caught[1]) / fall, 1.0, 0.02) << caught[1];
  EXPECT_NEAR(caught[2], cell, 0.05 * cell);
}

}  // namespace
