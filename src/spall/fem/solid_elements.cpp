#include "spall/fem/solid_elements.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <span>
#include <stdexcept>

#include <Eigen/Eigenvalues>
#include <fmt/format.h>

#include "spall/core/communicator.hpp"
#include "spall/core/cube_root.hpp"
#include "spall/core/error.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/pieces.hpp"
#include "spall/fem/hexahedron.hpp"
#include "spall/fem/lanes.hpp"
#include "spall/fem/tetrahedron.hpp"
#include "spall/materials/elastic.hpp"
#include "spall/materials/radial_return.hpp"

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

// DT2MS (THEORY §1, mass scaling): the sound speed c' at which element_time_step(l, c', tr D) is `step`. With
// Q = Q2 c' + a, a = Q1 l |tr D| while the element shrinks, l / (Q + sqrt(Q^2 + c'^2)) = step is
// c'^2 + 2 s Q2 c' + 2 s a - s^2 = 0, s = l / step; never below s / 2 (an element collapsing so fast
// that its viscosity holds its step near or below `step` keeps a smaller step rather than take
// unbounded mass).
Real sound_speed_for_step(Real length, Real step, Real volume_rate, const PartSettings& part) {
  const Real s = length / step;
  if (!(volume_rate < 0)) return s;
  const Real a = -part.bulk_quadratic * length * volume_rate, b = part.bulk_linear;
  const Real discriminant = s * s * (b * b + 1) - 2 * s * a;
  return discriminant > 0 ? std::max(-s * b + std::sqrt(discriminant), s / 2) : s / 2;
}

// Bulk viscosity q = rho l (Q1 l tr(D)^2 - Q2 c tr(D)) while tr(D) < 0, l = V^(1/3) (LS-DYNA's
// solid elements; the SPG particles use the same form with their spacing).
Real bulk_viscosity(Real rho, Real l, Real c, Real volume_rate, const PartSettings& part) {
  if (!(volume_rate < 0)) return 0;
  return rho * l * (part.bulk_quadratic * l * volume_rate * volume_rate - part.bulk_linear * c * volume_rate);
}

// Elements stored this many to a stretch of the node order (below).
constexpr std::size_t colour_stretch = 512;

// The storage order of one kind's elements (`order`, places in `elements`, in the deck's order
// on entry) and each one's colour. Greedy colouring in the deck's order: each element takes the
// lowest colour none of its nodes' other elements has taken (a bit per colour and node; a
// structured hexahedral mesh in the deck's usual order needs 8). Stored in the order of their first
// nodes in the node store (the deck's among those of one node), so that under MPI the elements a
// rank computes, those with a node of its block of the node order, are one stretch; and within
// each stretch of colour_stretch of that order colour by colour, so that a colour's pass reads its
// elements' state in runs, not one element here and one there (a third slower on a brick mesh of
// ELFORM 2 elements, which the prefetch of strided runs no longer helps).
void store_in_colours(const std::vector<ElementSetup>& elements, std::vector<Index>& order, int nodes_per_element,
                      Index node_count, std::vector<int>& colour_of) {
  std::vector<std::vector<bool>> taken;  // taken[c][node]
  std::vector<int> colour(elements.size(), -1);
  for (const Index k : order) {
    const auto& node = elements[k].node;
    int c = 0;
    for (;; ++c) {
      if (c == static_cast<int>(taken.size())) taken.emplace_back(node_count, false);
      bool free = true;
      for (int a = 0; a < nodes_per_element && free; ++a) free = !taken[c][node[a]];
      if (free) break;
    }
    for (int a = 0; a < nodes_per_element; ++a) taken[c][node[a]] = true;
    colour[k] = c;
  }
  std::stable_sort(order.begin(), order.end(),
                   [&](Index a, Index b) { return elements[a].node[0] < elements[b].node[0]; });
  for (std::size_t begin = 0; begin < order.size(); begin += colour_stretch) {
    const auto end = order.begin() + static_cast<std::ptrdiff_t>(std::min(order.size(), begin + colour_stretch));
    std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(begin), end,
                     [&](Index a, Index b) { return colour[a] < colour[b]; });
  }
  colour_of.resize(order.size());
  for (std::size_t p = 0; p < order.size(); ++p) colour_of[p] = colour[order[p]];
}

}  // namespace

Real element_volume(const std::array<Index, 8>& node, bool tetrahedron, const discretization::NodeStore& nodes) {
  if (tetrahedron) {
    TetNodes x;
    for (int a = 0; a < 4; ++a) x[a] = nodes.x0[node[a]];
    return tet_gradient(x).volume;
  }
  HexVectors x;
  for (int a = 0; a < 8; ++a) x[a] = nodes.x0[node[a]];
  return hex_gradient(x).volume;
}

SolidElements::SolidElements(std::vector<PartSettings> parts, const std::vector<ElementSetup>& elements,
                             const discretization::NodeStore& nodes)
    : parts_(std::move(parts)) {
  // Local nodes in node-store order (the store is in spatial order already, and the set-up holds
  // every node: a row is its place in the node order).
  std::vector<Index> local(nodes.size(), -1);
  for (const auto& e : elements)
    for (Index i : e.node) local[i] = 0;
  for (Index i = 0; i < nodes.size(); ++i)
    if (local[i] == 0) {
      local[i] = static_cast<Index>(node_.size());
      node_.push_back(i);
    }
  force_.resize(0), bulk_force_.resize(0);  // held from set_up_state on
  for (const auto& p : parts_) {
    hourglass_ |= p.elform == 1 && p.hourglass.form != HourglassForm::none;
    const Erosion& er = p.erosion;
    may_erode_ |= er.max_pressure || er.min_pressure || er.max_principal_stress || er.von_mises ||
                  er.max_principal_strain || er.min_principal_strain || er.effective_strain ||
                  er.volumetric_strain || er.failure_time;
    materials::PointState failed;
    failed.plastic_strain = std::numeric_limits<Real>::max();
    failed.damage = 1;
    may_erode_ |= er.material_failure && materials::erodes_element(p.material, failed);
  }

  const auto kind_of = [&](const ElementSetup& e) {
    const int elform = parts_[e.part].elform;
    return elform == 10 ? Kind::tetrahedron : elform == 2 ? Kind::hexahedron_selective_reduced : Kind::hexahedron;
  };
  for (Kind kind : {Kind::hexahedron, Kind::hexahedron_selective_reduced, Kind::tetrahedron}) {
    Block block;
    block.kind = kind;
    block.nodes_per_element = kind == Kind::tetrahedron ? 4 : 8;
    block.points_per_element = kind == Kind::hexahedron_selective_reduced ? 8 : 1;
    std::vector<Index> order;  // the kind's elements (places in the deck)
    for (Index k = 0; k < static_cast<Index>(elements.size()); ++k)
      if (kind_of(elements[k]) == kind) order.push_back(k);
    std::vector<int> colour_of;  // each stored element's colour
    store_in_colours(elements, order, block.nodes_per_element, nodes.size(), colour_of);
    bool stiffness = false, needs_strain = false, kinematic = false;
    for (const Index k : order) {
      const ElementSetup& e = elements[k];
      const PartSettings& part = parts_[e.part];
      const Real volume = element_volume(e.node, kind == Kind::tetrahedron, nodes);
      if (!(volume > 0))
        throw std::invalid_argument(fmt::format("element {}: volume {:.6g} at the start", e.id, volume));
      for (int a = 0; a < block.nodes_per_element; ++a) block.node.push_back(local[e.node[a]]);
      block.part.push_back(e.part);
      block.id.push_back(e.id);
      block.mass.push_back(part.material.density * volume);
      stiffness |= kind == Kind::hexahedron && part.hourglass.form == HourglassForm::stiffness;
      needs_strain |= part.erosion.needs_strain();
      kinematic |= materials::keeps_back_stress(part.material);
    }
    if (block.id.empty()) continue;
    const Index n = block.size();
    // The state's arrays on, holding no element yet (set_up_state).
    block.state.resize(0), block.thermo.resize(0), block.volume.resize(0), block.eroded.resize(0);
    if (kind == Kind::hexahedron) block.hourglass_energy.resize(0), block.hourglass_power.resize(0);
    if (stiffness) block.hourglass_force.resize(0);
    if (kinematic) block.back_stress.resize(0);
    if (needs_strain) block.strain.resize(0), block.effective_strain.resize(0);
    // Each colour's elements in storage order.
    const int colours = colour_of.empty() ? 0 : *std::max_element(colour_of.begin(), colour_of.end()) + 1;
    block.colour_offset.assign(colours + 1, 0);
    for (const int c : colour_of) ++block.colour_offset[c + 1];
    std::partial_sum(block.colour_offset.begin(), block.colour_offset.end(), block.colour_offset.begin());
    block.colour_element.resize(n);
    std::vector<Index> next(block.colour_offset.begin(), block.colour_offset.end() - 1);
    for (Index e = 0; e < n; ++e) block.colour_element[next[colour_of[e]]++] = e;
    block.mass.shrink_to_fit();
    block.node.shrink_to_fit(), block.part.shrink_to_fit(), block.id.shrink_to_fit();
    blocks_.push_back(std::move(block));
  }
  live_elements_.assign(node_.size(), 0);
  for (const Block& block : blocks_)
    for (Index k : block.node) ++live_elements_[k];
  node_part_.assign(node_.size(), -1);
  for (const Block& block : blocks_)
    for (std::size_t j = 0; j < block.node.size(); ++j) {
      const std::int32_t p = block.part[j / static_cast<std::size_t>(block.nodes_per_element)];
      std::int32_t& q = node_part_[block.node[j]];
      if (q < 0 || parts_[p].part_id < parts_[q].part_id) q = p;
    }
  eroded_internal_by_part_.assign(parts_.size(), 0);
  eroded_kinetic_by_part_.assign(parts_.size(), 0);
  // Under MPI each rank sets up the elements it computes alone, once the nodes are dealt
  // (distribute): no rank holds every element's state, even for a while.
  if (parallel::world().size() == 1) set_up_state(nodes);
}

