#include "spall/sph/fluid.hpp"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "spall/kernels/cubic_spline.hpp"

namespace spall::sph {

namespace {

// All three translations held: a dynamic boundary (wall) particle.
constexpr std::uint8_t all_translations = 7;

// Morris et al. 1997 and Monaghan 1992 both regularise 1 / r^2 with 0.01 h^2.
constexpr Real eta_squared_morris = 0.01;

// Time-step factors. Courant: the predictor-corrector density update is stable for w dt < 0.72
// and the fastest SPH acoustic mode has w ~ 1.04 c / h (cubic spline), so h / (c + |v|) is
// scaled by 0.4 (w dt ~ 0.42). Force: Monaghan 1992, dt <= 0.25 sqrt(h / |a|). Viscous: Morris
// et al. 1997, dt <= 0.125 h^2 / nu.
constexpr Real courant_factor = 0.4;
constexpr Real force_factor = 0.25;
constexpr Real viscous_factor = 0.125;

template <typename T>
void permute(std::vector<T>& values, std::span<const Index> order) {
  std::vector<T> sorted(values.size());
  for (std::size_t k = 0; k < order.size(); ++k) sorted[k] = values[order[k]];
  values.swap(sorted);
}

template <typename T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

Real FluidMaterial::pressure(Real rho) const {
  return std::max(bulk_modulus() * (std::pow(rho / density, gamma) - 1), pressure_cutoff);
}

Real FluidMaterial::sound_speed_at(Real rho) const {
  return sound_speed * std::pow(rho / density, (gamma - 1) / 2);
}

FluidFormulation::FluidFormulation(const FluidParameters& parameters,
                                   const std::vector<Index>& particle_nodes,
                                   const solver::NodeStore& nodes)
    : parameters_(parameters), support_(2 * parameters.smoothing_length) {
  const auto& m = parameters_.material;
  if (!(m.density > 0) || !(m.sound_speed > 0) || !(m.gamma > 0) || !(m.dynamic_viscosity >= 0))
    throw std::invalid_argument("SPH fluid: needs rho0 > 0, c0 > 0, gamma > 0 and mu >= 0");
  if (!(parameters_.smoothing_length > 0))
    throw std::invalid_argument("SPH fluid: the smoothing length must be > 0");
  if (parameters_.dimension != 2 && parameters_.dimension != 3)
    throw std::invalid_argument("SPH fluid: the dimension must be 2 or 3");
  if (parameters_.dimension == 2)
    for (Index i : particle_nodes)
      if (nodes.x[i].y() != nodes.x[particle_nodes.front()].y())
        throw std::invalid_argument("SPH fluid: in 2D every particle must lie in one plane y = const");
  const std::size_t n = particle_nodes.size();
  node_ = particle_nodes;
  mass_.resize(n);
  for (std::size_t a = 0; a < n; ++a) mass_[a] = static_cast<float>(nodes.mass[node_[a]]);
  density_.assign(n, m.density);
  rate_.assign(n, 0);
  previous_rate_.assign(n, 0);
  for (auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_, &predicted_density_, &pressure_term_})
    v->assign(n, 0);
  pressure_force_.assign(3 * n, 0);
  viscous_force_.assign(3 * n, 0);
  max_sound_speed_ = m.sound_speed;
}

void FluidFormulation::set_density_at_node(Index node, Real rho) {
  const auto it = std::find(node_.begin(), node_.end(), node);
  if (it == node_.end()) throw std::invalid_argument("SPH fluid: the node carries no fluid particle");
  density_[it - node_.begin()] = rho;
}

// Bins the particles into cells of edge support + skin and puts every per-particle array in cell
// order, so that the particles of a cell are contiguous.
void FluidFormulation::rebuild_cells(const solver::NodeStore& nodes) {
  const Index n = particle_count();
  std::vector<Vec3> x(n);
#pragma omp parallel for schedule(static)
  for (Index a = 0; a < n; ++a) x[a] = nodes.x[node_[a]];
  cells_.build(x, (1 + parameters_.skin) * support_);
  const std::span<const Index> order = cells_.order();
  permute(node_, order);
  permute(mass_, order);
  permute(density_, order);
  permute(rate_, order);
  permute(previous_rate_, order);
  // Moving particles before each slot, to tell in O(1) whether a slot range holds one.
  std::vector<Index> moving_before(n + 1, 0);
  for (Index a = 0; a < n; ++a)
    moving_before[a + 1] = moving_before[a] + (nodes.fixed[node_[a]] != all_translations);
  const Index cell_count = cells_.cell_count();
  active_cell_.assign(cell_count, 0);
#pragma omp parallel for schedule(static)
  for (Index c = 0; c < cell_count; ++c) {
    std::array<neighbors::ParticleRange, 9> ranges;
    const int range_count = cells_.neighborhood(c, ranges);
    for (int r = 0; r < range_count; ++r)
      if (moving_before[ranges[r].end] > moving_before[ranges[r].begin]) active_cell_[c] = 1;
  }
  Vec3 lower = n > 0 ? x[0] : Vec3::Zero();
  for (const Vec3& p : x) lower = lower.cwiseMin(p);
  origin_ = lower;
  cells_built_ = true;
  travelled_ = 0;
}

// Copies positions and velocities in cell order, predicts the densities and evaluates the
// equation of state once per particle.
void FluidFormulation::gather(const solver::NodeStore& nodes, Real dt) {
  const Index n = particle_count();
  const auto& m = parameters_.material;
  Real max_speed = 0, max_density = m.density;
#pragma omp parallel for schedule(static) reduction(max : max_speed, max_density)
  for (Index a = 0; a < n; ++a) {
    const Index i = node_[a];
    const Vec3 p = nodes.x[i] - origin_;
    const Vec3& v = nodes.v[i];
    x_[a] = static_cast<float>(p.x());
    y_[a] = static_cast<float>(p.y());
    z_[a] = static_cast<float>(p.z());
    vx_[a] = static_cast<float>(v.x());
    vy_[a] = static_cast<float>(v.y());
    vz_[a] = static_cast<float>(v.z());
    max_speed = std::max(max_speed, v.norm());
    // rho~^n = rho^{n-1} + dt (2 rho'^{n-1} - rho'^{n-2})
    Real rho = density_[a] + dt * (2 * Real(rate_[a]) - Real(previous_rate_[a]));
    if (nodes.fixed[i] == all_translations) rho = std::max(rho, m.density);
    predicted_density_[a] = static_cast<float>(rho);
    pressure_term_[a] = static_cast<float>(m.pressure(rho) / (rho * rho));
    max_density = std::max(max_density, rho);
  }
  max_speed_ = max_speed;
  max_sound_speed_ = m.sound_speed_at(max_density);
}

template <typename Visit>
void FluidFormulation::for_each_cell_neighbourhood(bool skip_inactive, Visit&& visit) const {
  const Index cell_count = cells_.cell_count();
#pragma omp for schedule(dynamic, 4)
  for (Index c = 0; c < cell_count; ++c) {
    std::array<neighbors::ParticleRange, 9> ranges;
    const int range_count = !skip_inactive || active_cell_[c] ? cells_.neighborhood(c, ranges) : 0;
    visit(cells_.cell(c), ranges, range_count);
  }
}

void FluidFormulation::pair_pass(solver::NodeStore& nodes, Real dt) {
  const auto& m = parameters_.material;
  const auto& av = parameters_.viscosity;
  const Real H = support_;
  const Real h = parameters_.smoothing_length;
  const float H2 = static_cast<float>(H * H);
  const Real inverse_H = 1 / H;
  // grad_a W_ab = F(r) x_ab with F = (dW/dr) / r = k (18 q - 12) for q <= 1/2 and
  // -6 k (1 - q)^2 / q beyond, k = sigma / H^(d+2) (seed 000 eq. 3 differentiated).
  const Real k = parameters_.dimension == 2
                     ? kernels::CubicSpline<2>::normalisation() / (H * H * H * H)
                     : kernels::CubicSpline<3>::normalisation() / (H * H * H * H * H);
  const Real eps2 = eta_squared_morris * h * h;
  const Real eta2 = av.eta * av.eta * h * h;
  const Real alpha_c = av.alpha * m.sound_speed;
  const Real beta = av.beta;
  const Real two_mu = 2 * m.dynamic_viscosity;
  Real max_acceleration = 0;

#pragma omp parallel reduction(max : max_acceleration)
  {
    std::vector<Index> found;
    for_each_cell_neighbourhood(true, [&](neighbors::ParticleRange own,
                                          const std::array<neighbors::ParticleRange, 9>& ranges,
                                          int range_count) {
      Index candidates = 0;
      for (int r = 0; r < range_count; ++r) candidates += ranges[r].end - ranges[r].begin;
      if (found.size() < static_cast<std::size_t>(candidates)) found.resize(candidates);
      for (Index a = own.begin; a < own.end; ++a) {
        // Screening in single precision, branch-free: about one candidate in six is inside.
        const float xa = x_[a], ya = y_[a], za = z_[a];
        Index count = 0;
        for (int r = 0; r < range_count; ++r) {
          for (Index b = ranges[r].begin; b < ranges[r].end; ++b) {
            const float dx = xa - x_[b], dy = ya - y_[b], dz = za - z_[b];
            found[count] = b;
            count += (dx * dx + dy * dy + dz * dz < H2) & (b != a);
          }
        }
        const Index node = node_[a];
        const bool wall = nodes.fixed[node] == all_translations;
        const Real rho_a = predicted_density_[a], P_a = pressure_term_[a], m_a = mass_[a];
        const Real vxa = vx_[a], vya = vy_[a], vza = vz_[a];
        Real rate = 0;
        Real fpx = 0, fpy = 0, fpz = 0, fvx = 0, fvy = 0, fvz = 0;
        for (Index s = 0; s < count; ++s) {
          const Index b = found[s];
          // Differences of single-precision values are exact in double: x_ab = -x_ba bitwise.
          const Real dx = Real(xa) - Real(x_[b]), dy = Real(ya) - Real(y_[b]),
                     dz = Real(za) - Real(z_[b]);
          const Real r2 = dx * dx + dy * dy + dz * dz;
          const Real r = std::sqrt(r2);
          const Real q = r * inverse_H;
          const Real F = q <= Real(0.5) ? k * (18 * q - 12) : -6 * k * (1 - q) * (1 - q) / q;
          const Real dvx = vxa - Real(vx_[b]), dvy = vya - Real(vy_[b]), dvz = vza - Real(vz_[b]);
          const Real vr = dvx * dx + dvy * dy + dvz * dz;
          const Real m_b = mass_[b];
          rate += m_b * F * vr;
          if (wall) continue;
          const Real rho_b = predicted_density_[b];
          const Real mm = m_a * m_b;
          const Real radial = -mm * (P_a + Real(pressure_term_[b])) * F;
          fpx += radial * dx;
          fpy += radial * dy;
          fpz += radial * dz;
          Real viscous_radial = 0;
          if (vr < 0) {
            const Real mu = h * vr / (r2 + eta2);
            const Real Pi = (-alpha_c * mu + beta * mu * mu) / (Real(0.5) * (rho_a + rho_b));
            viscous_radial = -mm * Pi * F;
          }
          const Real laminar = mm * two_mu / (rho_a * rho_b) * F * r2 / (r2 + eps2);
          fvx += viscous_radial * dx + laminar * dvx;
          fvy += viscous_radial * dy + laminar * dvy;
          fvz += viscous_radial * dz + laminar * dvz;
        }
        const Vec3 fp(fpx, fpy, fpz), fv(fvx, fvy, fvz);
        nodes.f[node] += fp + fv;
        for (int d = 0; d < 3; ++d) {
          pressure_force_[3 * a + d] = static_cast<float>(fp[d]);
          viscous_force_[3 * a + d] = static_cast<float>(fv[d]);
        }
        if (!wall) max_acceleration = std::max(max_acceleration, (fp + fv).norm() / m_a);
        // rho^n = rho^{n-1} + dt rho'^n; walls never go below rho0.
        Real rho = density_[a] + dt * rate;
        if (wall) rho = std::max(rho, m.density);
        density_[a] = rho;
        previous_rate_[a] = first_pass_ ? static_cast<float>(rate) : rate_[a];
        rate_[a] = static_cast<float>(rate);
      }
    });
  }
  max_acceleration_ = max_acceleration;
  first_pass_ = false;
}

void FluidFormulation::compute_forces(solver::NodeStore& nodes, Real dt) {
  // Every particle moved by dt v^{n-1/2} since the last call.
  Real max_speed = 0;
  const Index n = particle_count();
#pragma omp parallel for schedule(static) reduction(max : max_speed)
  for (Index a = 0; a < n; ++a) max_speed = std::max(max_speed, nodes.v[node_[a]].norm());
  travelled_ += dt * max_speed;
  // Two particles approach each other by at most twice the bound.
  if (!cells_built_ || 2 * travelled_ > parameters_.skin * support_) rebuild_cells(nodes);
  gather(nodes, dt);
  pair_pass(nodes, dt);
}

Real FluidFormulation::stable_time_step(const solver::NodeStore&) const {
  const Real h = parameters_.smoothing_length;
  Real dt = courant_factor * h / (max_sound_speed_ + max_speed_);
  if (max_acceleration_ > 0) dt = std::min(dt, force_factor * std::sqrt(h / max_acceleration_));
  const auto& m = parameters_.material;
  if (m.dynamic_viscosity > 0)
    dt = std::min(dt, viscous_factor * h * h * m.density / m.dynamic_viscosity);
  return dt;
}

solver::Formulation::Power FluidFormulation::internal_power(std::span<const Vec3> v) const {
  // Stored (compression) energy grows by -f_pressure . v; viscosity dissipates -f_viscous . v.
  // Reduced in particle order (deterministic).
  Power p;
  const Index n = particle_count();
  for (Index a = 0; a < n; ++a) {
    const Vec3& va = v[node_[a]];
    for (int d = 0; d < 3; ++d) {
      p.stored -= Real(pressure_force_[3 * a + d]) * va[d];
      p.dissipated -= Real(viscous_force_[3 * a + d]) * va[d];
    }
  }
  return p;
}

std::vector<Index> FluidFormulation::neighbour_counts() const {
  std::vector<Index> counts(particle_count(), 0);
  if (!cells_built_) return counts;
  const float H2 = static_cast<float>(support_ * support_);
#pragma omp parallel
  for_each_cell_neighbourhood(false, [&](neighbors::ParticleRange own,
                                         const std::array<neighbors::ParticleRange, 9>& ranges,
                                         int range_count) {
    for (Index a = own.begin; a < own.end; ++a) {
      Index count = 0;
      for (int r = 0; r < range_count; ++r)
        for (Index b = ranges[r].begin; b < ranges[r].end; ++b) {
          const float dx = x_[a] - x_[b], dy = y_[a] - y_[b], dz = z_[a] - z_[b];
          count += (dx * dx + dy * dy + dz * dz < H2) & (b != a);
        }
      counts[a] = count;
    }
  });
  return counts;
}

void FluidFormulation::add_fields(std::vector<io::output::PointField>& fields,
                                  const solver::NodeStore& nodes) const {
  const std::size_t n_nodes = nodes.id.size();
  std::vector<double> pressure(n_nodes, 0), density(n_nodes, 0), smoothing(n_nodes, 0);
  std::vector<std::int64_t> neighbour_count(n_nodes, 0);
  const auto counts = neighbour_counts();
  for (Index a = 0; a < particle_count(); ++a) {
    const Index i = node_[a];
    pressure[i] = parameters_.material.pressure(density_[a]);
    density[i] = density_[a];
    smoothing[i] = parameters_.smoothing_length;
    neighbour_count[i] = counts[a];
  }
  fields.push_back({"pressure", 1, std::move(pressure)});
  fields.push_back({"density", 1, std::move(density)});
  fields.push_back({"smoothing_length", 1, std::move(smoothing)});
  fields.push_back({"neighbour_count", 1, std::move(neighbour_count)});
}

std::size_t FluidFormulation::memory_bytes() const {
  std::size_t total = bytes(node_) + bytes(mass_) + bytes(density_) + bytes(rate_) +
                      bytes(previous_rate_) + bytes(predicted_density_) + bytes(pressure_term_) +
                      bytes(pressure_force_) + bytes(viscous_force_) + bytes(active_cell_);
  for (const auto* v : {&x_, &y_, &z_, &vx_, &vy_, &vz_}) total += bytes(*v);
  return total + cells_.memory_bytes();
}

Real FluidFormulation::max_wave_speed() const { return max_sound_speed_; }

}  // namespace spall::sph
