#include "spall/fem/solid_elements.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <stdexcept>

#include <fmt/format.h>

#include "spall/core/cube_root.hpp"
#include "spall/core/error.hpp"
#include "spall/core/parallel.hpp"
#include "spall/fem/hexahedron.hpp"
#include "spall/fem/tetrahedron.hpp"
#include "spall/materials/elastic.hpp"

namespace spall::fem {

namespace {

using Kind = SolidElements::Kind;

// Colours below this size run on the calling thread.
constexpr parallel::Schedule element_loops{.chunk = 0, .serial_below = 512};

template <typename T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// The element's step for its own bulk viscosity (LS-DYNA's form): L / (Q + sqrt(Q^2 + c^2)) with
// Q = Q2 c + Q1 L |tr D| while the element shrinks (fem-contact.md §2.4).
Real element_time_step(Real length, Real c, Real volume_rate, const PartSettings& part) {
  const Real q = volume_rate < 0 ? part.bulk_linear * c - part.bulk_quadratic * length * volume_rate : 0;
  return length / (q + std::sqrt(q * q + c * c));
}

// Bulk viscosity q = rho l (Q1 l tr(D)^2 - Q2 c tr(D)) while tr(D) < 0, l = V^(1/3) (LS-DYNA's
// solid elements; the SPG particles use the same form with their spacing).
Real bulk_viscosity(Real rho, Real volume, Real c, Real volume_rate, const PartSettings& part) {
  if (!(volume_rate < 0)) return 0;
  const Real l = cube_root(volume);
  return rho * l * (part.bulk_quadratic * l * volume_rate * volume_rate - part.bulk_linear * c * volume_rate);
}

}  // namespace

SolidElements::SolidElements(std::vector<PartSettings> parts, const std::vector<ElementSetup>& elements,
                             const discretization::NodeStore& nodes)
    : parts_(std::move(parts)) {
  // Local nodes in node-store order (the store is in spatial order already).
  std::vector<Index> local(nodes.size(), -1);
  for (const auto& e : elements)
    for (Index i : e.node) local[i] = 0;
  for (Index i = 0; i < nodes.size(); ++i)
    if (local[i] == 0) {
      local[i] = static_cast<Index>(node_.size());
      node_.push_back(i);
    }
  force_.assign(node_.size(), Vec3::Zero());
  bulk_force_.assign(node_.size(), Vec3::Zero());
  if (std::any_of(parts_.begin(), parts_.end(), [](const PartSettings& p) {
        return p.elform == 1 && p.hourglass.form != HourglassForm::none;
      }))
    hourglass_force_.assign(node_.size(), Vec3::Zero());

  const auto kind_of = [&](const ElementSetup& e) {
    const int elform = parts_[e.part].elform;
    return elform == 10 ? Kind::tetrahedron : elform == 2 ? Kind::hexahedron_selective_reduced : Kind::hexahedron;
  };
  for (Kind kind : {Kind::hexahedron, Kind::hexahedron_selective_reduced, Kind::tetrahedron}) {
    Block block;
    block.kind = kind;
    block.nodes_per_element = kind == Kind::tetrahedron ? 4 : 8;
    block.points_per_element = kind == Kind::hexahedron_selective_reduced ? 8 : 1;
    bool stiffness = false;
    for (const auto& e : elements) {
      if (kind_of(e) != kind) continue;
      const PartSettings& part = parts_[e.part];
      Real volume = 0;
      if (kind == Kind::tetrahedron) {
        TetNodes x;
        for (int a = 0; a < 4; ++a) x[a] = nodes.x0[e.node[a]];
        volume = tet_gradient(x).volume;
      } else {
        HexNodes x;
        for (int a = 0; a < 8; ++a) x[a] = nodes.x0[e.node[a]];
        volume = hex_gradient(x).volume;
      }
      if (!(volume > 0))
        throw std::invalid_argument(fmt::format("element {}: volume {:.6g} at the start", e.id, volume));
      for (int a = 0; a < block.nodes_per_element; ++a) block.node.push_back(local[e.node[a]]);
      block.part.push_back(e.part);
      block.id.push_back(e.id);
      block.mass.push_back(part.material.density * volume);
      block.volume.push_back(volume);
      block.density.push_back(part.material.density);
      const materials::Material& m = part.material;
      const Real e0 = m.initial_specific_energy;
      for (int g = 0; g < block.points_per_element; ++g) {
        block.state.push_back(materials::initial_state(m));
        block.thermo.push_back({e0, materials::eos_pressure(m, m.density, e0), materials::sound_speed(m, m.density, e0)});
      }
      stiffness |= kind == Kind::hexahedron && part.hourglass.form == HourglassForm::stiffness;
    }
    if (block.id.empty()) continue;
    const std::size_t n = block.id.size();
    block.viscous_pressure.assign(n, 0);
    if (kind == Kind::hexahedron) block.hourglass_energy.assign(n, 0);
    if (stiffness) block.hourglass_force.assign(hourglass_modes * n, Vec3::Zero());
    colour(block);
    blocks_.push_back(std::move(block));
  }
}

// Greedy colouring in element order: each element takes the lowest colour none of its nodes'
// other elements has taken (a bit per colour and node; a structured hexahedral mesh needs 8).
void SolidElements::colour(Block& block) const {
  const Index n = block.size();
  const int per = block.nodes_per_element;
  std::vector<std::vector<bool>> taken;  // taken[c][node]
  std::vector<int> colour_of(n);
  for (Index e = 0; e < n; ++e) {
    int c = 0;
    for (;; ++c) {
      if (c == static_cast<int>(taken.size())) taken.emplace_back(node_.size(), false);
      bool free = true;
      for (int a = 0; a < per && free; ++a) free = !taken[c][block.node[per * e + a]];
      if (free) break;
    }
    for (int a = 0; a < per; ++a) taken[c][block.node[per * e + a]] = true;
    colour_of[e] = c;
  }
  block.colour_offset.assign(taken.size() + 1, 0);
  for (Index e = 0; e < n; ++e) ++block.colour_offset[colour_of[e] + 1];
  for (std::size_t c = 0; c < taken.size(); ++c) block.colour_offset[c + 1] += block.colour_offset[c];
  block.colour_element.resize(n);
  std::vector<Index> next(block.colour_offset.begin(), block.colour_offset.end() - 1);
  for (Index e = 0; e < n; ++e) block.colour_element[next[colour_of[e]]++] = e;
}

// One element over the step: its strain rate at the middle of the step (x^{n-1/2} = x^n - dt/2
// v^{n-1/2}), the material update of its points, and its forces at x^n added to force_. Returns
// its stable step, or -1 when its volume is no longer positive.
template <Kind kind>
Real SolidElements::element_step(Block& block, Index e, const discretization::NodeStore& nodes, Real dt) {
  constexpr int N = kind == Kind::tetrahedron ? 4 : 8;
  const Index* local = &block.node[N * e];
  const PartSettings& part = parts_[block.part[e]];
  const materials::Material& material = part.material;
  std::array<Vec3, N> x, x_half, v;
  for (int a = 0; a < N; ++a) {
    const Index i = node_[local[a]];
    x[a] = nodes.x[i];
    v[a] = nodes.v[i];
    x_half[a] = x[a] - Real(0.5) * dt * v[a];
  }
  // b_I = dV/dx_I now and at the middle of the step.
  std::array<Vec3, N> b, b_half;
  Real volume, volume_half, length;
  HexCoefficients a_now;  // the hexahedron's basis coefficients (hourglass vectors)
  if constexpr (kind == Kind::tetrahedron) {
    const TetGradient now = tet_gradient(x), half = tet_gradient(x_half);
    b = now.b, volume = now.volume, b_half = half.b, volume_half = half.volume;
    length = volume > 0 ? tet_characteristic_length(now) : 0;
  } else {
    a_now = hex_coefficients(x);
    const HexGradient now = hex_gradient(a_now), half = hex_gradient(x_half);
    b = now.b, volume = now.volume, b_half = half.b, volume_half = half.volume;
    length = volume > 0 ? hex_characteristic_length(x, volume) : 0;
  }
  if (!(volume > 0) || !(volume_half > 0)) return -1;
  const Real rho = block.mass[e] / volume;
  Mat3 L = Mat3::Zero();  // the mean velocity gradient (1/V) sum_I v_I b_I^T
  for (int a = 0; a < N; ++a) L.noalias() += v[a] * b_half[a].transpose();
  L /= volume_half;
  const Real volume_rate = L.trace();

  // The material: one point, or the eight Gauss points of the selective-reduced hexahedron with
  // the element's mean volumetric rate in place of their own (B-bar; its pressure is their mean).
  materials::PointState* state = &block.state[block.points_per_element * e];
  materials::PointThermo* thermo = &block.thermo[block.points_per_element * e];
  Vec3 f[N];
  for (auto& fa : f) fa = Vec3::Zero();
  Real pressure = 0, c = 0;
  if constexpr (kind == Kind::hexahedron_selective_reduced) {
    std::array<Vec3, 8> grad;
    for (int g = 0; g < 8; ++g) {
      if (dt > 0) {
        if (!(hex_point_gradients(x_half, g, grad) > 0)) return -1;
        Mat3 Lg = Mat3::Zero();
        for (int a = 0; a < 8; ++a) Lg.noalias() += v[a] * grad[a].transpose();
        Lg.diagonal().array() += (volume_rate - Lg.trace()) / 3;
        materials::advance_point(material, state[g], thermo[g], Lg, dt, rho);
      }
      // The deviator's forces -integral S grad N_I dV at x^n, by the same rule.
      const Real J = hex_point_gradients(x, g, grad);
      if (!(J > 0)) return -1;
      const Mat3 S = J * state[g].deviatoric_stress;
      for (int a = 0; a < 8; ++a) f[a].noalias() -= S * grad[a];
      pressure += J * thermo[g].pressure;
      c = std::max(c, thermo[g].sound_speed);
    }
    pressure /= volume;  // the Gauss points' weights sum to the volume (det J integrated exactly)
  } else {
    if (dt > 0) materials::advance_point(material, state[0], thermo[0], L, dt, rho);
    pressure = thermo[0].pressure;
    c = thermo[0].sound_speed;
    for (int a = 0; a < N; ++a) f[a].noalias() = -(state[0].deviatoric_stress * b[a]);
  }
  const Real q = bulk_viscosity(rho, volume, c, volume_rate, part);
  for (int a = 0; a < N; ++a) {
    f[a] += pressure * b[a];  // -(-p I) b_I
    bulk_force_[local[a]] += q * b[a];
  }

  // Hourglass control of the one-point hexahedron (Flanagan & Belytschko 1981): the hourglass
  // rates qdot_alpha = sum_I v_I gamma_alphaI on the shape vectors
  // gamma_alphaI = Gamma_alphaI - (h_alpha . b_I) / V, h_alpha = sum_J x_J Gamma_alphaJ = 8 a_{4+alpha},
  // which vanish for rigid and linear motions (IHQ 1: on Gamma itself); f_I = -sum_alpha Q_alpha
  // gamma_alphaI with Q = a_h qdot (viscous, a_h = QM rho c V^(2/3) / 4) or Q += kappa qdot dt
  // (stiffness, kappa = QM 2G V^(1/3) / 4: with QM 0.1 a cube's bending mode gets about its
  // physical stiffness, docs/THEORY.md §10.3).
  if constexpr (kind == Kind::hexahedron) {
    const HourglassControl& hg = part.hourglass;
    if (hg.form != HourglassForm::none) {
      const Real l = cube_root(volume);
      for (int alpha = 0; alpha < hourglass_modes; ++alpha) {
        const int* Gamma = hex_basis[4 + alpha];
        Real gamma[8];
        const Vec3 h = 8 * a_now.a[4 + alpha] / volume;
        for (int a = 0; a < 8; ++a)
          gamma[a] = hg.form == HourglassForm::viscous_base ? Real(Gamma[a]) : Gamma[a] - h.dot(b[a]);
        Vec3 rate = Vec3::Zero();
        for (int a = 0; a < 8; ++a) rate += gamma[a] * v[a];
        Vec3 Q;
        if (hg.form == HourglassForm::stiffness) {
          Vec3& stored = block.hourglass_force[hourglass_modes * e + alpha];
          stored += (hg.coefficient * 2 * material.shear_modulus * l / 4 * dt) * rate;
          Q = stored;
        } else {
          Q = (hg.coefficient * rho * c * l * l / 4) * rate;
        }
        for (int a = 0; a < 8; ++a) hourglass_force_[local[a]] -= gamma[a] * Q;
        block.hourglass_energy[e] += dt * Q.dot(rate);  // for output: at the step's own rates
      }
    }
  }
  for (int a = 0; a < N; ++a) force_[local[a]] += f[a];
  block.volume[e] = volume;
  block.density[e] = rho;
  block.viscous_pressure[e] = q;
  return element_time_step(length, c, volume_rate, part);
}

void SolidElements::compute_forces(discretization::NodeStore& nodes, Real dt) {
  const bool hourglass = !hourglass_force_.empty();
  parallel::for_each(static_cast<Index>(node_.size()), [&](Index k) {
    force_[k] = bulk_force_[k] = Vec3::Zero();
    if (hourglass) hourglass_force_[k] = Vec3::Zero();
  }, element_loops);
  struct Found {
    Real step;
    Real sound_speed;
  };
  const auto combine = [](const Found& x, const Found& y) {
    return Found{std::min(x.step, y.step), std::max(x.sound_speed, y.sound_speed)};
  };
  const Found none{std::numeric_limits<Real>::infinity(), 0};
  Found found = none;
  parallel::LowestIndex inverted;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    Block& block = blocks_[k];
    const auto run = [&]<Kind kind>() {
      for (std::size_t c = 0; c + 1 < block.colour_offset.size(); ++c) {
        const Index begin = block.colour_offset[c];
        found = combine(found, parallel::reduce_exact(block.colour_offset[c + 1] - begin, none, [&](Index j) {
          const Index e = block.colour_element[begin + j];
          const Real step = element_step<kind>(block, e, nodes, dt);
          if (step < 0) {
            inverted.report(e);
            return none;
          }
          const Real c_e = block.thermo[block.points_per_element * e].sound_speed;
          return Found{step, c_e};
        }, combine, element_loops));
        if (inverted.value() >= 0) break;
      }
    };
    switch (block.kind) {
      case Kind::hexahedron: run.template operator()<Kind::hexahedron>(); break;
      case Kind::hexahedron_selective_reduced: run.template operator()<Kind::hexahedron_selective_reduced>(); break;
      case Kind::tetrahedron: run.template operator()<Kind::tetrahedron>(); break;
    }
    if (const Index e = inverted.value(); e >= 0)
      throw InstabilityError(fmt::format("FEM part {}: element {} has a negative volume: it inverted (element "
                                         "erosion is not available yet; a smaller TSSFAC or a finer mesh may help)",
                                         parts_[block.part[e]].part_id, block.id[e]));
  }
  parallel::for_each(static_cast<Index>(node_.size()), [&](Index k) {
    nodes.f[node_[k]] += force_[k] + bulk_force_[k] + (hourglass ? hourglass_force_[k] : Vec3::Zero());
  }, element_loops);
  stable_step_ = found.step;
  max_sound_speed_ = found.sound_speed;
}