void SolidElements::set_up_state(const discretization::NodeStore& nodes) {
  state_set_up_ = true;  // from here on held() and forces_held() are what this rank computes
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    Block& block = blocks_[k];
    const parallel::Range elements = held(k);
    block.hold(elements);
    const int per = block.nodes_per_element, points = block.points_per_element;
    parallel::for_each(elements.size(), [&](Index j) {
      const Index e = elements.begin + j;
      // The stretch held may hold elements another rank computes, whose nodes a window need not
      // hold: their volume is never read here (a new deal brings it with their state).
      bool nodes_held = true;
      std::array<Index, 8> node{};
      for (int a = 0; a < per; ++a) {
        const Index place = node_[block.node[per * e + a]];
        nodes_held = nodes_held && nodes.holds_place(place);
        node[a] = nodes.node_row(place);
      }
      block.volume[e] = nodes_held ? element_volume(node, block.kind == Kind::tetrahedron, nodes) : 0;
      const materials::Material& m = parts_[block.part[e]].material;
      const Real e0 = m.initial_specific_energy;
      for (int g = 0; g < points; ++g) {
        block.state[points * e + g] = materials::initial_state(m);
        block.thermo[points * e + g] = {e0, materials::eos_pressure(m, m.density, e0),
                                        materials::sound_speed(m, m.density, e0)};
        if (!block.back_stress.empty()) block.back_stress[points * e + g] = Mat3::Zero();
      }
      block.eroded[e] = 0;
      if (!block.mass_scale.empty()) block.mass_scale[e] = 1;
      if (!block.hourglass_energy.empty()) block.hourglass_energy[e] = block.hourglass_power[e] = 0;
      if (!block.hourglass_force.empty())
        for (int m = 0; m < hourglass_modes; ++m) block.hourglass_force[hourglass_modes * e + m] = Vec3::Zero();
      if (!block.strain.empty()) block.strain[e] = Mat3::Zero(), block.effective_strain[e] = 0;
    });
  }
  const parallel::Range forces = forces_held();
  force_.hold(forces.begin, forces.end);
  bulk_force_.hold(forces.begin, forces.end);
  force_.fill(Vec3::Zero());
  bulk_force_.fill(Vec3::Zero());
}

namespace {

template <std::size_t N>
void scatter(const std::array<Vec3, N>& f, const Index* local, RangeArray<Vec3>& to) {
  for (std::size_t n = 0; n < N; ++n) to[local[n]] += f[n];
}

template <int N>
struct Gathered {
  std::array<Vec3, N> x, v;
};

template <int N>
Gathered<N> gather(const Index* local, const std::vector<Index>& node, const discretization::NodeStore& nodes) {
  Gathered<N> g;
  for (int a = 0; a < N; ++a) {
    const Index i = nodes.node_row(node[local[a]]);
    g.x[a] = nodes.x[i];
    g.v[a] = nodes.v[i];
  }
  return g;
}

// A hexahedron over the step in its basis: a(x^n), a(v), and the volume gradients at x^n and at
// x^{n-1/2}, whose coefficients are a(x^n) - dt/2 a(v) (the map is linear in the nodes).
struct HexStep {
  HexVectors a, av;
  HexVolumeGradient now, half;
  bool inverted() const { return !(now.volume > 0) || !(half.volume > 0); }
};

HexStep hex_step(const std::array<Vec3, 8>& x, const std::array<Vec3, 8>& v, Real dt) {
  HexStep s;
  s.a = hex_coefficients(x);
  s.av = hex_coefficients(v);
  HexVectors a_half;
  for (int k = 0; k < 8; ++k) a_half[k] = s.a[k] - Real(0.5) * dt * s.av[k];
  s.now = hex_volume_gradient(s.a);
  s.half = hex_volume_gradient(a_half);
  return s;
}

Mat3 to_mat3(const LaneMatrix<Real>& a) {
  Mat3 m;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) m(i, j) = a.m[i][j];
  return m;
}

// The one-point hexahedra run side by side, an element a lane.
using Lane = simd::Pack;
constexpr int lanes = Lane::width;
using LaneVec = LaneVector<Lane>;

// values[index[l]] of every lane l.
LaneVec gather_lanes(const std::vector<Vec3>& values, const Index* index) {
  const Real* base = values.data()->data();
  return {Lane::gather<3>(base, index, 0), Lane::gather<3>(base, index, 1), Lane::gather<3>(base, index, 2)};
}

// The lanes of a pack, and a pack of lanes.
struct LaneValues {
  alignas(64) Real v[lanes];
  LaneValues() = default;
  explicit LaneValues(Lane p) { p.store(v); }
  Real operator[](int l) const { return v[l]; }
};

// Adds the nodal vectors f of the live lanes to their elements' nodes (local node indices).
void scatter_lanes(const HexArray<LaneVec>& f, const Index* const* local, const bool* live, RangeArray<Vec3>& to) {
  for (int a = 0; a < 8; ++a) {
    const LaneValues x(f[a][0]), y(f[a][1]), z(f[a][2]);
    for (int l = 0; l < lanes; ++l)
      if (live[l]) to[local[l][a]] += Vec3(x[l], y[l], z[l]);
  }
}

}  // namespace

