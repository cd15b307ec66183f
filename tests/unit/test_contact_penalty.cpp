// The contact module's pieces against hand results: the closest point of a triangle and of a
// quadrilateral segment, the bucket grid, and the penalty and friction response of one node on
// one rigid segment (fem-contact.md §2.6-2.8; docs/THEORY.md §12).
#include <gtest/gtest.h>

#include <cmath>

#include "spall/contact/penalty_contact.hpp"
#include "spall/contact/segment.hpp"
#include "spall/contact/segment_grid.hpp"

namespace spall::contact {
namespace {

using discretization::NodeStore;

TEST(ClosestOnTriangle, FaceEdgeAndVertexRegions) {
  const Vec3 a(0, 0, 0), b(1, 0, 0), c(0, 1, 0);
  auto point = [&](const Vec3& p) {
    const auto w = closest_on_triangle(p, a, b, c);
    EXPECT_NEAR(w[0] + w[1] + w[2], 1.0, 1e-15);
    return Vec3(w[0] * a + w[1] * b + w[2] * c);
  };
  EXPECT_LT((point({0.2, 0.3, 5}) - Vec3(0.2, 0.3, 0)).norm(), 1e-15);    // above the face
  EXPECT_LT((point({0.5, -2, -1}) - Vec3(0.5, 0, 0)).norm(), 1e-15);     // beside edge ab
  EXPECT_LT((point({1, 1, 0}) - Vec3(0.5, 0.5, 0)).norm(), 1e-15);       // beside edge bc
  EXPECT_LT((point({-1, -1, 3}) - a).norm(), 1e-15);                     // beyond vertex a
  EXPECT_LT((point({3, -0.5, 0}) - b).norm(), 1e-15);                    // beyond vertex b
  EXPECT_LT((point({-0.5, 4, 0}) - c).norm(), 1e-15);                    // beyond vertex c
}

TEST(ClosestOnSegment, QuadrilateralWeightsSpreadThePointToItsCorners) {
  // The unit square seen from +z: a point above (0.25, 0.5) has weights that rebuild it.
  const std::array<Vec3, 4> x = {Vec3(0, 0, 0), Vec3(1, 0, 0), Vec3(1, 1, 0), Vec3(0, 1, 0)};
  const SegmentPoint p = closest_on_segment(Vec3(0.25, 0.5, -0.1), x, false);
  EXPECT_NEAR(std::sqrt(p.distance_squared), 0.1, 1e-15);
  EXPECT_LT((p.normal - Vec3::UnitZ()).norm(), 1e-15);
  Vec3 rebuilt = Vec3::Zero();
  Real sum = 0;
  for (int k = 0; k < 4; ++k) rebuilt += p.weight[k] * x[k], sum += p.weight[k];
  EXPECT_NEAR(sum, 1.0, 1e-15);
  EXPECT_LT((rebuilt - Vec3(0.25, 0.5, 0)).norm(), 1e-15);
  // At the centre the four corners share alike.
  const SegmentPoint centre = closest_on_segment(Vec3(0.5, 0.5, 1), x, false);
  for (int k = 0; k < 4; ++k) EXPECT_NEAR(centre.weight[k], 0.25, 1e-15);
}

TEST(SegmentGrid, FindsEverySegmentWithinItsReach) {
  // A row of 50 unit squares along x; each segment must be a candidate for points within its reach.
  std::vector<Vec3> x;
  std::vector<Segment> segments;
  for (int i = 0; i <= 50; ++i) x.push_back(Vec3(i, 0, 0)), x.push_back(Vec3(i, 1, 0));
  for (Index i = 0; i < 50; ++i) {
    Segment s;
    s.node = {2 * i, 2 * i + 2, 2 * i + 3, 2 * i + 1};
    segments.push_back(s);
  }
  const std::vector<Real> reach(segments.size(), 0.3);
  SegmentGrid grid;
  grid.build(segments, reach, x);
  for (Index s = 0; s < 50; ++s)
    for (const Vec3& p : {Vec3(s + 0.5, 0.5, -0.29), Vec3(s + 0.01, 0.99, 0.29), Vec3(s + 0.99, -0.2, 0)}) {
      const auto found = grid.candidates(p);
      EXPECT_TRUE(std::find(found.begin(), found.end(), s) != found.end()) << s;
    }
  EXPECT_TRUE(grid.candidates(Vec3(10, 0.5, 5)).empty());  // far above
}

// One node of mass m over a fixed rigid square segment (corners in rigid body 0).
struct NodeOnSquare {
  NodeStore nodes;
  explicit NodeOnSquare(Real depth) {
    nodes.resize(5);
    const Vec3 corners[4] = {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)};
    for (int k = 0; k < 4; ++k) {
      nodes.x[k] = nodes.x0[k] = corners[k];
      nodes.mass[k] = 10;
      nodes.body[k] = 0;
    }
    nodes.x[4] = nodes.x0[4] = Vec3(0.2, 0.1, -depth);
    nodes.mass[4] = 2;
  }
  PenaltyContact contact(const PenaltyContact::Definition& d, Real node_stiffness, Real segment_stiffness) {
    PenaltyContact::Pass pass;
    pass.slave = {4};
    pass.slave_stiffness = {node_stiffness};
    Segment s;
    s.node = {0, 1, 2, 3};
    s.thickness = 1;
    s.stiffness = segment_stiffness;
    s.area = 4;
    pass.segment = {s};
    return PenaltyContact(d, {pass});
  }
};

TEST(PenaltyContact, PushesAPenetratingNodeOutWithTheSmallerStiffness) {
  NodeOnSquare scene(0.01);
  PenaltyContact::Definition d;  // PENOPT 1: min(node, segment)
  auto contact = scene.contact(d, 3e4, 5e4);
  contact.apply(scene.nodes, 0, 0);
  EXPECT_EQ(contact.touching(), 1);
  EXPECT_NEAR(scene.nodes.f[4].z(), 3e4 * 0.01, 1e-9);
  // The reaction on the segment's corners balances it, force and moment.
  Vec3 total = Vec3::Zero(), moment = Vec3::Zero();
  for (Index i = 0; i < 5; ++i) total += scene.nodes.f[i], moment += scene.nodes.x[i].cross(scene.nodes.f[i]);
  EXPECT_LT(total.norm(), 1e-12);
  EXPECT_LT(moment.norm(), 1e-12);
  EXPECT_NEAR(contact.side_a().force.z(), 300, 1e-9);
  EXPECT_NEAR(contact.side_b().force.z(), -300, 1e-9);
}

TEST(PenaltyContact, LetsGoOfANodeDeeperThanTheReleaseDepthOrInFront) {
  for (Real depth : {-0.01, 0.41}) {  // in front; deeper than 0.4 segment thicknesses
    NodeOnSquare scene(depth);
    auto contact = scene.contact({}, 1e4, 1e4);
    contact.apply(scene.nodes, 0, 0);
    EXPECT_EQ(contact.touching(), 0) << depth;
    EXPECT_EQ(scene.nodes.f[4], Vec3::Zero());
  }
}

TEST(PenaltyContact, TouchesBeyondAnEdgeOnlyWithinMaxpar) {
  // MAXPAR 1.025: a node whose projection lies beyond the segment's edge by up to 0.025 of its
  // size (2 for this square) still touches it; further out it does not.
  for (const auto& [x, touching] : {std::pair{1.04, 1}, std::pair{1.06, 0}}) {
    NodeOnSquare scene(0.01);
    scene.nodes.x[4].x() = x;
    auto contact = scene.contact({}, 1e4, 1e4);
    contact.apply(scene.nodes, 0, 0);
    EXPECT_EQ(contact.touching(), touching) << x;
  }
}

TEST(PenaltyContact, SoftConstraintStiffnessFollowsTheNodeMassAndStep) {
  // SOFT 1: k = max(k0, 0.5 SOFSCL m / dt^2) against a rigid segment (m* = the node's mass).
  NodeOnSquare scene(0.01);
  PenaltyContact::Definition d;
  d.soft = 1;
  d.soft_scale = 0.1;
  auto contact = scene.contact(d, 1.0, 1.0);
  contact.set_first_step(1e-3);
  contact.apply(scene.nodes, 0, 0);
  EXPECT_NEAR(scene.nodes.f[4].z(), 0.5 * 0.1 * 2 / 1e-6 * 0.01, 1e-6);
}

TEST(PenaltyContact, CoulombFrictionSticksThenSlidesAtMuTimesTheNormalForce) {
  NodeOnSquare scene(0.01);
  PenaltyContact::Definition d;
  d.friction.static_coefficient = 0.3;
  auto contact = scene.contact(d, 1e4, 1e4);
  const Real normal = 1e4 * 0.01;
  // A slow slide: the elastic trial k v dt stays under mu f_n, the node sticks.
  scene.nodes.v[4] = Vec3(1e-3, 0, 0);
  contact.apply(scene.nodes, 0, 1e-3);
  EXPECT_NEAR(scene.nodes.f[4].x(), -1e4 * 1e-3 * 1e-3, 1e-12);
  // A fast slide: the friction force is capped at mu f_n, against the sliding.
  scene.nodes.f[4] = Vec3::Zero();
  scene.nodes.v[4] = Vec3(0, 10, 0);
  contact.apply(scene.nodes, 0, 1e-3);
  EXPECT_NEAR(scene.nodes.f[4].norm(), std::hypot(normal, 0.3 * normal), 1e-9);
  EXPECT_NEAR(scene.nodes.f[4].z(), normal, 1e-12);
  EXPECT_LT(scene.nodes.f[4].y(), 0);
  // Exponential decay: mu = FD + (FS - FD) exp(-DC v).
  PenaltyContact::Friction f{0.5, 0.2, 2.0, 0};
  EXPECT_NEAR(f.coefficient(0), 0.5, 1e-15);
  EXPECT_NEAR(f.coefficient(1.0), 0.2 + 0.3 * std::exp(-2.0), 1e-15);
}

TEST(PenaltyContact, ViscousDampingResistsTheApproach) {
  // VDC: c = VDC/100 * 2 sqrt(k m) against a rigid segment; moving deeper at 1 adds c, moving out
  // at 1 takes it off.
  NodeOnSquare scene(0.01);
  PenaltyContact::Definition d;
  d.damping = 0.2;
  auto contact = scene.contact(d, 1e4, 1e4);
  const Real c = 0.2 * 2 * std::sqrt(1e4 * 2.0);
  for (Real v : {-1.0, 1.0}) {  // the segment faces +z; the node is behind it, below
    scene.nodes.f[4] = Vec3::Zero();
    scene.nodes.v[4] = Vec3(0, 0, v);
    contact.apply(scene.nodes, 0, 1e-3);
    EXPECT_NEAR(scene.nodes.f[4].z(), 1e4 * 0.01 - c * v, 1e-9);
  }
}

TEST(PenaltyContact, ANodeCaughtDeepIsPushedOnlyBeyondTheDepthItWasFoundAt) {
  // A node found behind the segment deeper than its approach over the last step brings it (let go
  // below the release depth and caught again as the tool moved on) pushes only with the depth
  // beyond the one it was found at, which shrinks as it comes out (THEORY §12.3): k d at d = 0.3
  // would shoot it out at d sqrt(k / m).
  NodeOnSquare scene(-0.01);  // in front: the contact's first step finds nothing
  auto contact = scene.contact({}, 1e4, 1e4);
  const Real dt = 1e-3;
  contact.apply(scene.nodes, 0, dt);
  ASSERT_EQ(contact.touching(), 0);
  auto push_at = [&](Real depth) {
    scene.nodes.x[4].z() = -depth;
    scene.nodes.f[4] = Vec3::Zero();
    contact.apply(scene.nodes, 0, dt);
    return scene.nodes.f[4].z();
  };
  EXPECT_EQ(push_at(0.3), 0);                           // found at rest 0.3 deep
  EXPECT_NEAR(push_at(0.35), 1e4 * 0.05, 1e-9);         // pushed 0.05 deeper
  EXPECT_EQ(push_at(0.1), 0);                           // comes out: the tracked depth follows
  EXPECT_NEAR(push_at(0.12), 1e4 * 0.02, 1e-9);         // and pushes from there
  EXPECT_EQ(push_at(-0.01), 0);                         // leaves
  // A node arriving at speed 1 is found at most 1 dt deep: pushed with its whole depth.
  scene.nodes.v[4] = Vec3(0, 0, -1);
  EXPECT_NEAR(push_at(0.8 * dt), 1e4 * 0.8 * dt, 1e-9);
}

}  // namespace
}  // namespace spall::contact
