#include "spall/spg/part.hpp"

#include <algorithm>
#include <cmath>
#include <fmt/format.h>
#include <limits>
#include <numeric>
#include <span>

#include "spall/core/bounding_box.hpp"
#include "spall/core/cube_root.hpp"
#include "spall/core/log.hpp"
#include "spall/core/pieces.hpp"
#include "spall/neighbors/near_particles.hpp"
#include "spall/spg/parallel.hpp"
#include "spall/spg/rk_shape.hpp"

namespace spall::spg {

namespace {

// Stable step dt = alpha h / (c + |v|), h the nodal spacing (support size over DX) scaled with the
// particle's volume change. The largest frequency of the assembled system on irregular blocks
// (tests/unit/test_spg_stiffness.cpp) puts the critical step at 0.94 to 1.25 h / c for ISPLINE 0-2,
// DX 1.2-2.4 and Poisson's ratios up to 0.49; alpha = 0.5 keeps the step at TSSFAC 1 below 0.75
// of it everywhere (THEORY §9.6).
constexpr Real courant_factor = 0.5;

// Conjugate-residual iterations of the integration-constraint correction (THEORY §9.4).
constexpr int setup_iterations = 2000;
constexpr int update_iterations = 25;

// The half-widths along the axes of the box that holds the window of half-widths a carried by the
// deformation F: the ellipsoid {F diag(a) u : |u| <= 1} reaches sqrt(sum_k F_dk^2 a_k^2) along axis
// d. A rotation leaves it at a; a stretch widens it as far as the material and its particles went.
Vec3 window_extent(const Mat3& F, const Vec3& a) { return (F * a.asDiagonal()).rowwise().norm(); }

// KERNEL 1 and 2 windows (THEORY §9.7) widen with the stretch up to this many times their first
// size, which bounds the neighbour search; they never narrow, so KERNEL 1's step keeps following the
// first spacing (windows squeezed with the material would need a step as narrow as they are: ten
// times shorter at the foot of a Taylor bar at 350 m/s; KERNEL 2's first bonds need it anyway,
// current_spacing). A Taylor bar at 350 m/s needs 3 with KERNEL 2 (test_spg_taylor_bar.cpp).
constexpr Real max_window_growth = 4;

// The node's spacing in each direction: a direction in which the elements around it have no extent
// (a flat patch) takes the largest spacing of the other two.
Vec3 nodal_spacing(const ParticleSetup& p) {
  Vec3 h = p.spacing;
  for (int d = 0; d < 3; ++d)
    if (!(h[d] > 0)) h[d] = p.spacing.maxCoeff();
  return h;
}

// The longitudinal wave speed of the material at rest: its density and initial specific energy.
Real reference_sound_speed(const materials::Material& mat) {
  return materials::sound_speed(mat, mat.density, mat.initial_specific_energy);
}

template <typename T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

}  // namespace

Part::Part(PartSettings settings, const std::vector<ParticleSetup>& particles, const discretization::NodeStore& nodes,
           const parallel::Communicator* across)
    : settings_(std::move(settings)) {
  const auto& mat = settings_.material;
  // Set up in blocks, this rank's particles follow those of the ranks before it in node order.
  const Index held = static_cast<Index>(particles.size());
  Index first = 0;
  if (across) {
    const std::vector<Index> counts = across->each(held);
    first = std::accumulate(counts.begin(), counts.begin() + across->rank(), Index(0));
  }
  node_.resize(held);
  for (Index k = 0; k < held; ++k) node_[k] = particles[k].node;
  if (across) node_ = across->all(std::span<const Index>(node_));  // each particle's node's place, every rank's
  const Index count = particle_count();
  // Every particle is this rank's own until the nodes are dealt; set up in blocks, those of its block.
  own_ = read_ = smoothed_ = {first, first + held};
  // The state held by stretch on, holding no particle until hold_state, the constants set up from
  // `particles` for the particles held (under MPI each rank its own at its first deal, the others'
  // coming from their ranks: particles_at_set_up_); but the windows and sound speeds, which the
  // first deal's search and the runaway check read, set up here for the particles given.
  visit_held_state(*this, [](auto& array, const auto&) { array.resize(0); });
  if (!materials::keeps_back_stress(mat)) back_stress_.clear();
  mass_scale_.clear();  // on with DT2MS (scale_mass_below)
  support_.hold_afresh(own_.begin, own_.end);
  for (Index i = own_.begin; i < own_.end; ++i)
    support_[i] = settings_.dilation.cwiseProduct(nodal_spacing(particles[i - first]));
  sound_speed_.hold_afresh(own_.begin, own_.end, reference_sound_speed(mat));
  x_.resize(0), v_.resize(0);

  // Under MPI each rank searches the bonds of its own particles, holds the rows and the state of
  // the particles it reads and builds the shape functions and correction of its own particles' rows
  // at the first deal (compute_forces), where the set-up would build every particle's and every
  // row's on every rank: the bonds take 17 B a bond, the shape functions 56 B, the state about
  // 650 B a particle.
  set_up_pending_ = parallel::world().size() > 1;
  if (set_up_pending_) {
    particles_at_set_up_ = particles;
    set_up_first_ = first;
    return;
  }
  x_.hold_afresh(0, count), v_.hold_afresh(0, count, Vec3::Zero());
  for (Index i = 0; i < count; ++i) x_[i] = nodes.x[node_[i]];
  search_bonds(nullptr);
  link_mirrors(bonds_, own_);
  hold_state(read_);
  set_up_constants(particles, 0, read_);
  set_up_shape_functions(nodes);
}

template <typename Self, typename Visit>
void Part::visit_carried_state(Self& part, Visit&& visit) {
  const Mat3 identity = Mat3::Identity(), zero = Mat3::Zero();
  const Vec3 none = Vec3::Zero();
  visit(part.F_, identity), visit(part.F_total_, identity), visit(part.spin_, zero);
  visit(part.state_, materials::initial_state(part.settings_.material)), visit(part.back_stress_, zero);
  visit(part.stabilization_force_, none);
  visit(part.psi_self_, Real(0)), visit(part.grad_self_, none);
  visit(part.correction_.self, none), visit(part.correction_.lambda, none), visit(part.correction_.mu, zero);
  visit(part.correction_.alpha, none), visit(part.correction_.beta, zero), visit(part.correction_.reference, none);
  const auto& mat = part.settings_.material;
  visit(part.specific_energy_, mat.initial_specific_energy), visit(part.density_, mat.density);
  visit(part.pressure_, materials::eos_pressure(mat, mat.density, mat.initial_specific_energy));
  visit(part.viscous_pressure_, Real(0)), visit(part.viscous_power_, Real(0));
  visit(part.sound_speed_, reference_sound_speed(mat));
  visit(part.degraded_, std::uint8_t(0)), visit(part.mass_scale_, Real(1));
  // The constants (and the volume and window, updated at each kernel update) come with the particle
  // from the rank that holds it, set up for every particle in the constructor: never fresh.
  visit(part.volume0_, Real(0)), visit(part.volume_ref_, Real(0)), visit(part.support_, none);
  visit(part.initial_support_, none);
  visit(part.spacing_, Real(0)), visit(part.mean_spacing_, Real(0)), visit(part.stiffness_, Real(0));
  visit(part.dashpot_, Real(0)), visit(part.initial_bond_count_, Index(0)), visit(part.on_surface_, std::uint8_t(0));
}

template <typename Self, typename Visit>
void Part::visit_held_state(Self& part, Visit&& visit) {
  visit_carried_state(part, visit);
  const Vec3 none = Vec3::Zero();
  visit(part.stabilization_total_, none), visit(part.stabilization_power_, Real(0));
  visit(part.xs_, none), visit(part.vs_, none), visit(part.h_, none), visit(part.force_, none);
  visit(part.weighted_stress_, Mat3::Zero());
}

void Part::hold_state(parallel::Range particles) {
  visit_held_state(*this, [&](auto& array, const auto& fresh) { array.hold(particles.begin, particles.end, fresh); });
}

void Part::set_up_constants(const std::vector<ParticleSetup>& setup, Index first, parallel::Range particles) {
  const auto& mat = settings_.material;
  // K + 4G/3 of the reference state, from its longitudinal wave speed.
  const Real c0 = reference_sound_speed(mat);
  const Real p_wave_modulus = mat.density * c0 * c0;
  for (Index i = particles.begin; i < particles.end; ++i) {
    const ParticleSetup& p = setup[i - first];
    const Vec3 h = nodal_spacing(p);
    volume0_[i] = volume_ref_[i] = p.volume;
    initial_support_[i] = settings_.dilation.cwiseProduct(h);
    spacing_[i] = h.minCoeff();
    mean_spacing_[i] = std::cbrt(h.prod());
    stiffness_[i] = settings_.stabilization_factor * p_wave_modulus * p.volume / (mean_spacing_[i] * mean_spacing_[i]);
    dashpot_[i] = 2 * settings_.stabilization_damping * std::sqrt(stiffness_[i] * mass(i));
    on_surface_[i] = p.on_surface ? 1 : 0;
  }
}

void Part::set_up_shape_functions(const discretization::NodeStore& nodes) {
  if (const Index j = build_shape_functions(true); j >= 0)
    throw InputError(settings_.where, "*SECTION_SOLID_SPG",
                     fmt::format("part {}: node {} has {} particles in its kernel support, too few (or "
                                 "all in one plane) for linear RK shape functions (singular moment "
                                 "matrix); increase DX/DY/DZ or refine the mesh",
                                 settings_.part_id, node_id(nodes, j), bonds_.count(j) + 1));
  correct_integration_constraint(true);
  // The set-up's solve is the patch test of the mesh as given: the user is told how far it got.
  if (correction_.iterations == 0)
    log::info(fmt::format("part {}: SPG integration constraint met by the particles as they are (no correction)",
                          settings_.part_id));
  else if (correction_.iterations < setup_iterations)
    log::info(fmt::format("part {}: SPG integration constraint met in {} iterations (residual {:.1e} of the "
                          "defect)", settings_.part_id, correction_.iterations, correction_.relative_residual));
  else
    log::info(fmt::format("part {}: SPG integration constraint met to {:.1e} of the defect after {} iterations, "
                          "unconverged (its solve slows with the body's size in particle spacings, THEORY §9.4); "
                          "the patch test holds to that", settings_.part_id, correction_.relative_residual,
                          correction_.iterations));
  set_up_pending_ = false;
}

Id Part::node_id(const discretization::NodeStore& nodes, Index particle) const {
  double id = owns(particle) ? static_cast<double>(nodes.id[nodes.node_row(node_[particle])])
                             : std::numeric_limits<double>::infinity();
  parallel::world().minimum({&id, 1});
  return static_cast<Id>(id);
}

// Bonds: the pairs in which one particle lies inside the other's support, in the current positions.
// Each rank searches the rows of its own particles; under MPI every row's length comes in (the
// offsets are every row's), and the rows a rank reads follow (take_read_rows).
Real Part::search_radius() const {
  Real radius = 0;
  for (Index a = own_.begin; a < own_.end; ++a) radius = std::max(radius, support_radius(settings_.shape, support_[a]));
  return parallel::world().largest(radius);
}

void Part::search_bonds(const BondList* previous, const std::vector<Index>* near) {
  const Real radius = search_radius();
  neighbors::VerletList verlet;
  neighbors::NeighborList found;  // of the particles `near`, by particle
  if (!near) {
    verlet.build(x_.view(particle_count()).every(), radius, 0, own_);  // one process: every particle's
  } else {
    // The rows are ascending in the particles' order, which `near` keeps: the same rows as a search
    // among every particle's positions.
    std::vector<Vec3> x(near->size());
    for (std::size_t k = 0; k < near->size(); ++k) x[k] = x_[(*near)[k]];
    const Index first = static_cast<Index>(std::lower_bound(near->begin(), near->end(), own_.begin) - near->begin());
    found.offsets.assign(particle_count() + 1, 0);
    if (!near->empty()) {
      verlet.build(x, radius, 0, {first, first + own_.size()});
      const neighbors::NeighborList& local = verlet.list();
      for (Index a = own_.begin; a < own_.end; ++a) {
        const Index row = first + a - own_.begin;
        for (Index k = local.offsets[row]; k < local.offsets[row + 1]; ++k)
          found.neighbors.push_back((*near)[local.neighbors[k]]);
        found.offsets[a + 1] = static_cast<Index>(found.neighbors.size());
      }
      std::fill(found.offsets.begin() + own_.end + 1, found.offsets.end(), found.offsets[own_.end]);
    }
  }
  const neighbors::NeighborList& list = near ? found : verlet.list();
  const auto shape = settings_.shape;
  auto covers = [&](Index i, Index j) {
    return kernel_value(shape, x_[i] - x_[j], support_[j]).value > 0 ||
           kernel_value(shape, x_[j] - x_[i], support_[i]).value > 0;
  };
  std::vector<Index> length = bond_row_lengths(list, covers, own_);
  share_(node_, length);
  BondList bonds;
  bonds.offsets = row_offsets(length);
  bonds.neighbour.resize(0), bonds.broken.resize(0), bonds.rest_length.resize(0);
  bonds.hold(bonds.entries(own_));
  fill_bond_rows(bonds, list, x_.view(particle_count()), covers, previous, broken_pairs_, own_);
  bonds_ = std::move(bonds);
  if (previous) return;
  // The set-up's rows, which bond_damage counts against.
  initial_bond_count_.resize(particle_count());
  for (Index i = 0; i < particle_count(); ++i) initial_bond_count_[i] = bonds_.count(i);
}

void Part::bring_bond_rows(const discretization::ReachShare& from, parallel::Range particles) {
  const parallel::Range held{bonds_.neighbour.held_begin(), bonds_.neighbour.held_end()};
  bonds_.hold(parallel::hull(held, bonds_.entries(particles)));
  from.rows(bonds_.offsets, bonds_.neighbour, bonds_.broken, bonds_.rest_length);
}

std::vector<Index> Part::bring_neighbourhood(discretization::NodeStore& nodes) {
  const parallel::Communicator& ranks = parallel::world();
  // A bond joins particles closer than the search radius R: the rows read are within R of a rank's
  // own particles, and the partners of those, which its smoothing reads, within 2 R.
  const Real radius = search_radius();
  BoundingBox own;
  for (Index a = own_.begin; a < own_.end; ++a) own.include(x_[a]);
  struct Near {
    std::int64_t particle;  // 64 bits: no padding travels
    Vec3 x, v, support;
  };
  std::vector<Index> particles;
  const std::vector<Near> came = neighbors::near_particles(
      own_, x_.view(particle_count()), ranks.each(own.grown(2 * radius)),
      [&](Index a) { return Near{a, x_[a], v_[a], support_[a]}; }, particles);
  // Held for the search beside the particles held already (those read, and those smoothed).
  if (!particles.empty()) {
    const parallel::Range near{particles.front(), particles.back() + 1};
    const parallel::Range kinematics = parallel::hull({x_.held_begin(), x_.held_end()}, near);
    const parallel::Range windows = parallel::hull({support_.held_begin(), support_.held_end()}, near);
    x_.hold(kinematics.begin, kinematics.end), v_.hold(kinematics.begin, kinematics.end);
    support_.hold(windows.begin, windows.end);
  }
  // Their nodes' rows too (collective).
  if (hold_nodes_)
    (*hold_nodes_)(particles.empty() ? parallel::Range{}
                                     : parallel::Range{node_[particles.front()], node_[particles.back()] + 1});
  for (const Near& p : came) {
    const auto a = static_cast<Index>(p.particle);
    const Index i = nodes.node_row(node_[a]);
    x_[a] = nodes.x[i] = p.x;
    v_[a] = nodes.v[i] = p.v;
    support_[a] = p.support;
  }
  return particles;
}

void Part::search_from_own(discretization::NodeStore& nodes) {
  x_.hold_afresh(own_.begin, own_.end), v_.hold_afresh(own_.begin, own_.end);
  for (Index a = own_.begin; a < own_.end; ++a) {
    const Index i = nodes.node_row(node_[a]);
    x_[a] = nodes.x[i], v_[a] = nodes.v[i];
  }
  const std::vector<Index> near = bring_neighbourhood(nodes);
  search_bonds(nullptr, &near);
}

void Part::set_up_read_constants() {
  if (own_.begin < set_up_first_ || own_.end > set_up_first_ + static_cast<Index>(particles_at_set_up_.size()))
    throw std::logic_error("SPG: the first deal gave a rank particles other than those it set up");
  set_up_constants(particles_at_set_up_, set_up_first_, own_);
  std::vector<ParticleSetup>().swap(particles_at_set_up_);
  reach_.arrays([&](auto&& bring) { visit_carried_state(*this, [&](auto& array, const auto&) { bring(array); }); });
}

void Part::take_read_rows(const discretization::ReachShare& from) {
  bring_bond_rows(from, read_);
  bonds_.hold(bonds_.entries(read_));
  link_mirrors(bonds_, own_);
}

// RK shape functions of every particle's row in the current positions, which become the reference
// configuration X. Broken bonds take no part (seed 001 eq. 14: Phi_K(x_J) = 0 across them).
Index Part::build_shape_functions(bool at_setup) {
  const Index n = particle_count();
  // Of the rows of the particles read (every row on one process): a rank's own computed here, the
  // others' in from their ranks below; a broken bond's entries stay 0.
  const parallel::Range rows = bonds_.entries(read_);
  psi_.hold_afresh(rows.begin, rows.end, 0);
  grad_.hold_afresh(rows.begin, rows.end, Vec3::Zero());
  // KERNEL 0: the windows deform with the material (mapped through each particle's accumulated
  // deformation), so a stretched bond keeps its weight until it fails (THEORY §9.7).
  const bool material_windows = settings_.kernel_update == KernelUpdate::updated_lagrangian;
  RangeArray<Mat3> window_map;  // of the rows' partners, among the particles read
  if (material_windows) {
    window_map.hold_afresh(read_.begin, read_.end);
    for (Index i = read_.begin; i < read_.end; ++i) window_map[i] = F_total_[i].inverse();
  }
  parallel::LowestIndex singular;
  parallel::region([&](const parallel::Team& team) {
    std::vector<KernelSample> samples;
    std::vector<Index> entry;  // bond position of each sample after the first (self)
    std::vector<Real> psi;
    std::vector<Vec3> grad;
    team.for_each(own_, [&](Index j) {  // the other ranks' come in below
      samples.clear();
      entry.clear();
      auto add = [&](Index i) {
        KernelSample s;
        s.y = x_[j] - x_[i];
        s.support = support_[i];
        if (material_windows) s.map = window_map[i];
        samples.push_back(s);
      };
      add(j);
      for (Index k = bonds_.offsets[j]; k < bonds_.offsets[j + 1]; ++k) {
        if (bonds_.broken[k]) continue;
        add(bonds_.neighbour[k]);
        entry.push_back(k);
      }
      psi.resize(samples.size());
      grad.resize(samples.size());
      const Vec3 scale = material_windows ? window_extent(F_total_[j], support_[j]) : support_[j];
      const Real rcond = rk_shape_functions(settings_.shape, samples, scale, psi, grad);
      degraded_[j] = rcond >= min_moment_rcond ? 0 : 1;
      if (degraded_[j]) {
        if (at_setup) {
          singular.report(j);
          return;
        }
        // Too few bonds left for a linear field (bond failure, or particles drifting apart under
        // an Eulerian kernel): the particle keeps a Shepard partition of unity for the smoothing
        // and no strain of its own (THEORY §9.8).
        if (!shepard_shape_functions(settings_.shape, samples, psi, grad)) {
          std::fill(psi.begin(), psi.end(), 0);
          psi[0] = 1;
        }
        std::fill(grad.begin(), grad.end(), Vec3::Zero());
      }
      psi_self_[j] = psi[0];
      grad_self_[j] = grad[0];
      for (std::size_t s = 1; s < samples.size(); ++s) {
        psi_[entry[s - 1]] = psi[s];
        grad_[entry[s - 1]] = grad[s];
      }
    });
  }, n > parallel_threshold);
  // What reaches the particles whose rows read them: their rows' self terms and degradation (the
  // smoothing, the springs, the stress weighing and the correction's solve at the particles read).
  reach_(psi_self_, grad_self_, degraded_);
  reach_.rows(bonds_.offsets, psi_, grad_);
  // At the set-up every rank names the same particle (under MPI each looked at its own).
  return at_setup ? parallel::world().lowest(singular.value()) : -1;
}

// The defect e_K = sum_J V_J D_JK of the nodal gradient operator (D = G A with ITB 1, G with ITB 2)
// at the particles whose support lies inside the body, then the correction that removes it.
void Part::correct_integration_constraint(bool at_setup) {
  const Index n = particle_count();
  // Surface particles: on the mesh's boundary, next to a broken bond, or without a strain of their
  // own. A particle is interior when no particle within the reach of its column of D (two rings of
  // bonds for G A, one for G) is on the surface. The solve reads it at a rank's own particles
  // alone. A rank flags the particles it reads itself (it holds their surface and degraded flags
  // and their rows), grows each ring over its own particles, and takes the grown flags of the
  // particles they read from their ranks before the next ring.
  const int rings = settings_.stabilization == Stabilization::fluid_particle ? 2 : 1;
  RangeArray<std::uint8_t> near;
  near.hold_afresh(read_.begin, read_.end, 0);
  parallel::for_each(read_, [&](Index j) {
    if (computes(j)) near[j] = on_surface_[j] || degraded_[j] || bonds_.broken_count(j) > 0;
  }, particle_loops);
  for (int ring = 0; ring < rings; ++ring) {
    RangeArray<std::uint8_t> grown = near;
    parallel::for_each(own_, [&](Index j) {
      for (Index k = bonds_.offsets[j]; k < bonds_.offsets[j + 1]; ++k)
        if (!bonds_.broken[k] && near[bonds_.neighbour[k]]) grown[j] = 1;
    }, particle_loops);
    near.swap(grown);
    if (ring + 1 < rings) reach_(near);
  }
  // Interior of a rank's own particles, active of those and their partners.
  RangeArray<std::uint8_t> interior, active;
  interior.hold_afresh(own_.begin, own_.end), active.hold_afresh(read_.begin, read_.end);
  parallel::for_each(own_, [&](Index j) { interior[j] = near[j] ? 0 : 1; }, particle_loops);
  parallel::for_each(read_, [&](Index j) { active[j] = degraded_[j] ? 0 : 1; }, particle_loops);
  // g_I = sum_J V_J grad Psi_I(X_J); with smoothing e_K = sum_I Psi_K(X_I) g_I. Of a rank's own
  // particles, which the solve is for, and g of their bond partners (among those read).
  RangeArray<Vec3> g, defect;
  g.hold_afresh(read_.begin, read_.end), defect.hold_afresh(own_.begin, own_.end);
  parallel::for_each(own_, [&](Index i) {
    Vec3 sum = volume_ref_[i] * grad_self_[i];
    for (Index k = bonds_.offsets[i]; k < bonds_.offsets[i + 1]; ++k)
      sum.noalias() += volume_ref_[bonds_.neighbour[k]] * grad_[bonds_.mirror[k]];
    g[i] = sum;
  }, particle_loops);
  if (settings_.stabilization == Stabilization::fluid_particle) {
    reach_(g);
    parallel::for_each(own_, [&](Index K) {
      Vec3 sum = psi_self_[K] * g[K];
      for (Index k = bonds_.offsets[K]; k < bonds_.offsets[K + 1]; ++k)
        sum.noalias() += psi_[bonds_.mirror[k]] * g[bonds_.neighbour[k]];
      defect[K] = sum;
    }, particle_loops);
  } else {
    parallel::for_each(own_, [&](Index K) { defect[K] = g[K]; }, particle_loops);
  }
  // Set-up: solve to round-off (the patch test of the mesh as given). Kernel updates: the geometry
  // has moved little since the last solve, whose multipliers start a short one.
  const int iterations = at_setup ? setup_iterations : update_iterations;
  correct_integration(bonds_, x_.view(n), volume_ref_.view(n), interior.view(n), active.view(n), defect.view(n),
                      iterations, own_, share_, reach_, correction_);
}

void Part::smooth(StretchView<Vec3> field, RangeArray<Vec3>& smoothed) const {
  const Index bonds = bonds_.entry_count();
  const StretchView<Index> neighbour = bonds_.neighbour.view(bonds);
  const StretchView<Real> psi = psi_.view(bonds);
  parallel::for_each(read_, [&, field, neighbour, psi](Index i) {
    if (!computes(i)) return;
    Vec3 s = psi_self_[i] * field[i];
    for (Index k = bonds_.offsets[i]; k < bonds_.offsets[i + 1]; ++k)
      s.noalias() += psi[k] * field[neighbour[k]];
    smoothed[i] = s;
  }, particle_loops);
}

// F and L at every particle from the (smoothed) positions and velocities, then the stress update.
Index Part::deformation(StretchView<Vec3> x, StretchView<Vec3> v, Real dt) {
  const auto& mat = settings_.material;
  parallel::LowestIndex inverted;
  // The bonds' values read through views held by the pass (as internal_forces).
  const Index bonds = bonds_.entry_count();
  const StretchView<Index> neighbour = bonds_.neighbour.view(bonds);
  const StretchView<Vec3> grad = grad_.view(bonds);
  const StretchView<std::uint8_t> broken = bonds_.broken.view(bonds);
  const Index n = particle_count();
  const StretchView<Vec3> X = x_.view(n), V = v_.view(n);  // as they are, unsmoothed
  // The partners' values of the correction's fluxes (correction_flux) and whether they are active.
  const StretchView<Vec3> lambda = correction_.lambda.view(n), reference = correction_.reference.view(n);
  const StretchView<Mat3> mu = correction_.mu.view(n);
  const StretchView<std::uint8_t> degraded = degraded_.view(n);
  parallel::for_each(own_, [&, x, v, X, V, neighbour, grad, broken, lambda, reference, mu, degraded](Index j) {
    if (degraded_[j]) {
      spin_[j] = Mat3::Zero();
      viscous_pressure_[j] = 0;
      viscous_power_[j] = 0;
      return;
    }
    // D' = D + C: the gradient of the (smoothed) field plus the correction acting on the nodal
    // values themselves.
    Mat3 F = x[j] * grad_self_[j].transpose() + X[j] * correction_.self[j].transpose();
    Mat3 dF = v[j] * grad_self_[j].transpose() + V[j] * correction_.self[j].transpose();
    const Vec3 alpha = correction_.alpha[j];
    const Mat3 beta = correction_.beta[j];
    const Real inverse_volume = 1 / volume_ref_[j];
    for (Index k = bonds_.offsets[j]; k < bonds_.offsets[j + 1]; ++k) {
      const Index i = neighbour[k];
      F.noalias() += x[i] * grad[k].transpose();
      dF.noalias() += v[i] * grad[k].transpose();
      if (broken[k] || degraded[i]) continue;  // no correction on the bond
      const Vec3 C = inverse_volume * correction_flux(alpha, beta, reference[j], lambda[i], mu[i], reference[i]);
      F.noalias() += X[i] * C.transpose();
      dF.noalias() += V[i] * C.transpose();
    }
    const Real det = F.determinant();
    if (!(det > 0)) {
      inverted.report(j);
      return;
    }
    F_[j] = F;
    const Mat3 L = dF * F.inverse();
    spin_[j] = Real(0.5) * (L - L.transpose());
    const Real rho = mass(j) / (volume_ref_[j] * det);
    materials::PointThermo thermo{specific_energy_[j], pressure_[j], sound_speed_[j]};
    materials::advance_point(mat, state_[j], thermo, L, dt, rho, materials::kept_back_stress(back_stress_, j));
    specific_energy_[j] = thermo.specific_energy;
    density_[j] = rho;
    pressure_[j] = thermo.pressure;
    sound_speed_[j] = thermo.sound_speed;
    // Bulk viscosity of LS-DYNA's solid elements, q = rho l (Q1 l tr(D)^2 - Q2 c tr(D)) while the
    // volume shrinks, with l the particle spacing followed through the volume change.
    const Real volume_rate = L.trace();  // tr(D)
    const Real volume = volume_ref_[j] * det;
    const Real length = mean_spacing_[j] * cube_root(volume / volume0_[j]);
    const Real q = volume_rate < 0 ? rho * length *
                                         (settings_.bulk_viscosity_quadratic * length * volume_rate * volume_rate -
                                          settings_.bulk_viscosity_linear * sound_speed_[j] * volume_rate)
                                   : 0;
    viscous_pressure_[j] = q;
    viscous_power_[j] = -volume * q * volume_rate;
  }, particle_loops);
  return inverted.value();
}

// The spring on the part of the motion that the smoothing removes, in rate form so that it keeps
// its memory across kernel updates, rotated with the particle's spin (THEORY §9.5).
void Part::update_stabilization(Real dt) {
  parallel::for_each(read_, [&](Index j) {
    if (!computes(j)) return;
    if (degraded_[j]) {
      stabilization_force_[j] = Vec3::Zero();
      stabilization_total_[j] = Vec3::Zero();
      stabilization_power_[j] = 0;
      return;
    }
    const Vec3& s = stabilization_force_[j];
    const Vec3 removed = v_[j] - vs_[j];  // the velocity the smoothing removes
    stabilization_force_[j] = s + dt * (stiffness_[j] * removed + spin_[j] * s);
    stabilization_total_[j] = stabilization_force_[j] + dashpot_[j] * removed;
    stabilization_power_[j] = dashpot_[j] * removed.squaredNorm();
  }, particle_loops);
}

// Per particle, the quantity IDAM judges bonds on (bond_failure.hpp). Called after the kernel
// update has folded F into F_total_, so F_total_ is the deformation from the initial configuration.
void Part::failure_quantity(RangeArray<Real>& out, parallel::Range particles) const {
  out.hold_afresh(particles.begin, particles.end);
  parallel::for_each(particles, [&](Index j) {
    switch (settings_.failure_quantity) {
      case BondFailure::plastic_strain:
        out[j] = state_[j].plastic_strain;
        break;
      case BondFailure::principal_stress:
        out[j] = max_principal_stress(state_[j].deviatoric_stress - pressure_[j] * Mat3::Identity());
        break;
      case BondFailure::shear_strain:
        out[j] = max_shear_strain(F_[j] * F_total_[j]);
        break;
    }
  }, particle_loops);
}

// A particle that bond failure left without a linear approximation can neither carry nor pass on
// a stress consistently; the bonds it still has would only let its stressed neighbours fling it
// off the crack. It is detached: its remaining bonds break too, and its neighbours' rows are
// rebuilt without it (which may detach them in turn: a pass detaches the particles degraded at its
// start, each rank its own, whatever the order). Particles degraded without any broken bond
// (neighbours lost to a stretch beyond the windows' bound) keep their bonds.
void Part::detach_degraded_particles() {
  for (int pass = 0; pass < 16; ++pass) {
    std::vector<BondPair> detaching;
    for (Index j = own_.begin; j < own_.end; ++j) {
      const Index broken = bonds_.broken_count(j);
      if (!degraded_[j] || broken == 0 || broken == bonds_.count(j)) continue;
      for (Index k = bonds_.offsets[j]; k < bonds_.offsets[j + 1]; ++k)
        if (!bonds_.broken[k]) detaching.push_back(std::minmax(j, bonds_.neighbour[k]));
    }
    detaching = every_ranks(std::move(detaching));
    if (detaching.empty()) return;
    break_bonds(bonds_, rows_read(), detaching, broken_pairs_);
    build_shape_functions(false);
  }
}

std::vector<BondPair> Part::every_ranks(std::vector<BondPair> pairs) const {
  if (share_.dealt()) pairs = parallel::world().all(std::span<const BondPair>(pairs));
  std::sort(pairs.begin(), pairs.end());
  pairs.erase(std::unique(pairs.begin(), pairs.end()), pairs.end());
  return pairs;
}

void Part::update_kernel(discretization::NodeStore& nodes) {
  const Index n = particle_count();
  // A rank folds F where it holds it current, in the particles it reads (every one on one
  // process; under MPI their F, material state and pressure come each step), and judges the bonds
  // of its own particles' rows from them: only the bonds it breaks travel, to every rank (the
  // broken pairs are every rank's). The others' folded F come with their state where a rank reads
  // them later (deal_anew; an Eulerian search's new partners below).
  parallel::for_each(read_, [&](Index j) {
    volume_ref_[j] *= F_[j].determinant();
    F_total_[j] = F_[j] * F_total_[j];
    F_[j] = Mat3::Identity();
  }, particle_loops);
  RangeArray<Real> quantity;
  failure_quantity(quantity, read_);
  // Broken bonds of each particle read, over every bond ever broken (also those an Eulerian update
  // drops).
  auto broken_per_particle = [&] {
    RangeArray<Index> count;
    count.hold_afresh(read_.begin, read_.end, 0);
    const auto counts = [&](Index i) { return i >= read_.begin && i < read_.end; };
    for (const auto& [i, j] : broken_pairs_) {
      if (counts(i)) ++count[i];
      if (counts(j)) ++count[j];
    }
    return count;
  };
  const RangeArray<Index> broken_before = broken_per_particle();
  break_bonds(bonds_, rows_read(),
              every_ranks(bonds_breaking(bonds_, quantity.view(n), x_.view(n), settings_.failure_value,
                                         settings_.failure_stretch, own_)),
              broken_pairs_);
  if (settings_.kernel_update != KernelUpdate::updated_lagrangian) {
    // Windows in the current configuration widen with the stretch of the material around each
    // particle (THEORY §9.7): windows of the first size lose the neighbours of material that spreads
    // (the foot of a Taylor bar) and leave their rows ill-conditioned; separation is the bonds' to
    // decide (IDAM), or the kernel's beyond max_window_growth.
    parallel::for_each(read_, [&](Index j) {
      const Vec3& a = initial_support_[j];
      support_[j] = window_extent(F_total_[j], a).cwiseMax(a).cwiseMin(max_window_growth * a);
    }, particle_loops);
  }
  const bool searching = settings_.kernel_update == KernelUpdate::eulerian;
  const bool distributed = parallel::world().size() > 1;
  if (searching) {
    const std::vector<Index> near = distributed ? bring_neighbourhood(nodes) : std::vector<Index>{};
    const BondList previous = std::move(bonds_);
    search_bonds(&previous, distributed ? &near : nullptr);
  }
  // Under MPI the bonds, the shape functions and the correction of the particles the new rows read
  // come in from their ranks.
  if (distributed) plan_reads(nodes);
  if (searching) take_read_rows(reach_);
  if (distributed) {
    plan_smoothed(nodes);
    hold_state(read_);  // KERNEL 1's new partners: their state comes in below
  }
  build_shape_functions(false);
  detach_degraded_particles();
  // A particle that lost bonds has lost the neighbourhood its spring measured the non-affine
  // motion against: the spring starts again from rest (else it kicks the new crack surface). Of
  // the particles read before and now: a KERNEL 1 search's new partners bring their springs below.
  const RangeArray<Index> broken_after = broken_per_particle();
  for (Index j = std::max(read_.begin, broken_before.held_begin()); j < std::min(read_.end, broken_before.held_end());
       ++j)
    if (broken_after[j] != broken_before[j]) stabilization_force_[j] = Vec3::Zero();
  // Bonds searched anew may have partners new to a rank: their folded F, volume and stress and
  // their springs, which the correction, the force and the next step's springs read (the rest
  // comes each step).
  if (settings_.kernel_update == KernelUpdate::eulerian)
    reach_(F_, F_total_, volume_ref_, state_, pressure_, viscous_pressure_, stabilization_force_, stabilization_total_,
           volume0_, initial_support_, spacing_, mean_spacing_, stiffness_, dashpot_, initial_bond_count_, on_surface_);
  correct_integration_constraint(false);
  steps_since_update_ = 0;
  ++kernel_updates_;
}

// h_I = sum_J V_J P_J grad Psi_I(X_J), then the force on K gathers h and s through Psi_K(X_I).
void Part::internal_forces() {
  parallel::for_each(read_, [&](Index j) {
    if (!computes(j)) return;  // read by no row of this rank's
    if (degraded_[j]) {
      weighted_stress_[j] = Mat3::Zero();
      return;
    }
    const Real volume = volume_ref_[j] * F_[j].determinant();
    const Mat3 sigma = state_[j].deviatoric_stress - (pressure_[j] + viscous_pressure_[j]) * Mat3::Identity();
    weighted_stress_[j] = volume * sigma * F_[j].inverse().transpose();
  }, particle_loops);
  // The bond passes read the partners' values through views held by the passes (a RangeArray's
  // first index and data reloaded at every bond, integration_constraint.cpp).
  const Index n = particle_count(), bonds = bonds_.entry_count();
  const StretchView<Mat3> P = weighted_stress_.view(n);
  const StretchView<Index> neighbour = bonds_.neighbour.view(bonds), mirror = bonds_.mirror.view(bonds);
  const StretchView<Real> psi = psi_.view(bonds);
  const StretchView<Vec3> grad = grad_.view(bonds);
  const StretchView<std::uint8_t> broken = bonds_.broken.view(bonds);
  const StretchView<Vec3> alpha = correction_.alpha.view(n), reference = correction_.reference.view(n);
  const StretchView<Mat3> beta = correction_.beta.view(n);
  const StretchView<Real> volume = volume_ref_.view(n);
  const StretchView<std::uint8_t> degraded = degraded_.view(n);
  parallel::for_each(own_, [&, P, neighbour, mirror, grad](Index i) {
    Vec3 h = P[i] * grad_self_[i];
    for (Index k = bonds_.offsets[i]; k < bonds_.offsets[i + 1]; ++k)
      h.noalias() += P[neighbour[k]] * grad[mirror[k]];
    h_[i] = h;
  }, particle_loops);
  reach_(h_);
  const bool smoothed = settings_.stabilization == Stabilization::fluid_particle;
  const StretchView<Vec3> h = h_.view(n), s = stabilization_total_.view(n);
  parallel::for_each(own_, [&, P, neighbour, mirror, psi, broken, alpha, reference, beta, volume, degraded, h,
                            s](Index K) {
    // f_K = -sum_I Psi_K(X_I) (h_I - s_I) - s_K, or with ITB 2 -h_K - s_K + sum_I Psi_K(X_I) s_I.
    Vec3 gathered = psi_self_[K] * (smoothed ? Vec3(h[K] - s[K]) : Vec3(-s[K]));
    for (Index k = bonds_.offsets[K]; k < bonds_.offsets[K + 1]; ++k) {
      const Index I = neighbour[k];
      gathered.noalias() += psi[mirror[k]] * (smoothed ? Vec3(h[I] - s[I]) : Vec3(-s[I]));
    }
    // The correction's share: -sum_J V_J P_J C_JK, C_JK from row J's values (correction_flux).
    Vec3 corrected = P[K] * correction_.self[K];
    if (!degraded[K]) {
      const Vec3 lambda = correction_.lambda[K];
      const Mat3 mu = correction_.mu[K];
      for (Index k = bonds_.offsets[K]; k < bonds_.offsets[K + 1]; ++k) {
        const Index J = neighbour[k];
        if (broken[k] || degraded[J]) continue;
        corrected.noalias() +=
            P[J] * (correction_flux(alpha[J], beta[J], reference[J], lambda, mu, reference[K]) / volume[J]);
      }
    }
    force_[K] = (smoothed ? Vec3(-gathered - s[K]) : Vec3(-h[K] - gathered - s[K])) - corrected;
  }, particle_loops);
}

void Part::find_own(const discretization::NodeStore& nodes) {
  // The particles are in node order and the nodes dealt in blocks: a rank's own are one stretch.
  const auto first_at = [&](Index node) {
    return static_cast<Index>(std::lower_bound(node_.begin(), node_.end(), node) - node_.begin());
  };
  own_ = {first_at(nodes.rank_begin[nodes.rank]), first_at(nodes.rank_begin[nodes.rank + 1])};  // places
}

std::vector<std::uint8_t> Part::plan_reads(const discretization::NodeStore& nodes) {
  reach_partition_ = nodes.partition;
  std::vector<std::uint8_t> reads =
      reach_.plan_rows(bonds_.offsets, bonds_.neighbour.view(bonds_.entry_count()), [&](Index j) { return owns(j); },
                       node_, share_, nodes, {own_.begin, own_.end});
  read_ = {};
  for (Index a = 0; a < particle_count(); ++a)
    if (reads[a]) read_ = parallel::hull(read_, {a, a + 1});
  reads_.hold_afresh(read_.begin, read_.end);
  std::copy(reads.begin() + read_.begin, reads.begin() + read_.end, reads_.data());
  return reads;
}

void Part::plan_smoothed(const discretization::NodeStore& nodes) {
  // The stretch holding the particles read and their bond partners, whose positions and velocities
  // the smoothing of the particles read reads (eq. 11).
  smoothed_ = read_;
  for (Index a = read_.begin; a < read_.end; ++a) {
    if (!reads_[a]) continue;
    for (Index k = bonds_.offsets[a]; k < bonds_.offsets[a + 1]; ++k)
      smoothed_ = parallel::hull(smoothed_, {bonds_.neighbour[k], bonds_.neighbour[k] + 1});
  }
  x_.hold(smoothed_.begin, smoothed_.end), v_.hold(smoothed_.begin, smoothed_.end);
  if (hold_nodes_) (*hold_nodes_)({});
  if (nodes.velocities_by_reach)
    velocity_reach_.plan_rows(bonds_.offsets, bonds_.neighbour.view(bonds_.entry_count()),
                              [&](Index j) { return reads_[j] != 0; }, node_, share_, nodes, {read_.begin, read_.end});
}

void Part::share_velocities(discretization::NodeStore& nodes) {
  if (!nodes.velocities_by_reach || !velocity_reach_.planned()) return;
  velocity_reach_.records<Vec3>([&](Index a) { return nodes.v[nodes.node_row(node_[a])]; },
                                [&](Index a, const Vec3& v) { nodes.v[nodes.node_row(node_[a])] = v; });
  kinematics_complete_ = false;
}

parallel::Range Part::nodes_read(const discretization::NodeStore& nodes) const {
  if (!velocity_reach_.planned()) return {0, nodes.size()};
  if (smoothed_.size() == 0) return {0, 0};
  const parallel::Range places = places_read();  // in node order: rows of the window
  return {nodes.node_row(places.begin), nodes.node_row(places.end - 1) + 1};
}

void Part::hold_shape_rows(parallel::Range rows) {
  psi_.hold(rows.begin, rows.end);
  grad_.hold(rows.begin, rows.end);
}

void Part::complete_kinematics(discretization::NodeStore& nodes) {
  if (kinematics_complete_) return;
  if (nodes.windowed()) {
    // The rows held, from the ranks that computed them (share_ is still the deal's they were
    // computed in): each rank writes its own rows into a checkpoint, and a new deal's rows that a
    // rank lacks come from their new ranks, which hold them current after this.
    discretization::ReachShare arrivals;
    arrivals.plan_held(node_, share_, nodes);
    struct Kinematics {
      Vec3 x, v;
      Real mass;
    };
    arrivals.records<Kinematics>(
        [&](Index a) {
          const Index i = nodes.node_row(node_[a]);
          return Kinematics{nodes.x[i], nodes.v[i], nodes.mass[i]};
        },
        [&](Index a, const Kinematics& k) {
          const Index i = nodes.node_row(node_[a]);
          nodes.x[i] = k.x, nodes.v[i] = k.v;
          if (!mass_scale_.empty()) nodes.mass[i] = k.mass;
        });
  } else if (mass_scale_.empty()) {
    share_.complete_nodes(node_, nodes);
  } else {
    // With DT2MS by reach the nodes' masses too, which each rank raises for its own particles
    // alone between new deals (scale_masses).
    const Index n = particle_count();
    std::vector<Real> mass(n);
    for (Index a = 0; a < n; ++a) mass[a] = nodes.mass[nodes.node_row(node_[a])];
    share_.complete_nodes(node_, nodes, mass);
    for (Index a = 0; a < n; ++a)
      if (!owns(a)) nodes.mass[nodes.node_row(node_[a])] = mass[a];
  }
  kinematics_complete_ = true;
}

// The state a particle carries (visit_carried_state) and the bonds' shape functions and
// correction, for the particles this rank's new rows read alone (a ReachShare planned against the
// old deal's ranks, each of which holds its own particles and their rows then): a particle's state
// travels to the ranks that need it, no further.
void Part::deal_anew(const discretization::NodeStore& nodes) {
  const discretization::ParticleShare dealt_before = share_;
  const parallel::Range held_before{psi_.held_begin(), psi_.held_end()}, state_before = held_state();
  share_.bind(nodes);
  find_own(nodes);
  // The rows of this rank's own particles first, which tell what it reads.
  std::vector<std::uint8_t> own(particle_count(), 0);
  std::fill(own.begin() + own_.begin, own.begin() + own_.end, 1);
  discretization::ReachShare owned;
  owned.plan(own, node_, dealt_before, nodes);
  bring_bond_rows(owned, own_);
  // Then the other particles it reads, theirs alone (its own rows are here).
  std::vector<std::uint8_t> others = plan_reads(nodes);
  std::fill(others.begin() + own_.begin, others.begin() + own_.end, 0);
  discretization::ReachShare arrivals;
  arrivals.plan(others, node_, dealt_before, nodes);
  take_read_rows(arrivals);
  plan_smoothed(nodes);
  // The state held before (that sent) and of the particles read now (that received) while it travels.
  hold_state(parallel::hull(state_before, read_));
  for (const discretization::ReachShare* from : {&owned, &arrivals})
    from->arrays([&](auto&& bring) { visit_carried_state(*this, [&](auto& array, const auto&) { bring(array); }); });
  hold_state(read_);
  // The rows held before (those sent) and the rows read now (those received) while they travel.
  hold_shape_rows(parallel::hull(held_before, bonds_.entries(read_)));
  for (const discretization::ReachShare* from : {&owned, &arrivals})
    from->rows(bonds_.offsets, psi_, grad_);
  hold_shape_rows(bonds_.entries(read_));
}

void Part::compute_forces(discretization::NodeStore& nodes, Real dt, const HoldNodes& hold_nodes) {
  hold_nodes_ = hold_nodes ? &hold_nodes : nullptr;
  const Index n = particle_count();
  const parallel::Communicator& ranks = parallel::world();
  const bool distributed = ranks.size() > 1;
  // A kernel update reads the positions of the particles a rank reads (the bond failure, the shape
  // functions and the correction of its own rows), which are current here (they are among those
  // whose velocities come in, smoothed_), and KERNEL 1's search those near its own particles
  // (bring_neighbourhood); a new deal's rows read the shape functions and the positions and
  // velocities of particles this rank may not have read before: with the velocities by reach,
  // from the deal they were computed in.
  const bool new_deal = distributed && share_.stale(nodes);
  if (new_deal) complete_kinematics(nodes);
  if (new_deal) deal_anew(nodes);
  share_.bind(nodes);
  if (distributed && reach_partition_ != nodes.partition) {  // the first deal, or a restart file read whole
    find_own(nodes);
    if (set_up_pending_) search_from_own(nodes);
    plan_reads(nodes);
    take_read_rows(reach_);
    plan_smoothed(nodes);
    hold_shape_rows(bonds_.entries(read_));
    hold_state(read_);
    if (set_up_pending_) set_up_read_constants();
  }
  if (set_up_pending_) set_up_shape_functions(nodes);
  parallel::for_each(smoothed_, [&](Index i) {
    const Index row = nodes.node_row(node_[i]);
    x_[i] = nodes.x[row];
    v_[i] = nodes.v[row];
  }, particle_loops);
  if (dt > 0) {
    smooth(v_.view(n), vs_);
    const bool smoothed = settings_.stabilization == Stabilization::fluid_particle;
    if (smoothed) smooth(x_.view(n), xs_);
    Index inverted = deformation(smoothed ? xs_.view(n) : x_.view(n), smoothed ? vs_.view(n) : v_.view(n), dt);
    inverted = ranks.lowest(inverted);  // every rank stops, naming the same particle
    if (inverted >= 0)
      throw InstabilityError(fmt::format("SPG part {}: the deformation gradient at node {} is no longer "
                                         "invertible (det F <= 0): the particles have inverted",
                                         settings_.part_id, node_id(nodes, inverted)));
    // What the bonded particles of other ranks read (the stress and the spin).
    if (distributed) reach_(F_, spin_, state_, pressure_, viscous_pressure_);
    update_stabilization(dt);
    if (++steps_since_update_ >= settings_.update_interval) update_kernel(nodes);
  }
  internal_forces();
  parallel::for_each(own_, [&](Index i) { nodes.f[nodes.node_row(node_[i])] += force_[i]; }, particle_loops);
  if (mass_scaling_.active)
    scale_masses(nodes, !nodes.velocities_by_reach || new_deal);
  else
    mass_scaling_.idle();
  hold_nodes_ = nullptr;
}

// DT2MS (THEORY §1, mass scaling): a particle f times heavier has the sound speed c / sqrt(f); one whose step
// alpha h / (c + |v|) is below the target gets the f that brings it there, c / sqrt(f) = s - |v| with
// s = alpha h / target (but never below s / 2: a particle faster than s / 2 keeps a step below the
// target rather than take unbounded mass), (f - 1) m more mass on its node, kept from then on. Its
// material keeps its density.
// Under MPI each rank scales its own particles (their factors travel with their state). With the
// velocities by reach only a node's rank reads its mass (its velocity update and energies, its
// slaves' touches), so each rank adds its own particles' new mass alone, and the masses come to
// the other ranks where they are needed (complete_kinematics: a checkpoint, a new deal); otherwise,
// and on a new deal's step, every rank adds every particle's raise, in from its rank (a contact
// with deformable segments reads any node's mass; after a new deal other formulations bring their
// nodes' state from the ranks that computed them before, after this pass: those ranks must hold
// this step's raise too).
void Part::scale_masses(discretization::NodeStore& nodes, bool whole) {
  const Index n = particle_count();
  // The mass each particle adds to its node this step: of a rank's own particles, or where the
  // others' come in too (`whole`), of every particle (an array of every particle's each step would
  // cost a rank 8 B a particle of every rank's).
  const parallel::Range held = whole ? parallel::Range{0, n} : own_;
  RangeArray<Real> raise;
  raise.hold_afresh(held.begin, held.end, 0);
  parallel::for_each(own_, [&](Index i) {
    const Real s = courant_factor * current_spacing(i) / mass_scaling_.step;
    const Real speed = nodes.v[nodes.node_row(node_[i])].norm();
    const Real ratio = sound_speed_[i] / std::max(s - speed, s / 2);
    const Real factor = std::max(mass_scale_[i], ratio * ratio);
    raise[i] = (factor - mass_scale_[i]) * mass(i);
    mass_scale_[i] = factor;
  }, particle_loops);
  if (whole)
    share_(node_, raise);
  else
    kinematics_complete_ = false;
  parallel::for_each(held, [&](Index i) {
    if (raise[i] > 0 && nodes.holds_place(node_[i]))  // every node unless a window
      nodes.mass[nodes.node_row(node_[i])] += raise[i];
  }, particle_loops);
  const Real added =
      parallel::exact_sum(own_, [&](Index i) { return (mass_scale_[i] - 1) * mass(i); }, &parallel::world());
  mass_scaling_.record(added);
}

void Part::scale_mass_below(Real step, bool first_step_only) {
  mass_scaling_.start(step, first_step_only);
  const parallel::Range held = held_state();
  mass_scale_.hold_afresh(held.begin, held.end, 1);
}

// The nodal spacing h scaled with the particle's volume change since the start; with KERNEL 2, the
// first spacing carried by the deformation, its narrowest axis: the bonds are the first ones, and
// neighbours that the material squeezed together steepen the gradients however wide the windows
// (a Taylor bar at 350 m/s inverts under the foot at 13 us with the volume rule, THEORY §9.6).
Real Part::current_spacing(Index i) const {
  if (settings_.kernel_update == KernelUpdate::pseudo_lagrangian)
    return window_extent(F_[i] * F_total_[i], initial_support_[i].cwiseQuotient(settings_.dilation))
        .minCoeff();
  return spacing_[i] * cube_root(volume_ref_[i] * F_[i].determinant() / volume0_[i]);
}

// CFL condition on the support size (seed 001 §2.1: the SPG step follows the support of the shape
// functions, not the closest nodal distance, so a distorted neighbourhood does not cut it down):
// dt <= alpha (a_min / DX) (V / V_0)^(1/3) / (c + |v|).
// Under MPI, of each rank's own particles, then the least over the ranks (every rank asks for it
// in the step's limit).
Real Part::stable_time_step(const discretization::NodeStore& nodes) const {
  const Real infinity = std::numeric_limits<Real>::infinity();
  double step = parallel::reduce_exact(
      own_, infinity,
      [&](Index i) {
        const Real c = mass_scale_.empty() ? sound_speed_[i] : sound_speed_[i] / std::sqrt(mass_scale_[i]);
        return courant_factor * current_spacing(i) / (c + nodes.v[nodes.node_row(node_[i])].norm());
      },
      [](Real a, Real b) { return std::min(a, b); }, particle_loops);
  parallel::world().minimum({&step, 1});
  return step;
}

discretization::InternalPower Part::internal_power(const discretization::NodeStore& nodes,
                                                  std::span<const Vec3> v) const {
  // The viscous share is the stress power of q and of the dashpot; the rest of the work of the
  // internal forces is stored. Exact sums over every rank's own particles (parallel::exact_sum).
  const Sums<2> sums = parallel::exact_sum(
      own_,
      [&](Index i) {
        return Sums<2>{{-force_[i].dot(v[nodes.node_row(node_[i])]), viscous_power_[i] + stabilization_power_[i]}};
      },
      &parallel::world());
  discretization::InternalPower p;
  p.dissipated = sums[1];
  p.stored = sums[0] - sums[1];
  return p;
}

Real Part::max_wave_speed() const {
  Real c = 0;
  for (Index a = own_.begin; a < own_.end; ++a) c = std::max(c, sound_speed_[a]);
  return parallel::world().largest(c);
}

void Part::write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const {
  const auto pressure = fields.node_real("pressure"), von_mises = fields.node_real("von_mises"),
             density = fields.node_real("density"),
             plastic_strain = fields.node_real("effective_plastic_strain"),
             bond_damage = fields.node_real("bond_damage"),
             stress = fields.node_real("stress", 6, discretization::symmetric_tensor_components);
  const auto broken_bonds = fields.node_integer("broken_bonds"), bond_count = fields.node_integer("bond_count");
  for (Index a = 0; a < particle_count(); ++a) {
    if (!owns(a)) continue;  // under MPI each rank writes its own particles (the others' are stale)
    const Index i = nodes.node_row(node_[a]);
    const Mat3& S = state_[a].deviatoric_stress;
    pressure[i] = pressure_[a];
    von_mises[i] = std::sqrt(Real(1.5) * S.cwiseProduct(S).sum());
    density[i] = density_[a];
    plastic_strain[i] = state_[a].plastic_strain;
    const Index broken = bonds_.broken_count(a);
    broken_bonds[i] = broken;
    bond_count[i] = bonds_.count(a) - broken;
    bond_damage[i] = initial_bond_count_[a] > 0 ? double(broken) / initial_bond_count_[a] : 0.0;
    const Mat3 sigma = S - pressure_[a] * Mat3::Identity();
    const double components[6] = {sigma(0, 0), sigma(1, 1), sigma(2, 2), sigma(0, 1), sigma(1, 2), sigma(2, 0)};
    for (int c = 0; c < 6; ++c) stress[6 * i + c] = components[c];
  }
}

void Part::checkpoint(Archive& a) {
  a.section("spg part 11");
  a.expect_size("SPG particles", node_.size());
  // x_ and v_ are the step's copies of the nodes' (compute_forces).
  a(bonds_.offsets, broken_pairs_, correction_, steps_since_update_, kernel_updates_, mass_scaling_);
  // The state held by stretch and the bonds, their shape functions and correction in pieces
  // (core/pieces.hpp): each rank writes its own particles' and their rows (rank 0 every one until
  // the nodes are dealt); read back whole, a rank keeps those it reads from its first step on
  // (hold_state, take_read_rows, hold_shape_rows).
  const parallel::Communicator& ranks = parallel::world();
  const Index n = particle_count();
  if (!a.reading()) {
    const parallel::Range mine = share_.dealt() ? own_ : ranks.rank() == 0 ? parallel::Range{0, n} : parallel::Range{};
    const auto write = [&](const auto& array, parallel::Range items) {
      const auto at = [&](Index j) { return items.begin + j; };
      parallel::write_array_pieces(a, array, items.size(), at, at, ranks);
    };
    visit_held_state(*this, [&](const auto& array, const auto&) { write(array, mine); });
    const parallel::Range rows = bonds_.entries(mine);
    write(bonds_.neighbour, rows), write(bonds_.broken, rows), write(bonds_.rest_length, rows);
    write(psi_, rows), write(grad_, rows);
  } else {
    const auto read = [&](auto& array, Index count) {
      parallel::read_array_pieces(a, array, count, {0, count}, [](Index k) { return k; });
    };
    visit_held_state(*this, [&](auto& array, const auto&) { read(array, n); });
    const Index bonds = bonds_.entry_count();
    read(bonds_.neighbour, bonds), read(bonds_.broken, bonds), read(bonds_.rest_length, bonds);
    read(psi_, bonds), read(grad_, bonds);
    link_mirrors(bonds_, {0, n});
  }
  // The rest written whole (complete_state); read back, the ranks plan their reach again.
  if (a.reading()) {
    kinematics_complete_ = true, set_up_pending_ = false, reach_partition_ = -1;
    std::vector<ParticleSetup>().swap(particles_at_set_up_);
  }
}

Index Part::degraded_count() const {
  std::int64_t n = 0;
  for (Index j = own_.begin; j < own_.end; ++j) n += degraded_[j];
  parallel::world().sum({&n, 1});
  return static_cast<Index>(n);
}

std::size_t Part::memory_bytes() const {
  std::size_t held = 0;
  visit_held_state(*this, [&](const auto& array, const auto&) { held += array.capacity_bytes(); });
  return held + bytes(node_) + reads_.capacity_bytes() + psi_.capacity_bytes() + grad_.capacity_bytes() +
         bytes(bonds_.offsets) + bonds_.neighbour.capacity_bytes() + bonds_.mirror.capacity_bytes() +
         bonds_.broken.capacity_bytes() + bonds_.rest_length.capacity_bytes() + bytes(broken_pairs_) +
         x_.capacity_bytes() + v_.capacity_bytes();
}

}  // namespace spall::spg