// One-point hexahedra of one part (count <= the pack's lanes), an element a lane; the lanes past
// count repeat the first element, and what they compute is dropped. Each element: its strain rate
// at the middle of the step (x^{n-1/2} = x^n - dt/2 v^{n-1/2}), the material update of its point
// (one lane at a time), and its forces at x^n added to its nodes. steps[l]: element l's stable
// step, -1 when its volume is no longer positive, -2 when it fails.
void SolidElements::hexahedra(Block& block, const Index* elements, int count, discretization::NodeStore& nodes,
                              Real dt, Real* steps) {
  const PartSettings& part = parts_[block.part[elements[0]]];
  Index e[lanes];
  const Index* local[lanes];
  alignas(64) Index node[8][lanes];  // node a of each lane's element: its row in the node store
  for (int l = 0; l < lanes; ++l) {
    e[l] = elements[l < count ? l : 0];
    local[l] = &block.node[8 * e[l]];
    for (int a = 0; a < 8; ++a) node[a][l] = nodes.node_row(node_[local[l][a]]);
  }
  HexArray<LaneVec> x, v;
  for (int a = 0; a < 8; ++a) x[a] = gather_lanes(nodes.x, node[a]), v[a] = gather_lanes(nodes.v, node[a]);
  // Everything in the element's basis: a(x^n), a(v), and the volume gradients at x^n and at
  // x^{n-1/2}, whose coefficients are a(x^n) - dt/2 a(v) (the map is linear in the nodes).
  const HexArray<LaneVec> a = hex_coefficients(x), av = hex_coefficients(v);
  HexArray<LaneVec> a_half;
  const Lane half_step(Real(0.5) * dt);
  for (int k = 0; k < 8; ++k) a_half[k] = a[k] - half_step * av[k];
  const auto now = hex_volume_gradient(a), half = hex_volume_gradient(a_half);
  alignas(64) Real mass[lanes];
  for (int l = 0; l < lanes; ++l) mass[l] = block.mass[e[l]];
  const Lane volume = now.volume, rho = Lane::load(mass) / volume;
  const LaneMatrix<Lane> L = basis_gradient(av, half.g) / half.volume;
  const Lane volume_rate = L.trace();
  const LaneValues volume_of(volume), half_volume_of(half.volume), rho_of(rho), rate_of(volume_rate),
      length_of(hex_characteristic_length(a, now.g, volume));
  LaneValues L_of[3][3];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) L_of[i][j] = LaneValues(L.m[i][j]);

  // The material, lane by lane: the stress, sound speed, length and bulk viscosity of each element.
  bool live[lanes] = {};
  LaneValues sigma_of[3][3], c_of, l_of, q_of;
  for (int l = 0; l < lanes; ++l) {
    for (auto& row : sigma_of)
      for (auto& s : row) s.v[l] = 0;
    c_of.v[l] = l_of.v[l] = q_of.v[l] = 0;
    if (l >= count) continue;
    steps[l] = -1;
    if (!(volume_of[l] > 0) || !(half_volume_of[l] > 0)) continue;
    Mat3 Ll;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) Ll(i, j) = L_of[i][j][l];
    materials::PointState& state = block.state[e[l]];
    materials::PointThermo& thermo = block.thermo[e[l]];
    if (dt > 0)
      materials::advance_point(part.material, state, thermo, Ll, dt, rho_of[l],
                               materials::kept_back_stress(block.back_stress, e[l]));
    const Real c = thermo.sound_speed;
    const Real stable_step = scaled_step(block, e[l], length_of[l], c, rate_of[l], nodes);
    if (fails(block, e[l], Ll, dt, stable_step)) {
      steps[l] = -2;
      continue;
    }
    const Real length = cube_root(volume_of[l]);  // of the bulk viscosity and the hourglass control
    c_of.v[l] = c, l_of.v[l] = length;
    q_of.v[l] = bulk_viscosity(rho_of[l], length, c, rate_of[l], part);
    const Mat3 sigma = state.deviatoric_stress - thermo.pressure * Mat3::Identity();
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) sigma_of[i][j].v[l] = sigma(i, j);
    steps[l] = stable_step;
    live[l] = true;
  }

  // f_I = -(sigma - q I) b_I = sum_k c_kI (-(sigma - q I) g_k / 8), the bulk viscosity q acting only
  // while the element shrinks: the basis coefficients of the forces, the hourglass control's added
  // below, then nodal. q's share alone goes to bulk_force_ too, whose work at the nodes' mid-step
  // velocities is what the bulk viscosity dissipates (book_energies).
  LaneMatrix<Lane> sigma;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) sigma.m[i][j] = Lane::load(sigma_of[i][j].v);
  const Lane q = Lane::load(q_of.v);
  for (int d = 0; d < 3; ++d) sigma.m[d][d] = sigma.m[d][d] - q;
  HexArray<LaneVec> force;
  force[0] = force[7] = zero_vector<LaneVec>();
  for (int k = 1; k < 7; ++k) force[k] = Lane(-0.125) * (sigma * now.g[k]);
  bool compressed[lanes];
  bool any_compressed = false;
  for (int l = 0; l < lanes; ++l) any_compressed |= compressed[l] = live[l] && q_of[l] != 0;
  if (any_compressed) {
    HexArray<LaneVec> bulk;
    bulk[0] = bulk[7] = zero_vector<LaneVec>();
    for (int k = 1; k < 7; ++k) bulk[k] = (Lane(0.125) * q) * now.g[k];
    scatter_lanes(hex_nodal(bulk), local, compressed, bulk_force_);
  }

  // Hourglass control (Flanagan & Belytschko 1981): the rates qdot_alpha = sum_I v_I gamma_alphaI on
  // gamma_alphaI = Gamma_alphaI - (h_alpha . b_I) / V, h_alpha = sum_J x_J Gamma_alphaJ = 8 a_{4+alpha},
  // which vanish for rigid and linear motions, are qdot_alpha = 8 a_{4+alpha}(v) - (sum_I v_I (x) b_I)
  // h_alpha / V (IHQ 1: on Gamma, 8 a_{4+alpha}(v)); f_I = -sum_alpha Q_alpha gamma_alphaI with
  // Q = a_h qdot (viscous, a_h = QM rho c V^(2/3) / 4) or Q += kappa qdot dt (stiffness,
  // kappa = QM 2G V^(1/3) / 4: with QM 0.1 a cube's bending mode gets about its physical
  // stiffness, docs/THEORY.md §10.3). In the basis: -Q_alpha Gamma_alphaI is the coefficient
  // -Q_alpha of monomial 4 + alpha, and sum_alpha Q_alpha (h_alpha . b_I) / V = M b_I / V with
  // M = sum_alpha Q_alpha (x) h_alpha adds M g_k / (8 V) to the others.
  const HourglassControl& hg = part.hourglass;
  LaneValues hourglass_power_of(Lane(0));
  if (hg.form != HourglassForm::none) {
    const bool orthogonal = hg.form != HourglassForm::viscous_base;
    const bool stiffness_form = hg.form == HourglassForm::stiffness;
    const LaneMatrix<Lane> velocity_gradient =
        orthogonal ? basis_gradient(av, now.g) / volume : LaneMatrix<Lane>::zero();
    const Lane c = Lane::load(c_of.v), length = Lane::load(l_of.v);
    const Lane viscous = Lane(hg.coefficient) * rho * c * length * length / Lane(4);
    const Lane stiffness = Lane(hg.coefficient * 2 * part.material.shear_modulus) * length / Lane(4);
    LaneMatrix<Lane> M = LaneMatrix<Lane>::zero();
    Lane power(0);
    for (int alpha = 0; alpha < hourglass_modes; ++alpha) {
      const LaneVec h = Lane(8) * a[4 + alpha];
      const LaneVec rate = Lane(8) * av[4 + alpha] - velocity_gradient * h;
      LaneVec Q;
      if (stiffness_form) {
        LaneValues stored[3];
        for (int l = 0; l < lanes; ++l)
          for (int d = 0; d < 3; ++d) stored[d].v[l] = block.hourglass_force[hourglass_modes * e[l] + alpha][d];
        Q = LaneVec(Lane::load(stored[0].v), Lane::load(stored[1].v), Lane::load(stored[2].v)) +
            (stiffness * Lane(dt)) * rate;
        const LaneValues qx(Q[0]), qy(Q[1]), qz(Q[2]);
        for (int l = 0; l < lanes; ++l)
          if (live[l]) block.hourglass_force[hourglass_modes * e[l] + alpha] = Vec3(qx[l], qy[l], qz[l]);
      } else {
        Q = viscous * rate;
      }
      force[4 + alpha] = force[4 + alpha] - Q;
      if (orthogonal) M.add_outer(Q, h);
      power += dot(Q, rate);
    }
    const Lane eight_volume = Lane(8) * volume;
    for (int k = 1; k < 7; ++k) {
      const LaneVec m = M * now.g[k];
      force[k] += LaneVec(m[0] / eight_volume, m[1] / eight_volume, m[2] / eight_volume);
    }
    hourglass_power_of = LaneValues(power);
  }
  scatter_lanes(hex_nodal(force), local, live, force_);
  for (int l = 0; l < lanes; ++l) {
    if (!live[l]) continue;
    block.volume[e[l]] = volume_of[l];
    block.hourglass_power[e[l]] = hourglass_power_of[l];
    block.hourglass_energy[e[l]] += dt * hourglass_power_of[l];  // for output
  }
}

