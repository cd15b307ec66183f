#include "spall/rigid/rigid_bodies.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "spall/core/communicator.hpp"

namespace spall::rigid {

namespace {

Mat3 cross_matrix(const Vec3& a) {
  Mat3 m;
  m << 0, -a.z(), a.y(), a.z(), 0, -a.x(), -a.y(), a.x(), 0;
  return m;
}

// The nearest rotation to R, by Gram-Schmidt on its columns: a product of a million exact
// rotations drifts from orthogonality by a million roundings; this keeps it at one.
Mat3 orthonormalized(const Mat3& R) {
  Vec3 a = R.col(0).normalized();
  Vec3 b = (R.col(1) - a.dot(R.col(1)) * a).normalized();
  Mat3 out;
  out.col(0) = a;
  out.col(1) = b;
  out.col(2) = a.cross(b);
  return out;
}

// The value a prescribed motion gives its degree of freedom over the step, or false when it is
// not active (outside BIRTH-DEATH). `current` is the velocity after the free update (VAD 1 adds
// to it) and `position` the displacement or angle reached (VAD 2 aims from it).
bool prescribed(const PrescribedMotion& m, Real time, Real dt, Real dt_mid, Real current, Real position,
                Real& value) {
  const Real t_mid = time + Real(0.5) * dt;
  if (t_mid < m.birth || t_mid > m.death) return false;
  switch (m.vad) {
    case 0: value = m.sf * m.curve->value(t_mid); break;
    case 1: value = current + dt_mid * m.sf * m.curve->value(time); break;
    default: value = dt > 0 ? (m.sf * m.curve->value(time + dt) - position) / dt : 0; break;
  }
  return true;
}

// `value` with its components along the held columns of `axes` set to 0.
Vec3 held(const Vec3& value, const std::array<bool, 3>& fixed, const Mat3& axes) {
  if (!(fixed[0] || fixed[1] || fixed[2])) return value;
  Vec3 local = axes.transpose() * value;
  for (int d = 0; d < 3; ++d)
    if (fixed[d]) local[d] = 0;
  return axes * local;
}

}  // namespace

Mat3 rotation_of(const Vec3& phi) {
  const Real angle = phi.norm();
  const Mat3 K = cross_matrix(phi);
  if (angle < 1e-8) return Mat3::Identity() + K + Real(0.5) * K * K;  // to O(angle^3)
  return Mat3::Identity() + (std::sin(angle) / angle) * K + ((1 - std::cos(angle)) / (angle * angle)) * K * K;
}

void RigidBodies::add(RigidBody body, discretization::NodeStore& nodes, const MassProperties* given) {
  body.mass = 0;
  Vec3 moment = Vec3::Zero(), momentum = Vec3::Zero();
  for (Index i : body.node) {
    body.mass += nodes.mass[i];
    moment += nodes.mass[i] * nodes.x[i];
    momentum += nodes.mass[i] * nodes.v[i];
  }
  body.centre = moment / body.mass;
  body.velocity = momentum / body.mass;
  body.inertia.setZero();
  body.angular_momentum.setZero();
  body.offset.clear();
  for (Index i : body.node) {
    const Vec3 r = nodes.x[i] - body.centre;
    body.offset.push_back(r);
    body.inertia += nodes.mass[i] * (r.squaredNorm() * Mat3::Identity() - r * r.transpose());
    body.angular_momentum += nodes.mass[i] * r.cross(nodes.v[i] - body.velocity);
    nodes.body[i] = static_cast<std::int32_t>(bodies_.size());
  }
  body.rotation.setIdentity();
  body.angular_velocity = body.inertia.inverse() * body.angular_momentum;
  if (given) {
    // The nodes now carry the given mass and centre (to round-off); the inertia is the given one.
    body.mass = given->mass;
    body.centre = given->centre;
    for (std::size_t k = 0; k < body.node.size(); ++k) body.offset[k] = nodes.x[body.node[k]] - body.centre;
    body.inertia = given->inertia;
    body.angular_momentum = body.inertia * body.angular_velocity;
  }
  body.initial_centre = body.step_centre = body.centre;
  body.last_velocity = body.velocity;
  body.last_angular_momentum = body.angular_momentum;
  body.last_angular_velocity = body.angular_velocity;
  node_rows_.insert(node_rows_.end(), body.node.begin(), body.node.end());
  std::sort(node_rows_.begin(), node_rows_.end());
  node_rows_.erase(std::unique(node_rows_.begin(), node_rows_.end()), node_rows_.end());
  bodies_.push_back(std::move(body));
}

void RigidBodies::share_forces(discretization::NodeStore& nodes) const {
  const parallel::Communicator& ranks = parallel::world();
  if (ranks.size() == 1 || node_rows_.empty()) return;
  if (nodes.by_region()) throw std::logic_error("rigid bodies: the nodes are dealt by region, not in blocks");
  // In blocks a rank's own body nodes are one stretch of the ascending rows, and every rank's, in
  // rank order, are all of them.
  const auto first = std::lower_bound(node_rows_.begin(), node_rows_.end(), nodes.owned_begin);
  const auto last = std::lower_bound(first, node_rows_.end(), nodes.owned_end);
  std::vector<Vec3> own;
  for (auto row = first; row != last; ++row) own.push_back(nodes.f[*row]);
  const std::vector<Vec3> every = ranks.all(std::span<const Vec3>(own));
  for (std::size_t k = 0; k < node_rows_.size(); ++k) nodes.f[node_rows_[k]] = every[k];
}

RigidBodies::Energies RigidBodies::energies(Real weight, Real reaction_weight, Real dt_mid) const {
  Energies e;
  for (const RigidBody& b : bodies_) {
    e.kinetic += b.kinetic_energy_at(weight);
    if (dt_mid > 0) {
      const Vec3 dv = b.velocity - b.last_velocity, dL = b.angular_momentum - b.last_angular_momentum;
      const Vec3 dw = b.angular_velocity - b.last_angular_velocity;
      const Vec3 reaction = b.mass * dv / dt_mid - b.force, reaction_moment = dL / dt_mid - b.moment;
      e.reaction_power += reaction.dot(b.last_velocity + reaction_weight * dv) +
                          reaction_moment.dot(b.last_angular_velocity + reaction_weight * dw);
    }
  }
  return e;
}

void RigidBodies::add_cell(discretization::CellShape shape, Id element_id, std::span<const Index> corners) {
  auto block = std::find_if(cells_.begin(), cells_.end(), [&](const auto& b) { return b.shape == shape; });
  if (block == cells_.end()) {
    block = cells_.insert(cells_.end(), discretization::CellBlock{shape, {}, {}});
    block->fields.push_back({"element_id", 1, std::vector<std::int64_t>{}});
  }
  block->connectivity.insert(block->connectivity.end(), corners.begin(), corners.end());
  std::get<std::vector<std::int64_t>>(block->fields.front().values).push_back(element_id);
}

void RigidBodies::write_fields(discretization::FieldSet& fields) const {
  for (const auto& block : cells_) fields.add_cell_block(block.shape) = block;
}

void RigidBodies::advance(discretization::NodeStore& nodes, Real time, Real dt, Real dt_mid) {
  for (RigidBody& b : bodies_) {
    // The nodes' forces at x^n (internal forces of deformable elements on shared nodes, contact,
    // loads) and their moment about the centre.
    Vec3 F = Vec3::Zero(), M = Vec3::Zero();
    for (Index i : b.node) {
      F += nodes.f[i];
      M += (nodes.x[i] - b.centre).cross(nodes.f[i]);
    }
    b.force = F, b.moment = M, b.step_centre = b.centre;
    b.last_velocity = b.velocity, b.last_angular_momentum = b.angular_momentum;
    b.last_angular_velocity = b.angular_velocity;
    b.velocity += (dt_mid / b.mass) * F;
    b.angular_momentum += dt_mid * M;  // L is conserved exactly when no moment acts

    // Translations: prescribed, or held (CMO 1, CON1), else free.
    for (const PrescribedMotion& m : b.motions)
      if (!m.rotation) {
        Real v;
        if (prescribed(m, time, dt, dt_mid, m.along(b.velocity), m.along(b.centre - b.initial_centre), v))
          m.set_along(b.velocity, v);
      }
    b.velocity = held(b.velocity, b.fixed_translation, b.constraint_axes);

    // Rotation: omega^{n+1/2} = J^{n+1/2, -1} L with J at the middle of the step, found by fixed
    // point from the last omega (the implicit midpoint rule for Euler's equations: L exactly
    // conserved, the energy to O(dt^2) without drift); then the components that are prescribed
    // or held, and L made to match them.
    std::array<std::pair<const PrescribedMotion*, Real>, 8> imposed;
    std::size_t imposed_count = 0;
    for (const PrescribedMotion& m : b.motions) {
      Real w;
      if (m.rotation && imposed_count < imposed.size() &&
          prescribed(m, time, dt, dt_mid, m.along(b.angular_velocity), m.along(b.angle), w))
        imposed[imposed_count++] = {&m, w};
    }
    const bool rotation_held = b.fixed_rotation[0] || b.fixed_rotation[1] || b.fixed_rotation[2];
    Vec3 omega = b.angular_velocity;
    Mat3 J_half;
    for (int iteration = 0; iteration < 4; ++iteration) {
      J_half = b.world_inertia(rotation_of(Real(0.5) * dt * omega) * b.rotation);
      omega = J_half.ldlt().solve(b.angular_momentum);
      for (std::size_t k = 0; k < imposed_count; ++k) imposed[k].first->set_along(omega, imposed[k].second);
      omega = held(omega, b.fixed_rotation, b.constraint_axes);
    }
    if (imposed_count > 0 || rotation_held) b.angular_momentum = J_half * omega;
    b.angular_velocity = omega;
    b.angle += dt * omega;

    // x_c^{n+1}, R^{n+1}, and the nodes' velocities that carry them there.
    b.centre += dt * b.velocity;
    b.rotation = orthonormalized(rotation_of(dt * omega) * b.rotation);
    for (std::size_t k = 0; k < b.node.size(); ++k) {
      const Index i = b.node[k];
      const Vec3 target = b.centre + b.rotation * b.offset[k];
      nodes.v[i] = dt > 0 ? Vec3((target - nodes.x[i]) / dt)
                          : Vec3(b.velocity + omega.cross(nodes.x[i] - b.centre));
    }
  }
}

}  // namespace spall::rigid
