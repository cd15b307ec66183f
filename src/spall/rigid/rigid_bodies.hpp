#pragma once
// Rigid bodies (*MAT_RIGID parts; fem-contact.md §2.5): each body is a set of nodes of the shared
// node store that move together. In the constraints phase a body sums its nodes' forces and
// moments, advances its centre's velocity and its angular momentum, applies its constraints and
// prescribed motion, turns by the exact rotation of its angular velocity over the step, and gives
// each node the velocity that carries it to its rigid position x_c + R r_I (so the body stays
// rigid to round-off however long it runs: the positions are never integrated, only placed).
// docs/THEORY.md §11.
#include <array>
#include <span>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/field_set.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/model/curve.hpp"

namespace spall::rigid {

// A prescribed motion of one degree of freedom of a body (*BOUNDARY_PRESCRIBED_MOTION_RIGID): the
// translation of its centre, or its rotation about an axis through the centre, along `direction`
// (a unit vector: DOF 1-3 and 5-7 the global axes, numbered `axis` 0-2, set exactly; DOF 4 and 8
// a *DEFINE_VECTOR, axis -1, the motion normal to it free).
struct PrescribedMotion {
  bool rotation = false;
  int axis = 0;
  Vec3 direction = Vec3::UnitX();
  int vad = 0;  // 0 velocity, 1 acceleration, 2 displacement (for rotations: angle)
  const model::Curve* curve = nullptr;
  Real sf = 1;
  Real birth = 0, death = 1e28;

  // The component of a vector along the motion's direction, and setting it to `value`.
  Real along(const Vec3& x) const { return axis >= 0 ? x[axis] : x.dot(direction); }
  void set_along(Vec3& x, Real value) const {
    if (axis >= 0)
      x[axis] = value;
    else
      x += (value - x.dot(direction)) * direction;
  }
};

struct RigidBody {
  Id part_id = 0;
  std::vector<Index> node;  // node-store indices
  std::vector<Vec3> offset;  // r_I: the node's position from the centre in the body's frame
  Real mass = 0;
  Mat3 inertia = Mat3::Zero();  // J about the centre, in the body's frame (the world's at t = 0)
  Vec3 centre = Vec3::Zero();   // x_c
  Vec3 initial_centre = Vec3::Zero();
  Vec3 angle = Vec3::Zero();    // the rotation so far, sum of dt omega (VAD 2: its component along the axis)
  Mat3 rotation = Mat3::Identity();
  Vec3 velocity = Vec3::Zero();          // v_c at the half step
  Vec3 angular_momentum = Vec3::Zero();  // L about the centre, world frame, at the half step
  Vec3 angular_velocity = Vec3::Zero();  // omega at the half step
  // *MAT_RIGID CMO 1 (CON1, CON2) or -1 (CON2's digits): the components held, along the columns of
  // constraint_axes (the world's, or CMO -1's coordinate system CON1).
  std::array<bool, 3> fixed_translation{}, fixed_rotation{};
  Mat3 constraint_axes = Mat3::Identity();
  std::vector<PrescribedMotion> motions;
  Vec3 force = Vec3::Zero(), moment = Vec3::Zero();  // of the nodes' forces at the last step
  Vec3 step_centre = Vec3::Zero();  // x_c at the last step's start, where force and moment act
  // v_c, L and omega at the half step before the last update (for the energies at t^n).
  Vec3 last_velocity = Vec3::Zero(), last_angular_momentum = Vec3::Zero(), last_angular_velocity = Vec3::Zero();