// The fully integrated hexahedron (ELFORM 2): at each of the 2 x 2 x 2 Gauss points its own
// velocity gradient with the element's mean volumetric rate in place of its own (B-bar), its own
// stress; the forces -integral S grad N_I dV by the same rule plus the mean pressure's p b_I.
template <>
Real SolidElements::element_step<Kind::hexahedron_selective_reduced>(Block& block, Index e,
                                                                     discretization::NodeStore& nodes, Real dt) {
  const Index* local = &block.node[8 * e];
  const PartSettings& part = parts_[block.part[e]];
  const auto [x, v] = gather<8>(local, node_, nodes);
  const HexStep geometry = hex_step(x, v, dt);
  if (geometry.inverted()) return -1;
  const auto& [a, av, now, half] = geometry;
  const Real volume = now.volume, rho = block.mass[e] / volume;
  Real volume_rate = 0;
  for (int k = 1; k < 7; ++k) volume_rate += av[k].dot(half.g[k]);
  volume_rate /= half.volume;
  materials::PointState* state = &block.state[8 * e];
  materials::PointThermo* thermo = &block.thermo[8 * e];
  HexVectors grad;
  HexVectors x_half_nodes;
  for (int n = 0; n < 8; ++n) x_half_nodes[n] = x[n] - Real(0.5) * dt * v[n];
  std::array<Vec3, 8> f;
  for (auto& fa : f) fa = Vec3::Zero();
  Real pressure = 0, c = 0;
  for (int g = 0; g < 8; ++g) {
    if (dt > 0) {
      if (!(hex_point_gradients(x_half_nodes, g, grad) > 0)) return -1;
      Mat3 Lg = Mat3::Zero();
      for (int n = 0; n < 8; ++n) Lg.noalias() += v[n] * grad[n].transpose();
      Lg.diagonal().array() += (volume_rate - Lg.trace()) / 3;
      materials::advance_point(part.material, state[g], thermo[g], Lg, dt, rho,
                               materials::kept_back_stress(block.back_stress, 8 * e + g));
    }
    const Real J = hex_point_gradients(x, g, grad);
    if (!(J > 0)) return -1;
    const Mat3 S = J * state[g].deviatoric_stress;
    for (int n = 0; n < 8; ++n) f[n].noalias() -= S * grad[n];
    pressure += J * thermo[g].pressure;
    c = std::max(c, thermo[g].sound_speed);
  }
  pressure /= volume;  // the Gauss points' weights sum to the volume (det J integrated exactly)
  const Real stable_step = scaled_step(block, e, hex_characteristic_length(a, now.g, volume), c, volume_rate, nodes);
  const Mat3 L = part.erosion.needs_strain() ? to_mat3(basis_gradient(av, half.g) / half.volume) : Mat3::Zero();
  if (fails(block, e, L, dt, stable_step)) return -2;
  // The mean pressure's and the bulk viscosity's p b_I + q b_I (q only while the element shrinks);
  // q's share alone to bulk_force_ too, for the energies.
  const Real q = bulk_viscosity(rho, cube_root(volume), c, volume_rate, part);
  HexVectors pressure_share;
  pressure_share[0] = pressure_share[7] = Vec3::Zero();
  for (int k = 1; k < 7; ++k) pressure_share[k] = Real(0.125) * pressure * now.g[k];
  const HexVectors p_b = hex_nodal(pressure_share);
  for (int n = 0; n < 8; ++n) f[n] += p_b[n];
  if (q != 0) {
    HexVectors bulk;
    bulk[0] = bulk[7] = Vec3::Zero();
    for (int k = 1; k < 7; ++k) bulk[k] = Real(0.125) * q * now.g[k];
    const HexVectors q_b = hex_nodal(bulk);
    scatter(q_b, local, bulk_force_);
    for (int n = 0; n < 8; ++n) f[n] += q_b[n];
  }
  scatter(f, local, force_);
  block.volume[e] = volume;
  return stable_step;
}

// The constant-strain tetrahedron (ELFORM 10): b_I exact, one point.
template <>
Real SolidElements::element_step<Kind::tetrahedron>(Block& block, Index e, discretization::NodeStore& nodes, Real dt) {
  const Index* local = &block.node[4 * e];
  const PartSettings& part = parts_[block.part[e]];
  const auto [x, v] = gather<4>(local, node_, nodes);
  TetNodes x_half;
  for (int n = 0; n < 4; ++n) x_half[n] = x[n] - Real(0.5) * dt * v[n];
  const TetGradient now = tet_gradient(x), half = tet_gradient(x_half);
  if (!(now.volume > 0) || !(half.volume > 0)) return -1;
  const Real volume = now.volume, rho = block.mass[e] / volume;
  Mat3 L = Mat3::Zero();
  for (int n = 0; n < 4; ++n) L.noalias() += v[n] * half.b[n].transpose();
  L /= half.volume;
  const Real volume_rate = L.trace();
  materials::PointState& state = block.state[e];
  materials::PointThermo& thermo = block.thermo[e];
  Mat3* back_stress = materials::kept_back_stress(block.back_stress, e);
  if (dt > 0) materials::advance_point(part.material, state, thermo, L, dt, rho, back_stress);
  const Real c = thermo.sound_speed;
  const Real stable_step = scaled_step(block, e, tet_characteristic_length(now), c, volume_rate, nodes);
  if (fails(block, e, L, dt, stable_step)) return -2;
  const Real q = bulk_viscosity(rho, cube_root(volume), c, volume_rate, part);
  // The stress's and the bulk viscosity's forces, -sigma b_I + q b_I; q's share alone to bulk_force_
  // too, for the energies.
  const Mat3 sigma = state.deviatoric_stress - thermo.pressure * Mat3::Identity();
  std::array<Vec3, 4> f, f_bulk;
  for (int n = 0; n < 4; ++n) f_bulk[n] = q * now.b[n], f[n] = f_bulk[n] - sigma * now.b[n];
  scatter(f, local, force_);
  if (q != 0) scatter(f_bulk, local, bulk_force_);
  block.volume[e] = volume;
  return stable_step;
}

// DT2MS (THEORY §1, mass scaling): an element f times heavier has the sound speed c / sqrt(f); one whose step is
// below the target gets the f that brings it there, (f - 1) m more mass shared by its nodes (the
// element's colour owns them in this pass) and kept from then on. Its material keeps its density.
Real SolidElements::scaled_step(Block& block, Index e, Real length, Real c, Real volume_rate,
                                discretization::NodeStore& nodes) {
  const PartSettings& part = parts_[block.part[e]];
  if (block.mass_scale.empty()) return element_time_step(length, c, volume_rate, part);
  Real& f = block.mass_scale[e];
  if (mass_scaling_.active) {
    const Real ratio = c / sound_speed_for_step(length, mass_scaling_.step, volume_rate, part);
    if (ratio * ratio > f) {
      const int per = block.nodes_per_element;
      const Real added = (ratio * ratio - f) * block.mass[e] / per;
      for (int a = 0; a < per; ++a) nodes.mass[nodes.node_row(node_[block.node[per * e + a]])] += added;
      f = ratio * ratio;
    }
  }
  return element_time_step(length, c / std::sqrt(f), volume_rate, part);
}

