#include "spall/contact/rigid_wall.hpp"

#include "spall/core/communicator.hpp"
#include "spall/core/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <span>
#include <stdexcept>

namespace spall::contact {

namespace {
// A few flops per node: below this many nodes a parallel loop costs more than it saves.
constexpr Index parallel_from = 1024;
}  // namespace

RigidWall::RigidWall(const Definition& definition, std::vector<Index> tracked, std::vector<std::uint8_t> front)
    : definition_(definition),
      nodes_(std::move(tracked)),
      state_(std::move(front)),
      velocity_(definition.mass > 0 ? definition.initial_velocity : 0),
      closing_(nodes_.size(), 0),
      candidate_(nodes_.size(), 0),
      candidate_mass_(nodes_.size(), 0) {
  if (state_.size() != nodes_.size()) throw std::invalid_argument("RigidWall: a front flag for every tracked node");
  for (std::uint8_t& s : state_) s = s ? std::uint8_t(in_front) : std::uint8_t(0);
}

bool RigidWall::inside(const Vec3& p) const {
  const auto& d = definition_;
  if (d.length_l > 0) {
    const Real a = p.dot(d.edge_l);
    if (a < 0 || a > d.length_l) return false;
  }
  if (d.length_m > 0) {
    const Real b = p.dot(d.edge_m);
    if (b < 0 || b > d.length_m) return false;
  }
  return true;
}

void RigidWall::complete_state() {
  if (mine_.empty()) return;
  struct Own {
    Index k;
    std::uint8_t state, padding[3];  // explicit: no unset byte travels
  };
  std::vector<Own> own;
  for (const Index k : passed_) own.push_back({k, state_[k], {0, 0, 0}});
  for (const Own& o : parallel::world().all(std::span<const Own>(own))) state_[o.k] = o.state;
}

void RigidWall::find_rows(const discretization::NodeStore& nodes, bool own_only) {
  if (rows_partition_ == nodes.partition && rows_layout_ == nodes.layout) return;
  const bool new_partition = rows_partition_ != nodes.partition;
  if (own_only && new_partition) complete_state();
  const Index count = static_cast<Index>(nodes_.size());
  row_.resize(count);
  for (Index k = 0; k < count; ++k) row_[k] = nodes.row_of(nodes_[k]);
  if (own_only) {
    mine_.resize(count);
    for (Index k = 0; k < count; ++k) mine_[k] = row_[k] >= 0 && nodes.owns(row_[k]);
  }
  passed_.clear();
  for (Index k = 0; k < count; ++k)
    if (!own_only || mine_[k]) passed_.push_back(k);
  rows_partition_ = nodes.partition;
  rows_layout_ = nodes.layout;
}

void RigidWall::enforce(discretization::NodeStore& nodes, Real t_mid, Real dt, Real dt_mid) {
  // Under MPI with velocities by reach the other ranks' nodes are stale here (or not held): a
  // rank's own alone, their state brought in from the ranks it was current on when the nodes were
  // dealt anew.
  const bool own_only = nodes.velocities_by_reach;
  find_rows(nodes, own_only);
  const auto skip = [&](Index k) { return own_only && !mine_[k]; };
  const Index passed = static_cast<Index>(passed_.size());
  force_.setZero();
  normal_force_ = 0;
  active_.clear();
  active_now_ = t_mid >= definition_.birth && t_mid <= definition_.death;
  const Vec3& n = definition_.normal;
  const Vec3 origin = definition_.origin + displacement_ * n;
  if (!active_now_) {
    // Not there yet (or any more): a node may pass the plane, and is then behind it at birth.
    parallel::for_each(passed, [&](Index j) {
      const Index k = passed_[j], i = row_[k];
      state_[k] = n.dot(nodes.x[i] + dt * nodes.v[i] - origin) >= 0 ? std::uint8_t(in_front)
                                                                    : std::uint8_t(0);
    }, {.serial_below = parallel_from});
    return;
  }
  parallel::for_each(passed, [&](Index j) {
    const Index k = passed_[j], i = row_[k];
    candidate_mass_[k] = nodes.mass[i];
    const Vec3 r = nodes.x[i] - origin;
    const Real d = n.dot(r);
    const Real u = n.dot(nodes.v[i]);
    // The distance at t^{n+1} is d + dt (u - V') = dt (c - V'). A step of zero length (the last
    // half kick) moves nothing: only a node on or behind the wall can be stopped then.
    closing_[k] = dt > 0 ? u + d / dt : (d > 0 ? std::numeric_limits<Real>::infinity() : u);
    candidate_[k] = (state_[k] & in_front) && inside(r + dt * nodes.v[i]);
  }, {.serial_below = parallel_from});
  candidates_.clear();
  for (const Index k : passed_)
    if (candidate_[k]) candidates_.push_back(k);
  if (own_only && definition_.mass > 0) share_candidates();
  const Real v_wall = solve_wall_velocity();

  const Friction& friction = definition_.friction;
  const Real v_before_impact = velocity_;
  impulse_.resize(active_.size());
  const Index pushed = static_cast<Index>(active_.size());
  parallel::for_each(pushed, [&](Index a) {
    const Index k = active_[a];
    if (skip(k)) {  // another rank's, which pushes it
      impulse_[a] = Vec3::Zero();
      return;
    }
    const Index i = row_[k];
    Vec3& v = nodes.v[i];
    const Vec3 v_before = v;
    // On the wall at t^{n+1}: u' = V' - d/dt = u + (V' - c).
    const Real du = v_wall - closing_[k];
    if (friction.weld && !(state_[k] & welded) && v_before_impact - n.dot(v) > friction.weld_speed)
      state_[k] |= welded;
    v += du * n;
    // The wall moves along n only, so the sliding velocity is the node's tangential velocity.
    const Vec3 slip = v - n.dot(v) * n;
    const Real speed = slip.norm();
    if (speed > 0) {
      if (friction.stick) {
        v -= slip;
      } else if (friction.coefficient > 0) {
        // Coulomb: the tangential impulse is at most mu times the normal one, m |du|.
        const Real limit = friction.coefficient * std::abs(du);
        v -= (speed <= limit ? Real(1) : limit / speed) * slip;
      }
    }
    impulse_[a] = nodes.mass[i] * (v - v_before);
  }, {.serial_below = parallel_from});

  // Summed exactly: the same for any thread count and, over the ranks, for any partition.
  const Sums<3> sums = parallel::exact_sum(
      pushed, [&](Index a) { return Sums<3>{{impulse_[a][0], impulse_[a][1], impulse_[a][2]}}; },
      own_only ? &parallel::world() : nullptr);
  const Vec3 total(sums[0], sums[1], sums[2]);
  if (dt_mid > 0) {
    force_ = (Vec3::Zero() - total) / dt_mid;  // 0 - 0 = +0: no "-0" in rwforc.csv
    normal_force_ = n.dot(total) / dt_mid;
  }
  if (definition_.mass > 0) velocity_ = v_wall;

  // Which side each node will be on at t^{n+1}: a pushed node is on the wall; a node that passes
  // the plane beside a finite wall, or was behind it, is behind until it comes back in front.
  if (dt > 0) {
    parallel::for_each(passed, [&](Index j) {
      const Index k = passed_[j];
      if (candidate_[k] != pushed_now) state_[k] = closing_[k] >= v_wall ? std::uint8_t(in_front) : std::uint8_t(0);
    }, {.serial_below = parallel_from});
  }
}

// A moving wall's velocity depends on every node it pushes: under MPI with velocities by reach the
// other ranks' candidates (closing value, mass, flags) come in, so that every rank solves for the
// same velocity and pushed set as one process (and applies the pushes to its own nodes): among the
// candidates in the order of the tracked nodes.
void RigidWall::share_candidates() {
  struct Candidate {
    Index k;
    std::uint8_t candidate, state, padding[2];  // explicit: no unset byte travels
    Real closing, mass;
  };
  std::vector<Candidate> own;
  for (const Index k : candidates_) own.push_back({k, candidate_[k], state_[k], {0, 0}, closing_[k], candidate_mass_[k]});
  for (const Candidate& c : parallel::world().all(std::span<const Candidate>(own)))
    if (!mine_[c.k]) {
      candidate_[c.k] = c.candidate, state_[c.k] = c.state, closing_[c.k] = c.closing, candidate_mass_[c.k] = c.mass;
      candidates_.push_back(c.k);
    }
  std::sort(candidates_.begin(), candidates_.end());
}

Real RigidWall::solve_wall_velocity() {
  auto push = [&](Index k) {
    candidate_[k] = pushed_now;
    active_.push_back(k);
  };
  if (definition_.mass <= 0) {
    // A fixed wall takes any impulse without moving: every node that would pass it is pushed.
    for (const Index k : candidates_)
      if ((state_[k] & welded) || closing_[k] < 0) push(k);
    return 0;
  }
  // A moving wall: momentum along n is conserved, M V + sum m u = M V' + sum m u', and every
  // pushed node leaves with u' = u + V' - c, so V' = (M V + sum m c) / (M + sum m) over the pushed
  // nodes. Welded nodes are always held; a free node is pushed iff c < V'. Taking free nodes in
  // ascending c, each one pushed lowers V' but keeps it above its own c, so the first that is
  // not below V' ends the set.
  Real momentum = definition_.mass * velocity_;
  Real mass = definition_.mass;
  for (const Index k : candidates_)
    if (state_[k] & welded) {
      const Real m = candidate_mass_[k];
      momentum += m * closing_[k];
      mass += m;
      push(k);
    }
  Real v_wall = momentum / mass;
  free_.clear();
  for (const Index k : candidates_)
    if (candidate_[k] == 1 && !(state_[k] & welded) && closing_[k] < v_wall) free_.push_back(k);
  std::sort(free_.begin(), free_.end(), [&](Index a, Index b) {
    return closing_[a] != closing_[b] ? closing_[a] < closing_[b] : a < b;
  });
  for (Index k : free_) {
    if (!(closing_[k] < v_wall)) break;
    const Real m = candidate_mass_[k];
    momentum += m * closing_[k];
    mass += m;
    v_wall = momentum / mass;
    push(k);
  }
  return v_wall;
}

void RigidWall::advance(Real dt) {
  if (definition_.mass > 0 && active_now_) displacement_ += dt * velocity_;
}

}  // namespace spall::contact
