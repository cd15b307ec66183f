#pragma once
// A planar rigid wall (*RIGIDWALL_PLANAR, _FINITE, _MOVING) as LS-DYNA's "stonewall": a kinematic
// constraint, not a penalty. After the velocity update, a tracked node that would be behind the
// wall at t^{n+1} = t^n + dt gets the normal velocity that puts it exactly on the wall at t^{n+1};
// friction then acts on its tangential velocity, limited by the normal impulse (Coulomb). The
// wall's force is the momentum those corrections give the nodes, over the step. A moving wall is
// a rigid body of mass M sliding along its normal: it takes the opposite impulses, so that the
// momentum of wall and nodes along the normal is conserved (docs/THEORY.md §5).
#include <cstdint>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/node_store.hpp"

namespace spall::contact {

class RigidWall {
 public:
  // FRIC as LS-DYNA codes it: 0 frictionless, (0, 1) Coulomb coefficient, 1 no sliding,
  // 2 welding with frictionless sliding, 3 welding with no sliding.
  struct Friction {
    Real coefficient = 0;  // Coulomb coefficient; 0 frictionless
    bool stick = false;    // no tangential sliding while in contact
    bool weld = false;     // a node that hits faster than weld_speed stays on the wall
    Real weld_speed = 0;   // WVEL
  };

  struct Definition {
    Id id = 0;                          // as reported in rwforc.csv
    Vec3 origin = Vec3::Zero();         // the tail point, on the wall at t = 0
    Vec3 normal = Vec3::UnitZ();        // unit, towards the side of the tracked nodes
    Vec3 edge_l = Vec3::UnitX();        // finite walls: unit edge directions in the plane,
    Vec3 edge_m = Vec3::UnitY();        // m = n x l, the rectangle's corner at the origin
    Real length_l = 0, length_m = 0;    // extents along l and m; 0 = unbounded
    Friction friction;
    Real birth = 0, death = 1e20;
    Real mass = 0;                      // 0: a fixed wall; > 0: a moving wall of this mass
    Real initial_velocity = 0;          // moving wall: velocity along the normal at t = 0
  };

  // `tracked` are the nodes' places in the deck, ascending; `front` says for each whether it
  // starts on the wall's front side (starts_in_front): one behind it is not caught until it comes
  // to the front.
  RigidWall(const Definition& definition, std::vector<Index> tracked, std::vector<std::uint8_t> front);
  static bool starts_in_front(const Definition& definition, const Vec3& x) {
    return definition.normal.dot(x - definition.origin) >= 0;
  }

  // Corrects the velocities v^{n+1/2} of nodes that would pass the wall over [t^n, t^n + dt]
  // (t_mid = t^n + dt/2 decides birth and death); dt_mid is the step of that velocity update,
  // over which the impulses become forces. Under MPI with velocities by reach
  // (NodeStore::velocities_by_reach) of a rank's own nodes, the force summed over the ranks (and a
  // moving wall's velocity solved from every rank's candidates); otherwise of every node, on every
  // rank alike.
  void enforce(discretization::NodeStore& nodes, Real t_mid, Real dt, Real dt_mid);
  // Under MPI with velocities by reach: every rank's contact state of its own nodes in, so that the
  // state is whole (a checkpoint; enforce does it itself when the nodes are dealt anew or move
  // between the ranks). Collective.
  void complete_state();
  // Moves a moving wall on to t^{n+1} with its new velocity.
  void advance(Real dt);

  const Definition& definition() const { return definition_; }
  const std::vector<Index>& tracked() const { return nodes_; }
  // The last step's force of the nodes on the wall, and its normal component (positive when
  // the nodes push against the wall).
  const Vec3& force() const { return force_; }
  Real normal_force() const { return normal_force_; }
  // The wall's motion and the nodes' contact state (a restart continues them).
  void checkpoint(Archive& a) {
    a.expect_size("nodes tracked by a rigid wall", nodes_.size());
    a(state_, velocity_, displacement_, active_now_, force_, normal_force_, closing_, candidate_, active_, free_,
      impulse_);
  }
  // A moving wall's velocity along its normal v^{n+1/2} and displacement along it at t^n.
  Real velocity() const { return velocity_; }
  Real displacement() const { return displacement_; }

 private:
  enum : std::uint8_t { in_front = 1, welded = 2 };  // state_ bits
  static constexpr std::uint8_t pushed_now = 2;      // candidate_ value of a pushed node

  bool inside(const Vec3& p) const;  // within the finite extent (point relative to the origin)
  // The wall's velocity after the impulses, and which candidates are pushed (`active_`).
  Real solve_wall_velocity();
  void share_candidates();
  // Each tracked node's row in `nodes`, once the rows change (NodeStore::layout); at a new
  // partition under MPI with velocities by reach, the state of the nodes this rank computed in the
  // last one to every rank first.
  void find_rows(const discretization::NodeStore& nodes, bool own_only);

  Definition definition_;
  std::vector<Index> nodes_;  // the tracked nodes' places in the deck
  std::vector<Index> row_;    // and their rows in the node store (-1: not held by this rank)
  long long rows_partition_ = -1, rows_layout_ = -1;
  // Under MPI with velocities by reach: 1 for the tracked nodes this rank computes, whose state_
  // is current here (empty while every rank holds every node's).
  std::vector<std::uint8_t> mine_;
  // The tracked nodes (positions in nodes_) whose state this rank keeps: those mine_ marks, or
  // every one; each step's pass goes over these alone.
  std::vector<Index> passed_;
  std::vector<std::uint8_t> state_;
  Real velocity_ = 0;
  Real displacement_ = 0;
  bool active_now_ = false;
  Vec3 force_ = Vec3::Zero();
  Real normal_force_ = 0;
  // Per step, per tracked node: closing value c = u + d/dt, with d the node's distance in front
  // of the wall at t^n and u its normal velocity; it passes the wall moving at V iff c < V.
  std::vector<Real> closing_;
  std::vector<std::uint8_t> candidate_;  // 1: in front and inside the extent; 2: pushed
  std::vector<Index> candidates_;        // this step's candidates (with a moving wall every rank's), ascending
  std::vector<Real> candidate_mass_;     // moving wall: each candidate's mass
  std::vector<Index> active_;            // positions in nodes_ of the nodes pushed this step
  std::vector<Index> free_;              // moving wall: unwelded candidates, by closing value
  std::vector<Vec3> impulse_;            // m dv of each active node
};

}  // namespace spall::contact