bool SolidElements::fails(Block& block, Index e, const Mat3& L, Real dt, Real stable_step) {
  if (erosion_step_ > 0 && stable_step < erosion_step_) return true;
  const PartSettings& part = parts_[block.part[e]];
  const Erosion& er = part.erosion;
  Mat3 strain = Mat3::Zero();
  Real effective = 0;
  if (!block.strain.empty()) {
    // Jaumann-rotated like the stress, so that a rigid rotation leaves it unchanged.
    const Mat3 D = Real(0.5) * (L + L.transpose());
    strain = block.strain[e] += dt * (D + materials::jaumann_rotation(L, block.strain[e]));
    effective = block.effective_strain[e] += dt * materials::effective_strain_rate(materials::deviator(D));
  }
  if (!may_erode_) return false;
  Vec3 principal_strain = Vec3::Zero();
  if (er.max_principal_strain || er.min_principal_strain) {
    Eigen::SelfAdjointEigenSolver<Mat3> solver;
    solver.computeDirect(strain, Eigen::EigenvaluesOnly);
    principal_strain = solver.eigenvalues();  // ascending
  }
  const Real volumetric =
      er.volumetric_strain ? std::log(block.volume[e] * part.material.density / block.mass[e]) : 0;
  int failed_points = 0;
  for (int g = 0; g < block.points_per_element; ++g) {
    const materials::PointState& state = block.state[block.points_per_element * e + g];
    const Real p = block.thermo[block.points_per_element * e + g].pressure;
    if (er.material_failure && materials::erodes_element(part.material, state)) {
      ++failed_points;
      continue;
    }
    int met = 0;
    if (er.max_pressure) met += p >= *er.max_pressure;
    if (er.min_pressure) met += p <= *er.min_pressure;
    if (er.von_mises) met += materials::von_mises(state.deviatoric_stress) >= *er.von_mises;
    if (er.max_principal_stress) {
      const Real sigma_1 = materials::max_principal_stress(state.deviatoric_stress - p * Mat3::Identity());
      met += sigma_1 >= *er.max_principal_stress;
    }
    if (er.max_principal_strain) met += principal_strain[2] >= *er.max_principal_strain;
    if (er.min_principal_strain) met += principal_strain[0] <= *er.min_principal_strain;
    if (er.effective_strain) met += effective >= *er.effective_strain;
    if (er.volumetric_strain)
      met += *er.volumetric_strain > 0 ? volumetric >= *er.volumetric_strain : volumetric <= *er.volumetric_strain;
    if (er.failure_time) met += time_ >= *er.failure_time;
    failed_points += met >= er.criteria;
  }
  return failed_points >= er.points;
}

void SolidElements::remove_eroded(discretization::NodeStore& nodes) {
  // The energies and mass taken out, each an exact sum over the elements of the rank's own, then
  // over the ranks: the same for any partition.
  // Kinetic energy, internal energy, mass, then the internal and the kinetic energy of each part.
  const std::size_t parts = parts_.size();
  std::vector<ExactSum> taken(3 + 2 * parts);
  for (std::size_t k_block = 0; k_block < blocks_.size(); ++k_block) {
    Block& block = blocks_[k_block];
    const int per = block.nodes_per_element, points = block.points_per_element;
    // In element order: a node's mass loses its elements' shares in the serial order (a rank
    // computes every element on its own nodes, and sets only 1 on those it computes).
    const parallel::Range elements = held(k_block);
    for (Index e = elements.begin; e < elements.end; ++e) {
      if (block.eroded[e] != 1) continue;
      block.eroded[e] = 2;
      const PartSettings& part = parts_[block.part[e]];
      const Real m = block.mass[e];
      // What its nodes lose: the mass DT2MS added too.
      const Real nodal = (block.mass_scale.empty() ? m : block.mass_scale[e] * m) / per;
      const bool owned = books(block, e);
      Real internal = 0;
      for (int g = 0; g < points; ++g)
        internal += block.thermo[points * e + g].specific_energy - part.material.initial_specific_energy;
      if (owned) {
        eroded_now_.push_back(block.id[e]);
        taken[1] += m * internal / points;
        taken[2] += m;
        taken[3 + static_cast<std::size_t>(block.part[e])] += m * internal / points;
      }
      for (int a = 0; a < per; ++a) {
        const Index k = block.node[per * e + a], i = nodes.node_row(node_[k]);
        if (owned) {
          const Real kinetic = Real(0.5) * nodal * nodes.v[i].squaredNorm();
          taken[0] += kinetic;
          taken[3 + parts + static_cast<std::size_t>(block.part[e])] += kinetic;
        }
        nodes.mass[i] -= nodal;
        if (--live_elements_[k] == 0) {
          nodes.mass[i] = other_mass_[k];  // the share of other formulations, exactly
          if (!(nodes.mass[i] > 0)) nodes.mass[i] = 0, nodes.active[i] = 0;
        }
      }
    }
  }
  if (share_) {
    parallel::world().sum(taken);
    eroded_now_ = parallel::world().all(std::span<const Id>(eroded_now_));
  }
  std::sort(eroded_now_.begin(), eroded_now_.end());
  eroded_kinetic_step_ = taken[0].value();
  eroded_internal_step_ = taken[1].value();
  eroded_mass_ += taken[2].value();
  for (std::size_t p = 0; p < parts; ++p) {
    eroded_internal_by_part_[p] = taken[3 + p].value();
    eroded_kinetic_by_part_[p] = taken[3 + parts + p].value();
  }
}

void SolidElements::Block::hold(parallel::Range elements) {
  carried_state([&](auto& array, int per) { array.hold(per * elements.begin, per * elements.end); });
  hourglass_power.hold(elements.begin, elements.end);
}

namespace {

// Each element's values of a state array (`per` an element) from the rank `arrivals` planned to
// send it.
template <typename T>
void bring(const discretization::ReachShare& arrivals, RangeArray<T>& array, int per) {
  if (array.empty()) return;
  for (int g = 0; g < per; ++g)
    arrivals.records<T>([&](Index e) { return array[per * e + g]; },
                        [&](Index e, const T& value) { array[per * e + g] = value; });
}

}  // namespace

SolidElements::Share SolidElements::plan_share(const discretization::NodeStore& nodes) const {
  Share s;
  s.partition = nodes.partition;
  s.nodes.bind(nodes);
  std::vector<std::uint8_t> reads(node_.size(), 0);  // the local nodes of the elements computed here
  for (const Block& block : blocks_) {
    const int per = block.nodes_per_element;
    std::vector<std::uint8_t> computed(block.size(), 0);
    Share::Computed& mine = s.blocks.emplace_back();
    mine.held = {block.size(), 0};
    for (Index e = 0; e < block.size(); ++e) {
      for (int a = 0; a < per; ++a) computed[e] |= s.nodes.owns(node_[block.node[per * e + a]]);
      if (!computed[e]) continue;
      for (int a = 0; a < per; ++a) reads[block.node[per * e + a]] = 1;
      mine.held = {std::min(mine.held.begin, e), std::max(mine.held.end, e + 1)};
    }
    if (mine.held.begin >= mine.held.end) mine.held = {0, 0};
    // The block's colours, each restricted to the elements computed here.
    mine.offset.push_back(0);
    for (std::size_t c = 0; c + 1 < block.colour_offset.size(); ++c) {
      for (Index j = block.colour_offset[c]; j < block.colour_offset[c + 1]; ++j)
        if (computed[block.colour_element[j]]) mine.element.push_back(block.colour_element[j]);
      mine.offset.push_back(static_cast<Index>(mine.element.size()));
    }
  }
  const auto first = std::find(reads.begin(), reads.end(), 1);
  const auto last = std::find(reads.rbegin(), reads.rend(), 1);
  if (first != reads.end())
    s.forces = {static_cast<Index>(first - reads.begin()), static_cast<Index>(reads.rend() - last)};
  if (!nodes.velocities_by_reach) return s;
  s.velocities.plan(reads, node_, s.nodes, nodes);
  s.places_read = {nodes.rank_begin[nodes.rank], nodes.rank_begin[nodes.rank + 1]};
  for (std::size_t k = 0; k < node_.size(); ++k)
    if (reads[k]) s.places_read = parallel::hull(s.places_read, {node_[k], node_[k] + 1});
  return s;
}

void SolidElements::hold_nodes(discretization::NodeStore& nodes) const {
  if (nodes.window_by_reads) nodes.hold_window(share_->places_read.begin, share_->places_read.end);
}

