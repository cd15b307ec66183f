// ISYM 1 (fem-contact.md §1.6: "do not include faces with normal boundary constraints (e.g.,
// segments of brick elements on a symmetry plane)"): a face on a symmetry plane of the model is no
// contact surface. A rigid cube overlapping the face x = 0 of an elastic block, whose nodes there an
// SPC holds in x (the plane of a half model), slides along it at 1 m/s with friction mu = 0.5:
// - ISYM 0: the face pushes the cube out (a velocity along -x) and friction slows it;
// - ISYM 1 (card B, or *CONTROL_CONTACT's card 5): the face is no segment, nothing acts on the
//   cube, which keeps its velocity to round-off (Newton's first law);
// - ISYM 1 with the SPC holding y instead of x: the face is no symmetry plane and pushes as with 0.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "support/contact_decks.hpp"

using namespace spall;
using namespace spall::test_support;

namespace {

constexpr Real speed = 1.0;

// The block (part 2, 3 x 3 x 5 hexahedra of 10 mm, x from 0) with its x = 0 nodes held along
// `held` (DOFX DOFY DOFZ of *BOUNDARY_SPC_SET); the cube (rigid part 1, 6 mm) 0.4 mm into it
// across that face, moving along z. `isym` on the contact's optional card B, or `control_isym`
// on *CONTROL_CONTACT card 5.
std::string deck(const std::string& isym, const std::string& control_isym, std::array<const char*, 3> held) {
  std::string d = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({"5.0e-3"});
  d += rigid_part(1, 1000, 1e7, 0.3, false) +
       hex_box(1, Vec3(-0.0056, 0.012, 0.02), Vec3(0.006, 0.006, 0.006), {1, 1, 1}, 1001, 1001);
  d += deformable_part(Body::fem, 2, 1000, 1e7, 0.3) +
       hex_box(2, Vec3::Zero(), Vec3(0.03, 0.03, 0.05), {3, 3, 5}, 1, 1);
  std::vector<Id> plane;  // the block's nodes at x = 0: i = 0 of its 4 x 4 x 6 lattice
  for (int k = 0; k <= 5; ++k)
    for (int j = 0; j <= 3; ++j) plane.push_back(1 + 4 * (j + 4 * k));
  d += node_set(1, plane) + "*BOUNDARY_SPC_SET\n" + row({"1", "0", held[0], held[1], held[2]});
  d += "*CONTROL_CONTACT\n" + row({}) + row({}) + row({}) + row({}) + row({control_isym});
  d += "*CONTACT_AUTOMATIC_NODES_TO_SURFACE\n" + row({"1", "2", "3", "3"}) + row({"0.5", "0.5"}) + row({}) +
       row({}) + row({"", "", "", "", isym});
  d += "*INITIAL_VELOCITY_GENERATION\n" + row({"1", "2", "0.0", "0.0", "0.0", number(speed)}) + row({});
  return d + "*END\n";
}

// The cube's velocity at the end.
Vec3 cube_velocity(const std::string& text) {
  log::set_quiet(true);
  test::DeckFolder folder;
  const model::Model model = io::keyword::read_deck(folder.write("symmetry.k", text));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  solver::run(problem, {});
  for (Index i = 0; i < problem.nodes.size(); ++i)
    if (problem.nodes.part[i] == 1) return problem.nodes.v[i];
  return Vec3::Constant(std::nan(""));
}

TEST(ContactSymmetry, AFaceOnASymmetryPlaneIsNoSegmentWithIsym) {
  const Vec3 pushed = cube_velocity(deck("0", "0", {"1", "0", "0"}));
  std::printf("ISYM 0: the cube's velocity (%.6g, %.6g, %.6g) m/s\n", pushed.x(), pushed.y(), pushed.z());
  EXPECT_LT(pushed.x(), -1e-3 * speed);
  EXPECT_LT(pushed.z(), speed * (1 - 1e-3));
  for (const auto& [isym, control] : {std::pair{"1", ""}, std::pair{"", "1"}}) {
    const Vec3 free = cube_velocity(deck(isym, control, {"1", "0", "0"}));
    std::printf("ISYM %s, *CONTROL_CONTACT ISYM %s: (%.6g, %.6g, %.6g) m/s\n", isym, control, free.x(), free.y(),
                free.z());
    EXPECT_NEAR((free - Vec3(0, 0, speed)).norm(), 0.0, 1e-12 * speed);
  }
  // Held along y, the face x = 0 is no symmetry plane: it pushes.
  const Vec3 not_symmetry = cube_velocity(deck("1", "0", {"0", "1", "0"}));
  EXPECT_LT(not_symmetry.x(), -1e-3 * speed);
}

}  // namespace