  // v_c at the point `weight` of the way from the last half step to this one (t^n at the time
  // loop's weight), and the kinetic energy there, 1/2 m v_c.v_c + 1/2 omega.L (the body's own mass
  // properties, not its nodes', so that *PART_INERTIA counts as it moves).
  Vec3 velocity_at(Real weight) const { return last_velocity + weight * (velocity - last_velocity); }
  Real kinetic_energy_at(Real weight) const {
    const Vec3 w = last_angular_velocity + weight * (angular_velocity - last_angular_velocity);
    const Vec3 L = last_angular_momentum + weight * (angular_momentum - last_angular_momentum);
    return Real(0.5) * mass * velocity_at(weight).squaredNorm() + Real(0.5) * w.dot(L);
  }
  // J in the world's frame at the rotation R: R J0 R^T.
  Mat3 world_inertia(const Mat3& R) const { return R * inertia * R.transpose(); }

  // The motion; the nodes, mass properties and prescribed motions are the deck's.
  void checkpoint(Archive& a) {
    a(centre, angle, rotation, velocity, angular_momentum, angular_velocity, force, moment, step_centre,
      last_velocity, last_angular_momentum, last_angular_velocity);
  }
};

// The rotation by the angle |phi| about phi / |phi| (Rodrigues' formula).
Mat3 rotation_of(const Vec3& phi);

// A body's mass, centre and inertia about it (world axes) given rather than summed from its nodes
// (*PART_INERTIA).
struct MassProperties {
  Real mass = 0;
  Vec3 centre = Vec3::Zero();
  Mat3 inertia = Mat3::Zero();
};

class RigidBodies {
 public:
  // Mass, centre, inertia, velocity and angular momentum from the nodes' masses, positions and
  // velocities at the start; marks the nodes' body in `nodes.body`. With `given` properties (whose
  // mass and centre the nodes' masses must carry: rigid/setup.cpp) the inertia is the given one,
  // and the angular momentum J omega for the omega of the nodes' velocities.
  void add(RigidBody body, discretization::NodeStore& nodes, const MassProperties* given = nullptr);

  // The bodies' share of the energy ledger at t^n, their nodes' left out of the time loop's sums:
  // the kinetic energy at the point `weight` of the way from the last half step to this one
  // (RigidBody::kinetic_energy_at), and the power of the constraints and prescribed motions (the
  // momentum and angular momentum they added over dt_mid, against the body's forces) at the point
  // `reaction_weight`.
  struct Energies {
    Real kinetic = 0;
    Real reaction_power = 0;
  };
  Energies energies(Real weight, Real reaction_weight, Real dt_mid) const;

  // The constraints phase of step n: nodes at x^n with forces f^n, velocities v^{n+1/2} from the
  // velocity update (which the bodies overwrite for their nodes). `time` is t^n, `dt` the step
  // to t^{n+1}, `dt_mid` the one the velocities were advanced by.
  void advance(discretization::NodeStore& nodes, Real time, Real dt, Real dt_mid);

  // An element of a body, for the field output: its shape, deck ID and node-store corners (VTK's
  // order, which is LS-DYNA's for these shapes).
  void add_cell(discretization::CellShape shape, Id element_id, std::span<const Index> corners);
  // The bodies' elements as cell blocks with their `element_id`, so that ParaView draws the tool.
  void write_fields(discretization::FieldSet& fields) const;

  // Every body's nodes' rows, ascending, each once.
  const std::vector<Index>& node_rows() const { return node_rows_; }
  // Under MPI with the velocities by reach (NodeStore::velocities_by_reach), before advance: each
  // body node's force from the rank that owns it, whole there (its formulations' forces, the loads
  // and every contact touch), in place of every node's force from every rank (collective; the nodes
  // dealt in blocks).
  void share_forces(discretization::NodeStore& nodes) const;

  const std::vector<RigidBody>& bodies() const { return bodies_; }
  bool empty() const { return bodies_.empty(); }
  void checkpoint(Archive& a) {
    a.expect_size("rigid bodies", bodies_.size());
    a(bodies_);
  }

 private:
  std::vector<RigidBody> bodies_;
  std::vector<Index> node_rows_;
  std::vector<discretization::CellBlock> cells_;  // one block a shape
};

}  // namespace spall::rigid