void SolidElements::distribute(discretization::NodeStore& nodes) {
  if (parallel::world().size() == 1) return;
  if (share_ && share_->partition == nodes.partition) {
    if (!nodes.windowed()) hold_nodes(nodes);  // every node, as a restart file was read into them
    return;
  }
  refresh_nodes(nodes);  // from the deal before, which share_ was made for
  std::optional<Share> before = std::move(share_);
  share_ = plan_share(nodes);
  hold_nodes(nodes);  // the rows it lacks from their new ranks, whose own are current now
  if (!state_set_up_) {
    set_up_state(nodes);
    return;
  }
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    Block& block = blocks_[k];
    const Share::Computed& mine = share_->blocks[k];
    if (before) {
      // The elements computed here anew, from the owners of their first nodes in the deal before
      // (who computed them); the arrays hold the old stretch (what this rank sends) and the new
      // (what it receives) while they travel.
      std::vector<std::uint8_t> computed(block.size(), 0);
      for (const Index e : mine.element) computed[e] = 1;
      std::vector<Index> first(block.size());
      for (Index e = 0; e < block.size(); ++e) first[e] = node_[block.node[block.nodes_per_element * e]];
      discretization::ReachShare arrivals;
      arrivals.plan_by_place(computed, first, before->nodes, [](Index e) { return e; }, {0, block.size()});
      block.hold(parallel::hull(before->blocks[k].held, mine.held));
      block.carried_state([&](auto& array, int values) { bring(arrivals, array, values); });
    }
    block.hold(mine.held);
  }
  force_.hold(share_->forces.begin, share_->forces.end);  // each step's anew
  bulk_force_.hold(share_->forces.begin, share_->forces.end);
}

namespace {

// A local node's state as it travels to a rank that holds its row (explicit padding: no unset byte
// travels).
struct NodeState {
  Vec3 x, v;
  Real mass;
  std::int32_t live_elements;
  std::uint8_t active, padding[3];
};

}  // namespace

void SolidElements::refresh_nodes(discretization::NodeStore& nodes) {
  if (!share_ || !nodes.velocities_by_reach) return;
  discretization::ReachShare arrivals;
  arrivals.plan_held(node_, share_->nodes, nodes);
  arrivals.records<NodeState>(
      [&](Index k) {
        const Index i = nodes.node_row(node_[k]);
        return NodeState{nodes.x[i], nodes.v[i], nodes.mass[i], live_elements_[k], nodes.active[i], {0, 0, 0}};
      },
      [&](Index k, const NodeState& s) {
        const Index i = nodes.node_row(node_[k]);
        nodes.x[i] = s.x, nodes.v[i] = s.v, nodes.mass[i] = s.mass, nodes.active[i] = s.active;
        live_elements_[k] = s.live_elements;
      });
}

void SolidElements::share_state(discretization::NodeStore& nodes) {
  if (!share_ || !nodes.velocities_by_reach) return;
  share_->velocities.records<Vec3>([&](Index k) { return nodes.v[nodes.node_row(node_[k])]; },
                                   [&](Index k, const Vec3& v) { nodes.v[nodes.node_row(node_[k])] = v; });
}

parallel::Range SolidElements::rows_read(const discretization::NodeStore& nodes) const {
  if (!share_ || !nodes.velocities_by_reach) return {0, nodes.size()};
  // The rows hold those places: the window is held over them, or a new deal's hull over them.
  return {share_->places_read.begin - nodes.window_first(), share_->places_read.end - nodes.window_first()};
}

// A checkpoint gets each element's state from the rank that books it (checkpoint), and each row
// from its rank where the rows are a window (NodeStore::checkpoint); rank 0 writes every local
// node's live element count.
void SolidElements::complete_state(discretization::NodeStore& nodes) {
  if (!nodes.windowed()) return refresh_nodes(nodes);
  if (share_) share_->nodes(node_, live_elements_);
}

void SolidElements::share_masses(discretization::NodeStore& nodes) {
  share_->nodes(node_, live_elements_);
  const parallel::Communicator& ranks = parallel::world();
  ranks.share(std::span(nodes.mass), nodes.rank_begin);
  ranks.share(std::span(nodes.active), nodes.rank_begin);
}

void SolidElements::compute_forces(discretization::NodeStore& nodes, Real dt) {
  distribute(nodes);
  const parallel::Range forces = forces_held();
  parallel::for_each(forces.size(), [&](Index j) {
    force_[forces.begin + j] = bulk_force_[forces.begin + j] = Vec3::Zero();
  }, element_loops);
  time_ += dt;
  eroded_kinetic_step_ = eroded_internal_step_ = 0;
  std::fill(eroded_internal_by_part_.begin(), eroded_internal_by_part_.end(), Real(0));
  std::fill(eroded_kinetic_by_part_.begin(), eroded_kinetic_by_part_.end(), Real(0));
  eroded_now_.clear();
  struct Found {
    Real step;
    Real sound_speed;
    Index eroding;  // elements deleted during this step
  };
  const auto combine = [](const Found& x, const Found& y) {
    return Found{std::min(x.step, y.step), std::max(x.sound_speed, y.sound_speed), x.eroding + y.eroding};
  };
  const Found none{std::numeric_limits<Real>::infinity(), 0, 0};
  Found found = none;
  parallel::LowestIndex inverted;
  for (std::size_t k_block = 0; k_block < blocks_.size(); ++k_block) {
    Block& block = blocks_[k_block];
    Index inverted_colour = -1;
    // What one element's step tells: its stable step, or that it was deleted or inverted.
    const auto outcome = [&](Index e, Real step) {
      if (step == -2 || (step == -1 && erode_enabled_)) {  // deleted: no forces from now on
        block.eroded[e] = 1;
        return Found{std::numeric_limits<Real>::infinity(), 0, 1};
      }
      if (step < 0) {
        inverted.report(e);
        return none;
      }
      return Found{step, block.thermo[block.points_per_element * e].sound_speed, 0};
    };
    // The elements this rank computes, colour by colour.
    const std::vector<Index>& offset = share_ ? share_->blocks[k_block].offset : block.colour_offset;
    const std::vector<Index>& computed = share_ ? share_->blocks[k_block].element : block.colour_element;
    const auto run = [&]<Kind kind>() {
      for (std::size_t c = 0; c + 1 < offset.size(); ++c) {
        const Index begin = offset[c], size = offset[c + 1] - begin;
        const Index* colour = computed.data() + begin;
        if constexpr (kind == Kind::hexahedron) {
          // The colour's elements a pack of lanes at a time, each run of one part together.
          found = combine(found, parallel::reduce_exact((size + lanes - 1) / lanes, none, [&](Index j) {
            Index live[lanes];
            int count = 0;
            for (Index k = j * lanes; k < std::min(size, (j + 1) * lanes); ++k)
              if (!block.eroded[colour[k]]) live[count++] = colour[k];
            Found result = none;
            Real steps[lanes];
            for (int first = 0, last; first < count; first = last) {
              for (last = first + 1; last < count && block.part[live[last]] == block.part[live[first]];) ++last;
              hexahedra(block, live + first, last - first, nodes, dt, steps + first);
            }
            for (int l = 0; l < count; ++l) result = combine(result, outcome(live[l], steps[l]));
            return result;
          }, combine, element_loops));
        } else {
          found = combine(found, parallel::reduce_exact(size, none, [&](Index j) {
            const Index e = colour[j];
            if (block.eroded[e]) return none;
            return outcome(e, element_step<kind>(block, e, nodes, dt));
          }, combine, element_loops));
        }
        if (inverted.value() >= 0) {
          inverted_colour = static_cast<Index>(c);
          break;
        }
      }
    };
    switch (block.kind) {
      case Kind::hexahedron: run.template operator()<Kind::hexahedron>(); break;
      case Kind::hexahedron_selective_reduced: run.template operator()<Kind::hexahedron_selective_reduced>(); break;
      case Kind::tetrahedron: run.template operator()<Kind::tetrahedron>(); break;
    }
    Index e = inverted.value();
    if (share_) {  // the lowest of the first colour with one, over the ranks: as one process finds it
      const Index colour = parallel::world().lowest(inverted_colour);
      if (colour >= 0) e = parallel::world().lowest(inverted_colour == colour ? e : -1);
    }
    if (e >= 0)
      throw InstabilityError(fmt::format("FEM part {}: element {} has a negative volume: it inverted (*CONTROL_TIMESTEP "
                                         "ERODE 1 deletes inverted elements instead; a smaller TSSFAC or a finer mesh "
                                         "may help)", parts_[block.part[e]].part_id, block.id[e]));
  }
  if (share_) {  // the smallest step, the fastest wave and whether an element eroded, over the ranks
    double values[3] = {found.step, -found.sound_speed, found.eroding > 0 ? -1.0 : 0.0};
    parallel::world().minimum(values);
    found = {values[0], -values[1], values[2] < 0 ? 1 : 0};
  }
  if (found.eroding > 0) remove_eroded(nodes);
  // With the velocities by reach only a node's rank reads its mass and activity, and they are whole
  // there (it computes every element on the node): they come in at a new deal and a checkpoint.
  if (share_ && !nodes.velocities_by_reach && (found.eroding > 0 || mass_scaling_.active)) share_masses(nodes);
  if (mass_scaling_.active) {
    // Over the elements each rank books (only those it computes are current there).
    Real added = 0;
    for (std::size_t k = 0; k < blocks_.size(); ++k) {
      const Block& block = blocks_[k];
      const parallel::Range elements = held(k);
      added += parallel::exact_sum(elements.size(), [&](Index j) {
        const Index e = elements.begin + j;
        return books(block, e) ? (block.mass_scale[e] - 1) * block.mass[e] : Real(0);
      }, share_ ? &parallel::world() : nullptr);
    }
    mass_scaling_.record(added);
  } else {
    mass_scaling_.idle();
  }
  parallel::for_each(forces.size(), [&](Index j) {
    if (const Index k = forces.begin + j; owns(k)) nodes.f[nodes.node_row(node_[k])] += force_[k];
  }, element_loops);
  stable_step_ = found.step;
  max_sound_speed_ = found.sound_speed;
}

