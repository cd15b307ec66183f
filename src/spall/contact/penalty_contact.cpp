#include "spall/contact/penalty_contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <utility>

#include "spall/core/communicator.hpp"
#include "spall/core/exact_sum.hpp"
#include "spall/core/parallel.hpp"

namespace spall::contact {

namespace {
// A few dozen flops for a node with no segment in its cell: below this many a parallel loop
// costs more than it saves.
constexpr Index parallel_from = 4096;

using discretization::NodeStore;

std::array<Vec3, 4> corners_of(const Segment& segment, const NodeStore& nodes) {
  return {nodes.x[segment.node[0]], nodes.x[segment.node[1]], nodes.x[segment.node[2]], nodes.x[segment.node[3]]};
}
}  // namespace

Real PenaltyContact::Friction::coefficient(Real sliding_speed) const {
  if (!(decay > 0)) return static_coefficient;
  return dynamic_coefficient + (static_coefficient - dynamic_coefficient) * std::exp(-decay * sliding_speed);
}

PenaltyContact::PenaltyContact(const Definition& definition, std::vector<Pass> passes)
    : definition_(definition), stiffness_step_(definition.stiffness_step) {
  for (auto& pass : passes) {
    PassState state;
    state.reach.resize(pass.segment.size());
    state.grow.resize(pass.segment.size());
    for (std::size_t s = 0; s < pass.segment.size(); ++s) {
      state.reach[s] = definition_.release_depth * pass.segment[s].thickness;
      state.grow[s] = state.reach[s] + pass.segment[s].offset;
    }
    state.status.resize(pass.segment.size(), live);
    for (std::size_t s = 0; s < pass.elements.size(); ++s)
      if (pass.elements[s].beyond != 0) state.status[s] = waiting;
    state.found.assign(pass.slave.size(), -1);
    state.pass = std::move(pass);
    passes_.push_back(std::move(state));
  }
}

void PenaltyContact::erode(std::span<const Id> elements) {
  const auto eroded = [&](Id id) { return id != 0 && std::binary_search(elements.begin(), elements.end(), id); };
  for (auto& state : passes_) {
    const std::vector<FaceElements>& of = state.pass.elements;
    for (std::size_t s = 0; s < of.size(); ++s) {
      std::uint8_t& status = state.status[s];
      if (status == gone) continue;
      if (eroded(of[s].own))
        status = gone;
      else if (status == waiting && eroded(of[s].beyond))
        status = live;
    }
  }
}

Index PenaltyContact::touching() const {
  Index n = 0;
  for (const auto& state : passes_) n += static_cast<Index>(state.touches.size());
  return n;
}

void PenaltyContact::apply(NodeStore& nodes, Real t, Real dt) {
  side_[0] = side_[1] = Resultant{};
  // Nodes dealt anew: a slave's last touch (its friction) may be another rank's.
  const bool dealt_anew = std::exchange(partition_, nodes.partition) != nodes.partition;
  if (t < definition_.birth || t > definition_.death) {
    for (auto& state : passes_) {
      state.touches.clear();  // friction history ends with the contact
      state.started = false;
    }
    return;
  }
  std::array<ExactSum, 12> sums;  // side A's force and moment, then side B's, over the passes
  for (auto& state : passes_) {
    if (dealt_anew) complete_touches(state);
    search(state, nodes);
    respond(state, nodes, dt);
    gather(state, nodes, sums);
    state.started = true;
  }
  parallel::world().sum(sums);
  for (int s = 0; s < 2; ++s) {
    side_[s].force = Vec3(sums[6 * s].value(), sums[6 * s + 1].value(), sums[6 * s + 2].value());
    side_[s].moment = Vec3(sums[6 * s + 3].value(), sums[6 * s + 4].value(), sums[6 * s + 5].value());
  }
}

// Each slave node's segment: of the live segments in its cell (not one it is a corner of, nor one
// of its own rigid body's, nor one with an eroded corner), the one with the closest point; a touch
// when the node is behind its contact surface (Segment::contact_at), less deep than the segment's
// reach, and not beside it (MAXPAR). Under MPI, of this rank's own slave nodes.
void PenaltyContact::search(PassState& state, const NodeStore& nodes) const {
  const Pass& pass = state.pass;
  const Definition& d = definition_;
  state.grid.build(pass.segment, state.grow, nodes.x);
  parallel::for_each(static_cast<Index>(pass.slave.size()), [&](Index k) {
    const Index i = pass.slave[k];
    state.found[k] = -1;
    if (!nodes.owns(i) || !nodes.active[i] || !(nodes.mass[i] > 0)) return;
    const Vec3& x = nodes.x[i];
    Real best = std::numeric_limits<Real>::infinity(), gap = 0, beyond = 0;
    std::int32_t chosen = -1;
    for (Index s : state.grid.candidates(x)) {
      if (state.status[s] != live || !state.grid.within_reach(s, x)) continue;
      const Segment& segment = pass.segment[s];
      bool skip = false;
      for (Index corner : segment.node)
        skip |= corner == i || !nodes.active[corner] ||
                (nodes.body[i] != NodeStore::no_body && nodes.body[corner] == nodes.body[i]);
      if (skip) continue;
      const SegmentPoint p = closest_on_segment(x, corners_of(segment, nodes), segment.triangle());
      if (p.distance_squared < best) {
        best = p.distance_squared;
        chosen = static_cast<std::int32_t>(s);
        gap = p.normal.dot(x - p.point);
        beyond = (x - p.point - gap * p.normal).squaredNorm();  // from the segment, in its plane
      }
    }
    // Behind the contact surface, not deeper than its reach, and its projection on the segment's
    // plane not beyond an edge by more than MAXPAR - 1 of the segment's size (sqrt of its area).
    if (chosen < 0) return;
    const Segment& segment = pass.segment[chosen];
    const Real depth = segment.contact_at(gap).penetration;
    if (depth > 0 && depth <= state.reach[chosen] && beyond <= d.edge_tolerance * d.edge_tolerance * segment.area)
      state.found[k] = chosen;
  }, {.serial_below = parallel_from});

  // The touches in slave order, each keeping the friction force it had on the last step.
  state.previous.swap(state.touches);
  state.touches.clear();
  std::size_t before = 0;
  for (Index k = 0; k < static_cast<Index>(pass.slave.size()); ++k) {
    if (state.found[k] < 0) continue;
    Touch touch;
    touch.slave = k;
    touch.segment = state.found[k];
    while (before < state.previous.size() && state.previous[before].slave < k) ++before;
    if (before < state.previous.size() && state.previous[before].slave == k) {
      touch.friction = state.previous[before].friction;
      touch.tracked_depth = state.previous[before].tracked_depth;
    }
    state.touches.push_back(touch);
  }
}

// The penalty force of each touch (docs/THEORY.md §12.2-12.3).
void PenaltyContact::respond(PassState& state, const NodeStore& nodes, Real dt) const {
  const Pass& pass = state.pass;
  const Definition& d = definition_;
  parallel::for_each(static_cast<Index>(state.touches.size()), [&](Index a) {
    Touch& touch = state.touches[a];
    const Index i = pass.slave[touch.slave];
    const Segment& segment = pass.segment[touch.segment];
    const SegmentPoint p = closest_on_segment(nodes.x[i], corners_of(segment, nodes), segment.triangle());
    touch.weight = p.weight;
    touch.slave_position = nodes.x[i];
    const Segment::Contact side = segment.contact_at(p.normal.dot(nodes.x[i] - p.point));
    const Vec3& n = touch.normal = side.sign * p.normal;
    Real penetration = side.penetration;

    Vec3 v_rel = nodes.v[i];
    Real master_mass = 0;
    bool rigid_master = false;
    for (int c = 0; c < segment.corners(); ++c) {
      const Index J = segment.node[c];
      v_rel -= p.weight[c] * nodes.v[J];
      master_mass += nodes.mass[J] / segment.corners();
      rigid_master |= nodes.body[J] != NodeStore::no_body;
    }
    // m* of the soft constraint and the mass the damping sees: a rigid segment does not move
    // under one node.
    const Real slave_mass = nodes.mass[i];
    const Real stiff_mass = rigid_master ? slave_mass : std::min(slave_mass, master_mass);
    const Real damped_mass = rigid_master ? slave_mass : slave_mass * master_mass / (slave_mass + master_mass);

    Real k = d.penopt == 2   ? segment.stiffness
             : d.penopt == 3 ? pass.slave_stiffness[touch.slave]
                             : std::min(segment.stiffness, pass.slave_stiffness[touch.slave]);
    if (d.soft == 1 && stiffness_step_ > 0)
      k = std::max(k, Real(0.5) * d.soft_scale * stiff_mass / (stiffness_step_ * stiffness_step_));

    const Real v_n = n.dot(v_rel);  // > 0: separating
    // A node found deeper than its approach over the last step could have taken it (let go below
    // the release depth, then caught again as the tool moved on) is not shot out at k times that
    // depth (at SOFT 1 that leaves it at about depth sqrt(k / m), hundreds of m/s inside a drill):
    // the depth it was found at is tracked, shrinks as it comes out, and only the depth beyond
    // it pushes. Nodes touching on the contact's first step (initial interference) are pushed out.
    if (touch.tracked_depth < 0)
      touch.tracked_depth = state.started && penetration > 2 * std::max(-v_n, Real(0)) * dt ? penetration : 0;
    touch.tracked_depth = std::min(touch.tracked_depth, penetration);
    penetration -= touch.tracked_depth;
    const Real damping = d.damping * 2 * std::sqrt(k * damped_mass);
    touch.normal_force = std::max(Real(0), k * penetration - damping * v_n);

    // Friction: the last force turned into the new tangent plane, the elastic trial of the slip
    // over the last step, then the Coulomb limit (and the viscous cap VC A).
    const Vec3 v_t = v_rel - v_n * n;
    Vec3 previous = touch.friction - n.dot(touch.friction) * n;
    const Real kept = previous.norm();
    if (kept > 0) previous *= touch.friction.norm() / kept;
    Vec3 trial = previous - k * dt * v_t;
    Real limit = d.friction.coefficient(v_t.norm()) * touch.normal_force;
    if (d.friction.viscous_limit > 0) limit = std::min(limit, d.friction.viscous_limit * segment.area);
    const Real size = trial.norm();
    if (size > limit) trial *= size > 0 ? limit / size : Real(0);
    touch.friction = trial;
  }, {.serial_below = 256});
}

// Under MPI each rank searches and answers its own slave nodes and keeps their touches; every
// rank's come in where a slave's last touch may be another rank's (a new deal) and before a
// checkpoint, in slave order, as one process has them.
void PenaltyContact::complete_touches(PassState& state) const {
  const parallel::Communicator& ranks = parallel::world();
  if (ranks.size() == 1) return;
  std::vector<Touch> all = ranks.all(std::span<const Touch>(state.touches));
  std::sort(all.begin(), all.end(), [](const Touch& a, const Touch& b) { return a.slave < b.slave; });
  state.touches = std::move(all);
}

void PenaltyContact::complete_state() {
  for (auto& state : passes_) complete_touches(state);
}

// Adds the forces to the nodes: the slave takes F, the corners -w_J F. Each node takes its terms
// in slave order (the slave's, then each corner's), as one process adds them: under MPI a rank's
// touches' terms on another rank's node go to that rank, which adds every term on its own nodes
// (whose forces are then whole there; a body takes its nodes' from their ranks). The resultants
// and their moments are exact sums over the touches and the ranks: the same for any partition.
void PenaltyContact::gather(const PassState& state, NodeStore& nodes, std::array<ExactSum, 12>& sums) {
  const parallel::Communicator& ranks = parallel::world();
  const Pass& pass = state.pass;
  struct Term {  // a force on a node, its place in the order: the touch's slave, then 0 or 1 + corner
    Index slave;
    std::int32_t order;
    Index node;
    double force[3];
  };
  // On one process the touches come in slave order, and so do the terms: each is added at once.
  const bool alone = ranks.size() == 1;
  std::vector<std::vector<Term>> terms(alone ? 0 : ranks.size());
  const int slave_side = pass.slaves_are_side_a ? 0 : 6, segment_side = 6 - slave_side;
  const auto add = [&](const Touch& touch, std::int32_t order, Index node, const Vec3& force, const Vec3& at) {
    if (alone)
      nodes.f[node] += force;
    else
      terms[nodes.rank_of(node)].push_back({touch.slave, order, node, {force.x(), force.y(), force.z()}});
    const Vec3 moment = at.cross(force);
    const int side = order > 0 ? segment_side : slave_side;
    for (int d = 0; d < 3; ++d) sums[side + d] += force[d], sums[side + 3 + d] += moment[d];
  };
  for (const Touch& touch : state.touches) {
    const Vec3 force = touch.normal_force * touch.normal + touch.friction;
    add(touch, 0, pass.slave[touch.slave], force, touch.slave_position);
    const Segment& segment = pass.segment[touch.segment];
    for (int c = 0; c < segment.corners(); ++c)
      add(touch, 1 + c, segment.node[c], -touch.weight[c] * force, nodes.x[segment.node[c]]);
  }
  if (alone) return;
  std::vector<Term> mine = ranks.deliver(terms);
  std::sort(mine.begin(), mine.end(),
            [](const Term& a, const Term& b) { return a.slave < b.slave || (a.slave == b.slave && a.order < b.order); });
  for (const Term& term : mine) nodes.f[term.node] += Vec3(term.force[0], term.force[1], term.force[2]);
}

void PenaltyContact::book_energies(discretization::EnergyLedger& ledger, const NodeStore& nodes,
                                   std::span<const Vec3> v, Real dt) const {
  using Role = discretization::EnergyLedger::Role;
  std::array<ExactSum, 2> power;  // normal, friction
  for (const auto& state : passes_)
    for (const Touch& touch : state.touches) {
      const Index i = state.pass.slave[touch.slave];
      if (!nodes.owns(i)) continue;  // its rank's (every rank's are here after complete_state)
      const Segment& segment = state.pass.segment[touch.segment];
      Vec3 v_rel = v[i];
      for (int c = 0; c < segment.corners(); ++c) v_rel -= touch.weight[c] * v[segment.node[c]];
      power[0] += touch.normal_force * touch.normal.dot(v_rel);
      power[1] += touch.friction.dot(v_rel);
    }
  parallel::world().sum(power);
  // The energy the contact takes is minus the work its forces do on the nodes.
  ledger.add(contact_energy, Role::stored, -dt * power[0].value());
  ledger.add(friction_energy, Role::dissipated, -dt * power[1].value());
}

bool PenaltyContact::segments_rigid(const NodeStore& nodes) const {
  for (const Index node : definition_.moment_node)
    if (node >= 0 && nodes.body[node] == NodeStore::no_body) return false;
  for (const auto& state : passes_)
    for (const Segment& segment : state.pass.segment)
      for (int c = 0; c < segment.corners(); ++c)
        if (nodes.body[segment.node[c]] == NodeStore::no_body) return false;
  return true;
}

}  // namespace spall::contact