Real SolidElements::stable_time_step(const discretization::NodeStore&) const { return stable_step_; }

void SolidElements::book_energies(discretization::EnergyLedger& ledger, std::span<const Vec3> v, Real dt) const {
  using Ledger = discretization::EnergyLedger;
  // The work of each share of the internal forces at the mid-step velocities: the stress's is
  // stored, the bulk viscosity's and the hourglass control's are their own terms.
  const bool hourglass = !hourglass_force_.empty();
  const Sums<3> work = parallel::ordered_sum(static_cast<Index>(node_.size()), [&](Index k) {
    const Vec3& u = v[node_[k]];
    Sums<3> w;
    w[0] = -force_[k].dot(u);
    w[1] = -bulk_force_[k].dot(u);
    w[2] = hourglass ? -hourglass_force_[k].dot(u) : 0;
    return w;
  }, Sums<3>{});
  ledger.add(Ledger::internal_energy, Ledger::Role::stored, dt * work[0]);
  ledger.add(Ledger::artificial_viscosity_energy, Ledger::Role::dissipated, dt * work[1]);
  if (hourglass) ledger.add(Ledger::hourglass_energy, Ledger::Role::dissipated, dt * work[2]);
}

void SolidElements::write_fields(discretization::FieldSet& fields, const discretization::NodeStore&) const {
  for (const Block& block : blocks_) {
    auto& cells = fields.add_cell_block(block.kind == Kind::tetrahedron ? discretization::CellShape::tetrahedron
                                                                        : discretization::CellShape::hexahedron);
    const Index n = block.size();
    const int per = block.nodes_per_element, points = block.points_per_element;
    cells.connectivity.resize(static_cast<std::size_t>(per) * n);
    for (std::size_t k = 0; k < cells.connectivity.size(); ++k) cells.connectivity[k] = node_[block.node[k]];
    const auto field = [&](const char* name, int components, std::vector<std::string> labels = {}) {
      auto& f = cells.fields.emplace_back();
      f.name = name;
      f.components = components;
      f.values = std::vector<double>(static_cast<std::size_t>(components) * n);
      f.component_names = std::move(labels);
      return std::get<std::vector<double>>(f.values).data();
    };
    double* stress = field("stress", 6, discretization::symmetric_tensor_components);
    double* pressure = field("pressure", 1);
    double* von_mises = field("von_mises", 1);
    double* plastic_strain = field("effective_plastic_strain", 1);
    double* density = field("density", 1);
    double* hourglass = block.hourglass_energy.empty() ? nullptr : field("hourglass_energy", 1);
    auto& ids = cells.fields.emplace_back();
    ids.name = "element_id";
    ids.values = std::vector<std::int64_t>(block.id.begin(), block.id.end());
    for (Index e = 0; e < n; ++e) {
      // The mean over the element's points (the Gauss points carry equal weight to round-off for
      // an element that is not badly distorted).
      Mat3 S = Mat3::Zero();
      Real p = 0, eps = 0;
      for (int g = 0; g < points; ++g) {
        S += block.state[points * e + g].deviatoric_stress;
        p += block.thermo[points * e + g].pressure;
        eps += block.state[points * e + g].plastic_strain;
      }
      S /= points, p /= points, eps /= points;
      const Mat3 sigma = S - p * Mat3::Identity();
      const Real voigt[6] = {sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(2, 0)};
      std::copy(voigt, voigt + 6, stress + 6 * e);
      pressure[e] = p;
      von_mises[e] = materials::von_mises(S);
      plastic_strain[e] = eps;
      density[e] = block.density[e];
      if (hourglass) hourglass[e] = block.hourglass_energy[e];
    }
  }
}

void SolidElements::add_nodal_masses(discretization::NodeStore& nodes) const {
  for (const Block& block : blocks_)
    for (Index e = 0; e < block.size(); ++e)
      for (int a = 0; a < block.nodes_per_element; ++a)
        nodes.mass[node_[block.node[block.nodes_per_element * e + a]]] += block.mass[e] / block.nodes_per_element;
}

Index SolidElements::element_count() const {
  Index n = 0;
  for (const Block& block : blocks_) n += block.size();
  return n;
}

std::size_t SolidElements::memory_bytes() const {
  std::size_t total = bytes(node_) + bytes(force_) + bytes(bulk_force_) + bytes(hourglass_force_);
  for (const Block& b : blocks_)
    total += bytes(b.node) + bytes(b.part) + bytes(b.id) + bytes(b.mass) + bytes(b.state) + bytes(b.thermo) +
             bytes(b.volume) + bytes(b.density) + bytes(b.viscous_pressure) + bytes(b.hourglass_energy) + bytes(b.hourglass_force) +
             bytes(b.colour_offset) + bytes(b.colour_element);
  return total;
}

}  // namespace spall::fem