Real SolidElements::stable_time_step(const discretization::NodeStore&) const { return stable_step_; }

bool SolidElements::scale_mass_below(Real step, bool first_step_only) {
  mass_scaling_.start(step, first_step_only);
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    RangeArray<Real>& scale = blocks_[k].mass_scale;
    scale.resize(0);  // on, holding nothing until set_up_state makes the held elements' 1
    if (!state_set_up_) continue;
    scale.hold(held(k).begin, held(k).end);
    scale.fill(1);
  }
  return true;
}

void SolidElements::sum_parts(discretization::PartSummary& parts, const discretization::NodeStore&) const {
  using Summary = discretization::PartSummary;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const Block& block = blocks_[k];
    const parallel::Range elements = held(k);
    for (Index e = elements.begin; e < elements.end; ++e) {
      if (!books(block, e)) continue;
      const Id part = parts_[block.part[e]].part_id;
      if (!block.hourglass_energy.empty() && !block.eroded[e])
        parts.add(part, Summary::hourglass_energy, block.hourglass_energy[e]);
      // As the ledger's added_mass: an eroded element's too.
      if (!block.mass_scale.empty()) parts.add(part, Summary::added_mass, (block.mass_scale[e] - 1) * block.mass[e]);
    }
  }
}

void SolidElements::book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                                  std::span<const Vec3> v, Real dt) const {
  using Ledger = discretization::EnergyLedger;
  // The work of the internal forces and of the bulk viscosity's share at the mid-step velocities;
  // the hourglass control's dissipation at each element's own rates (as LS-DYNA books it; an exact
  // sum over the elements the rank books, then over the ranks). The rest is stored.
  const parallel::Range forces = forces_held();
  const Sums<2> work = parallel::exact_sum(forces.size(), [&](Index j) {
    Sums<2> w;
    const Index k = forces.begin + j;
    if (!owns(k)) return w;  // another rank's: its forces are whole only there
    const Vec3& u = v[nodes.node_row(node_[k])];
    w[0] = -force_[k].dot(u);
    w[1] = -bulk_force_[k].dot(u);
    return w;
  }, share_ ? &parallel::world() : nullptr);
  Real hourglass = 0;
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const Block& block = blocks_[k];
    if (block.hourglass_power.empty()) continue;
    const parallel::Range elements = held(k);
    hourglass += parallel::exact_sum(elements.size(), [&](Index j) {
      const Index e = elements.begin + j;
      return !block.eroded[e] && books(block, e) ? block.hourglass_power[e] : Real(0);
    }, share_ ? &parallel::world() : nullptr);
  }
  ledger.add(Ledger::internal_energy, Ledger::Role::stored, dt * (work[0] - work[1] - hourglass) - eroded_internal_step_);
  ledger.add(Ledger::artificial_viscosity_energy, Ledger::Role::dissipated, dt * work[1]);
  if (hourglass_) ledger.add(Ledger::hourglass_energy, Ledger::Role::dissipated, dt * hourglass);
  if (may_erode_ || erode_enabled_) {
    ledger.add(Ledger::eroded_kinetic_energy, Ledger::Role::dissipated, eroded_kinetic_step_);
    ledger.add(Ledger::eroded_internal_energy, Ledger::Role::dissipated, eroded_internal_step_);
    ledger.set(Ledger::eroded_mass, Ledger::Role::reported, eroded_mass_);
  }
  if (mass_scaling_.step > 0) ledger.add(Ledger::added_mass, Ledger::Role::reported, mass_scaling_.added_this_step);
  if (!ledger.part_ids().empty()) book_part_work(ledger, nodes, v, dt);
}

void SolidElements::book_part_work(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                                   std::span<const Vec3> v, Real dt) const {
  // *DATABASE_MATSUM: internal_energy as above, part by part: the stored work at each local node
  // under its part (node_part_), less each element's hourglass dissipation and, as it erodes, its
  // internal energy (collectives, only with the card). A node that parts share books its whole
  // work to one: an element's own work is not kept apart.
  const std::vector<Id>& ids = ledger.part_ids();
  std::vector<int> slot(parts_.size());  // parts_ -> the ledger's parts
  for (std::size_t p = 0; p < parts_.size(); ++p) slot[p] = ledger.part_slot(parts_[p].part_id);
  const parallel::Communicator* across = share_ ? &parallel::world() : nullptr;
  const parallel::Range forces = forces_held();
  std::vector<Real> work = parallel::exact_sums_by_group(
      forces.size(), static_cast<int>(ids.size()),
      [&](Index j) { return owns(forces.begin + j) ? slot[node_part_[forces.begin + j]] : -1; },
      [&](Index j) {
        const Index k = forces.begin + j;
        return -(force_[k] - bulk_force_[k]).dot(v[nodes.node_row(node_[k])]);
      },
      across);
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const Block& block = blocks_[k];
    if (block.hourglass_power.empty()) continue;
    const parallel::Range elements = held(k);
    const std::vector<Real> hourglass = parallel::exact_sums_by_group(
        elements.size(), static_cast<int>(ids.size()),
        [&](Index j) {
          const Index e = elements.begin + j;
          return !block.eroded[e] && books(block, e) ? slot[block.part[e]] : -1;
        },
        [&](Index j) { return block.hourglass_power[elements.begin + j]; }, across);
    for (std::size_t p = 0; p < ids.size(); ++p) work[p] -= hourglass[p];
  }
  for (std::size_t p = 0; p < parts_.size(); ++p) {
    if (slot[p] < 0) continue;
    const auto k = static_cast<std::size_t>(slot[p]);
    ledger.add_part_work(k, -eroded_internal_by_part_[p]);
    ledger.add_part_eroded(k, eroded_internal_by_part_[p], eroded_kinetic_by_part_[p]);
  }
  for (std::size_t p = 0; p < ids.size(); ++p) ledger.add_part_work(p, dt * work[p]);
}

// Each block's state in pieces (core/pieces.hpp): each rank writes the elements it books; read
// back, a rank keeps the stretch of those it computes (every element's where the nodes are not
// dealt).
void SolidElements::checkpoint(Archive& a, const discretization::NodeStore& nodes) {
  a.section("fem solids 2");
  a.expect_size("element blocks", blocks_.size());
  const parallel::Communicator& ranks = parallel::world();
  if (a.reading()) {
    // Read into nodes dealt already (a restart), a rank keeps the stretch it computes alone; a new
    // deal before the first step brings the others' from it (distribute).
    share_.reset();
    if (ranks.size() > 1 && (!nodes.rank_begin.empty() || nodes.by_region())) share_ = plan_share(nodes);
    state_set_up_ = true;
  } else if (!state_set_up_) {
    set_up_state(nodes);  // the set-up's, every element's before the nodes are dealt
  }
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    Block& block = blocks_[k];
    const Index n = block.size();
    a.expect_size("elements in a block", static_cast<std::size_t>(n));
    if (!a.reading()) {
      // Ascending; rank 0 every element until the nodes are dealt (the set-up's state).
      std::vector<Index> own;
      for (Index e = held(k).begin; e < held(k).end; ++e)
        if (share_ && share_->nodes.dealt() ? books(block, e) : ranks.rank() == 0) own.push_back(e);
      const Index count = static_cast<Index>(own.size());
      const auto element = [&](Index j) { return own[j]; };
      parallel::write_pieces<Index>(a, count, element, element, ranks);
      block.carried_state([&](const auto& array, int per) {
        const auto value = [&](Index j) { return per * own[j / per] + j % per; };  // its place in the array
        parallel::write_array_pieces(a, array, count * per, value, value, ranks);
      });
      continue;
    }
    std::vector<Index> element;  // each piece's elements, in the file's order
    std::vector<std::uint8_t> read(n, 0);
    Index mismatch = -1;
    parallel::read_pieces<Index>(a, [&](Index e) {
      if ((e < 0 || e >= n || read[e]) && mismatch < 0) mismatch = e;
      if (e >= 0 && e < n) read[e] = 1;
      element.push_back(e);
    });
    if (mismatch < 0 && std::find(read.begin(), read.end(), 0) != read.end()) mismatch = n;
    if (mismatch >= 0)
      throw InputError(fmt::format("{}: the checkpoint does not match this deck (its solid elements are not this "
                                   "deck's)", a.source()));
    block.carried_state([&](auto& array, int per) {
      const parallel::Range values{per * held(k).begin, per * held(k).end};  // each written at its own index
      parallel::read_array_pieces(a, array, per * n, values, [&](Index j) { return per * element[j / per] + j % per; },
                                  values);
    });
    block.hourglass_power.hold(held(k).begin, held(k).end);  // each step's anew
  }
  if (a.reading()) {  // each step's anew, before the energies read them
    force_.resize(0), bulk_force_.resize(0);
    force_.hold(forces_held().begin, forces_held().end);
    bulk_force_.hold(forces_held().begin, forces_held().end);
  }
  a(stable_step_, max_sound_speed_, time_, erosion_step_, live_elements_, other_mass_, eroded_kinetic_step_,
    eroded_internal_step_, eroded_mass_, mass_scaling_, erode_enabled_);
}

namespace {

// An element's stress as elout.csv and the field output give it: the mean over its integration
// points (the Gauss points carry equal weight to round-off for an element that is not badly
// distorted), in Voigt order xx yy zz xy yz zx.
struct MeanState {
  std::array<Real, 6> stress{};
  Real pressure = 0, von_mises = 0, plastic_strain = 0;
};

template <class Block>
MeanState mean_state(const Block& block, Index e) {
  const int points = block.points_per_element;
  Mat3 S = Mat3::Zero();
  MeanState mean;
  for (int g = 0; g < points; ++g) {
    S += block.state[points * e + g].deviatoric_stress;
    mean.pressure += block.thermo[points * e + g].pressure;
    mean.plastic_strain += block.state[points * e + g].plastic_strain;
  }
  S /= points;
  mean.pressure /= points;
  mean.plastic_strain /= points;
  const Mat3 sigma = S - mean.pressure * Mat3::Identity();
  mean.stress = {sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(2, 0)};
  mean.von_mises = materials::von_mises(S);
  return mean;
}

}  // namespace

void SolidElements::write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const {
  for (std::size_t k = 0; k < blocks_.size(); ++k) {
    const Block& block = blocks_[k];
    auto& cells = fields.add_cell_block(block.kind == Kind::tetrahedron ? discretization::CellShape::tetrahedron
                                                                        : discretization::CellShape::hexahedron);
    const int per = block.nodes_per_element;
    // The elements whose first node this rank owns: its piece's cells (all of them on one process).
    std::vector<Index> written;
    for (Index e = held(k).begin; e < held(k).end; ++e)
      if (books(block, e)) written.push_back(e);
    const Index n = static_cast<Index>(written.size());
    cells.connectivity.resize(static_cast<std::size_t>(per) * n);
    for (Index c = 0; c < n; ++c)
      for (int k = 0; k < per; ++k)
        cells.connectivity[per * c + k] = nodes.node_row(node_[block.node[per * written[c] + k]]);
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
    if (may_erode_ || erode_enabled_) {
      auto& eroded = cells.fields.emplace_back();
      eroded.name = "eroded";
      auto& flags = eroded.values.emplace<std::vector<std::int64_t>>(n);
      for (Index c = 0; c < n; ++c) flags[c] = block.eroded[written[c]] != 0;
    }
    auto& ids = cells.fields.emplace_back();
    ids.name = "element_id";
    auto& id = ids.values.emplace<std::vector<std::int64_t>>(n);
    for (Index c = 0; c < n; ++c) id[c] = block.id[written[c]];
    for (Index c = 0; c < n; ++c) {
      const Index e = written[c];
      const MeanState mean = mean_state(block, e);
      std::copy(mean.stress.begin(), mean.stress.end(), stress + 6 * c);
      pressure[c] = mean.pressure;
      von_mises[c] = mean.von_mises;
      plastic_strain[c] = mean.plastic_strain;
      density[c] = block.mass[e] / block.volume[e];
      if (hourglass) hourglass[c] = block.hourglass_energy[e];
    }
  }
}

void SolidElements::follow_elements(std::span<const Id> ids, std::vector<std::uint8_t>& taken) {
  std::map<Id, std::size_t> place;
  for (std::size_t k = 0; k < ids.size(); ++k) place.emplace(ids[k], k);
  followed_.clear();
  for (std::size_t k = 0; k < blocks_.size(); ++k)
    for (Index e = 0; e < blocks_[k].size(); ++e)
      if (const auto it = place.find(blocks_[k].id[e]); it != place.end()) {
        followed_.push_back({k, e, it->second});
        taken[it->second] = 1;
      }
}

void SolidElements::element_histories(std::span<double> values) const {
  for (const Followed& f : followed_) {
    const Block& block = blocks_[f.block];
    const parallel::Range held_here = held(f.block);
    if (f.element < held_here.begin || f.element >= held_here.end || !books(block, f.element)) continue;
    const MeanState mean = mean_state(block, f.element);
    double* out = &values[discretization::element_history_values * f.place];
    std::copy(mean.stress.begin(), mean.stress.end(), out);
    out[6] = mean.pressure;
    out[7] = mean.von_mises;
    out[8] = mean.plastic_strain;
    out[9] = block.eroded[f.element] != 0 ? 1 : 0;
  }
}

void SolidElements::add_nodal_masses(discretization::NodeStore& nodes) {
  other_mass_.resize(node_.size());
  for (std::size_t k = 0; k < node_.size(); ++k) other_mass_[k] = nodes.mass[nodes.node_row(node_[k])];
  for (const Block& block : blocks_)
    for (Index e = 0; e < block.size(); ++e)
      for (int a = 0; a < block.nodes_per_element; ++a)
        nodes.mass[nodes.node_row(node_[block.node[block.nodes_per_element * e + a]])] +=
            block.mass[e] / block.nodes_per_element;
}

Index SolidElements::eroded_count() const {
  Index n = 0;
  for (std::size_t k = 0; k < blocks_.size(); ++k)
    for (Index e = held(k).begin; e < held(k).end; ++e) n += blocks_[k].eroded[e] != 0 && books(blocks_[k], e);
  return n;
}

Index SolidElements::element_count() const {
  Index n = 0;
  for (const Block& block : blocks_) n += block.size();
  return n;
}

std::size_t SolidElements::memory_bytes() const {
  std::size_t total = bytes(node_) + force_.capacity_bytes() + bulk_force_.capacity_bytes() +
                      bytes(live_elements_) + bytes(other_mass_);
  for (const Block& b : blocks_) {
    total += bytes(b.node) + bytes(b.part) + bytes(b.id) + bytes(b.mass) + bytes(b.colour_offset) +
             bytes(b.colour_element) + b.hourglass_power.capacity_bytes();
    b.carried_state([&](const auto& array, int) { total += array.capacity_bytes(); });
  }
  if (share_)
    for (const Share::Computed& c : share_->blocks) total += bytes(c.offset) + bytes(c.element);
  return total;
}

}  // namespace spall::fem
