#include "spall/sph/fluid.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include <fmt/format.h>

#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/pieces.hpp"
#include "spall/core/reorder.hpp"
#include "spall/core/simd.hpp"
#include "spall/kernels/kernel.hpp"
#include "spall/neighbors/trimmed_stencil.hpp"
#include "spall/sph/fluid_pairs.hpp"

namespace spall::sph {

using namespace fluid_pairs;

namespace {

// All three translations held: a dynamic boundary (wall) particle.
constexpr std::uint8_t all_translations = 7;

// Shrinks each range to the span from its first to its last moving particle, dropping the ranges
// without one, in place; returns how many are left.
template <typename Ranges>
int moving_spans(const std::uint8_t* moving, Ranges& ranges, int count) {
  int kept = 0;
  for (int r = 0; r < count; ++r) {
    Index begin = ranges[r].begin, end = ranges[r].end;
    while (begin < end) {  // the first moving particle, sixteen slots at a time
      const unsigned bits = moving_lanes(moving, begin, end);
      if (bits) {
        begin += std::countr_zero(bits);
        break;
      }
      begin += 16;
    }
    if (begin >= end) continue;
    while (true) {  // past the last one, from the end (begin moves, so this stops there)
      const Index from = std::max(begin, end - 16);
      const unsigned bits = moving_lanes(moving, from, end);
      if (bits) {
        end = from + 32 - std::countl_zero(bits);
        break;
      }
      end = from;
    }
    ranges[kept++] = {begin, end};
  }
  return kept;
}

// Time-step factors. Courant: the predictor-corrector density update is stable for w dt < 0.72
// and the fastest SPH acoustic mode has w ~ 1.04 c / h (cubic spline), so h / (c + |v| + the
// viscous signal speed) is scaled by 0.4 (w dt ~ 0.42); another kernel's fastest mode is faster
// (kernels::fastest_acoustic_mode) and its factor smaller in proportion. Force: Monaghan 1992,
// dt <= 0.25 sqrt(h / |a|). Viscous: Morris et al. 1997, dt <= 0.125 h^2 / nu.
constexpr Real courant_factor = 0.4;
constexpr Real force_factor = 0.25;
constexpr Real viscous_factor = 0.125;

// Cells of edge (support + skin) / 2, searched by the trimmed stencil: each particle screens only
// the runs of cells that can reach its support (neighbors/trimmed_stencil.hpp).
constexpr int stencil_reach = 2;
// The pack of the pair loops: the widest single-precision pack of the build (simd::FloatPack,
// sixteen lanes with AVX-512, else eight) and its double accumulator. The records have this many
// past the last particle, plus one, so that the screen's last loads of a range stay inside them
// (the lanes past the range are masked).
using Lanes = simd::FloatPack;
using WideLanes = simd::WideFloatSum;
// Walls whose continuity sums run side by side, one per lane of a pack of eight (wall_rates).
using WallLanes = simd::Float8;
constexpr int wall_group = WallLanes::width;
constexpr Index simd_width = Lanes::width;

template <typename T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}

// What a particle's rank sends of it to a rank whose particles are near (share_state).
struct HaloRecord {
  Vec3 v;
  Real density;
  float rate, previous_rate;
};

}  // namespace

FluidMaterial FluidMaterial::tait(Real rho0, Real c0, Real gamma, Real mu) {
  FluidMaterial m;
  m.density = rho0;
  m.eos = materials::Murnaghan{gamma, rho0 * c0 * c0 / gamma};
  m.dynamic_viscosity = mu;
  return m;
}

Real FluidMaterial::pressure(Real rho) const {
  return std::max(materials::evaluate_eos(eos, density, rho, specific_energy).pressure,
                  pressure_cutoff);
}

Real FluidMaterial::sound_speed_at(Real rho) const {
  const auto value = materials::evaluate_eos(eos, density, rho, specific_energy);
  return std::sqrt(std::max(materials::isentropic_bulk_modulus(value, rho), Real(0)) / rho);
}

FluidFormulation::FluidFormulation(const FluidParameters& parameters,
                                   const std::vector<Index>& particle_nodes,
                                   const discretization::NodeStore& nodes)
    : parameters_(parameters), support_(2 * parameters.smoothing_length) {
  const auto& m = parameters_.material;
  if (!(m.density > 0) || !(m.reference_sound_speed() > 0) || !(m.dynamic_viscosity >= 0))
    throw std::invalid_argument("SPH fluid: needs rho0 > 0, a sound speed > 0 at rho0 and mu >= 0");
  if (!(parameters_.smoothing_length > 0))
    throw std::invalid_argument("SPH fluid: the smoothing length must be > 0");
  if (parameters_.dimension != 2 && parameters_.dimension != 3)
    throw std::invalid_argument("SPH fluid: the dimension must be 2 or 3");
  if (parameters_.dimension == 2)
    for (Index i : particle_nodes)
      if (nodes.x[i].z() != nodes.x[particle_nodes.front()].z())
        throw std::invalid_argument("SPH fluid: in 2D every particle must lie in one plane z = const");
  const std::size_t n = particle_nodes.size();
  node_ = particle_nodes;
  mass_.resize(n);
  for (std::size_t a = 0; a < n; ++a) mass_[a] = static_cast<float>(nodes.mass[node_[a]]);
  // One mass for every particle of every rank (a rank may be given a block of them): collective.
  constexpr double none = std::numeric_limits<double>::infinity();
  double lightest_and_negated_heaviest[2] = {none, none};
  for (const float m : mass_) {
    lightest_and_negated_heaviest[0] = std::min<double>(lightest_and_negated_heaviest[0], m);
    lightest_and_negated_heaviest[1] = std::min<double>(lightest_and_negated_heaviest[1], -m);
  }
  parallel::world().minimum(lightest_and_negated_heaviest);
  if (lightest_and_negated_heaviest[0] == -lightest_and_negated_heaviest[1])
    uniform_mass_ = static_cast<float>(lightest_and_negated_heaviest[0]);
  density_.assign(n, m.density);
  rate_.assign(n, 0);
  previous_rate_.assign(n, 0);
  record_.assign(n + simd_width + 1, FluidRecord{});
  pressure_force_.assign(3 * n, 0);
  viscous_force_.assign(3 * n, 0);
  max_sound_speed_ = m.reference_sound_speed();
  // The Courant factor keeps w dt of the fastest acoustic mode where the cubic spline's 0.4 puts it.
  const auto fastest = [&](kernels::KernelKind kind) {
    return kernels::with_kernel(kind, parameters_.dimension,
                                [](auto kernel) { return kernels::fastest_acoustic_mode<decltype(kernel)>(); });
  };
  courant_factor_ = parameters_.kernel == kernels::KernelKind::cubic_spline
                        ? courant_factor
                        : courant_factor * fastest(kernels::KernelKind::cubic_spline) / fastest(parameters_.kernel);
}

// Per cell: 1 when a particle of which `chosen(a)` holds is in the 5 x 5 x 5 cells around it.
template <class Chosen>
std::vector<std::uint8_t> FluidFormulation::cells_near(Chosen&& chosen) const {
  // Chosen particles before each slot, to tell in O(1) whether a slot range holds one.
  const Index n = particle_count();
  std::vector<Index> before(n + 1, 0);
  for (Index a = 0; a < n; ++a) before[a + 1] = before[a] + (chosen(a) ? 1 : 0);
  const Index cell_count = cells_.cell_count();
  std::vector<std::uint8_t> near(cell_count, 0);
  parallel::region([&](const parallel::Team& team) {
    neighbors::TrimmedStencil stencil(cells_, stencil_reach);
    neighbors::TrimmedStencil::Ranges ranges;
    team.for_each(cell_count, [&](Index c) {
      stencil.prepare(c);
      const int range_count = stencil.block(ranges);
      for (int r = 0; r < range_count; ++r)
        if (before[ranges[r].end] > before[ranges[r].begin]) near[c] = 1;
    }, {.chunk = 64});
  });
  return near;
}

// Bins the particles into cells of edge (support + skin) / 2 and puts every per-particle array in
// cell order, so that the particles of a cell are contiguous.
void FluidFormulation::rebuild_cells(const discretization::NodeStore& nodes) {
  const Index n = particle_count();
  std::vector<Vec3> x(n);
  std::vector<Id> id(n);
  parallel::for_each(n, [&](Index a) {
    x[a] = nodes.x[node_[a]];
    id[a] = nodes.id[node_[a]];
  });
  // Within a cell by node ID: the order, and so every sum over neighbours, is the same however the
  // particles were stored (the deck's card order, earlier rebuilds, a rank's share of them).
  cells_.build(x, (1 + parameters_.skin) * support_ / stencil_reach, id);
  // The cell list keeps no order: from here on the particles are in cell order.
  take_cell_order(nodes, cells_.take_order());
  finish_build();
}

void FluidFormulation::take_cell_order(const discretization::NodeStore& nodes, std::span<const Index> order) {
  reorder(node_, order);
  const Index n = particle_count();
  share_.reorder();
  reorder(mass_, order);
  reorder(density_, order);
  reorder(rate_, order);
  reorder(previous_rate_, order);
  // As many records and forces as particles (with rows of its own a rank's particles come and go;
  // the records past the last stay empty for the packs that read past it).
  record_.resize(n + simd_width + 1);
  std::fill(record_.begin() + n, record_.end(), FluidRecord{});
  pressure_force_.resize(3 * n);
  viscous_force_.resize(3 * n);
  // Bits to n + simd_width, and the four bytes that moving_lanes reads from the last one.
  moving_.assign((n + simd_width) / 8 + 4, 0);
  for (Index a = 0; a < n; ++a) {
    const bool moving = nodes.fixed[node_[a]] != all_translations;
    moving_[a / 8] |= static_cast<std::uint8_t>(moving << (a % 8));
  }
  active_cell_ = cells_near([&](Index a) { return nodes.fixed[node_[a]] != all_translations; });
  near_owned_partition_ = -1;  // marked again for these cells (compute_forces)
}

void FluidFormulation::finish_build() {
  // Positions are taken relative to the grid corner, in single precision: a position and the
  // distance test carry relative errors of a few 2^-24 of the box size and of the support, which
  // the stencil's radius covers with this margin.
  origin_ = cells_.lower();
  const auto& along = cells_.cells_along();
  const Real box = cells_.cell_size() * static_cast<Real>(std::max({along[0], along[1], along[2]}));
  rounding_margin_ = 1e-6 * (box + support_);
  cells_built_ = true;
  travelled_ = 0;
}

namespace {
// A particle that comes in at a rebuild from the rank that holds it current (rebuild_near_region):
// its node's row and its continuity state.
struct Arrival {
  discretization::NodeStore::Row node;
  Real density;
  float rate, previous_rate;
};
}  // namespace

// A rank's passes read the particles within two cells of a cell of its own, and the cells they read
// are active when a moving particle is within two cells of them (cells_near): every particle within
// four cells of its own, which are in its region after the migration, so within five cell edges of
// the region's box (half a cell more against rounding). Those come in from the ranks that compute
// them (whose copy is current, also of the particles that move to this rank), with the grid of the
// box of every particle; no other particle is binned here, nor held: the particles beyond reach
// and their nodes' rows are dropped (rows of its own, NodeStore), and a particle that comes in for
// the first time brings its node's row.
void FluidFormulation::rebuild_near_region(discretization::NodeStore& nodes) {
  const parallel::Communicator& ranks = parallel::world();
  const int size = ranks.size(), self = ranks.rank();
  const Index n = particle_count();
  const BoundingBox own = parallel::fold_exact(
      n, BoundingBox{}, [&](BoundingBox& box, Index a) { if (owns(a)) box.include(nodes.x[node_[a]]); },
      [](BoundingBox& box, const BoundingBox& other) { box.include(other); });
  const BoundingBox grid = over_ranks(own, ranks);
  if (!grid.finite) {
    Index worst = -1;
    for (Index a = 0; a < n && worst < 0; ++a)
      if (owns(a) && !nodes.x[node_[a]].allFinite()) worst = static_cast<Index>(nodes.id[node_[a]]);
    throw InstabilityError(
        fmt::format("neighbour search: the particle on node {} has a non-finite position", ranks.lowest(worst)));
  }
  const Real asked = (1 + parameters_.skin) * support_ / stencil_reach;
  // The cells are the last rebuild's after a restart (binned_; the particles have moved by less than
  // the skin since, which the half cell covers), else those of the grid of every particle's box.
  const Real reach = 5.5 * (binned_ ? binned_->cell_size : neighbors::CellList::cell_size_over(grid, asked));
  // Each of this rank's particles to every other rank whose region it is within reach of (with its
  // key after a restart).
  std::vector<std::uint8_t> current(n, 0);
  std::vector<std::vector<Arrival>> to(size);
  std::vector<std::vector<neighbors::CellKey>> keys_to(binned_ ? size : 0);
  for (Index a = 0; a < n; ++a) {
    if (!owns(a)) continue;
    current[a] = 1;
    const Index i = node_[a];
    nodes.regions.near(nodes.x[i], reach, [&](int r) {
      if (r == self) return;
      to[r].push_back({nodes.row(i), density_[a], rate_[a], previous_rate_[a]});
      if (binned_) keys_to[r].push_back(binned_->key[a]);
    });
  }
  const std::vector<Arrival> receive = ranks.deliver(to);
  const std::vector<neighbors::CellKey> keys_in = binned_ ? ranks.deliver(keys_to) : std::vector<neighbors::CellKey>();
  to = {};
  keys_to = {};
  const BoundingBox near_region = nodes.regions.box(self).grown(reach);
  drop_beyond(nodes, near_region, current);
  std::vector<Index> slot(nodes.size(), -1);
  for (Index a = 0; a < particle_count(); ++a) slot[node_[a]] = a;
  std::vector<Index> row(receive.size());
  Index arriving = 0;
  for (std::size_t k = 0; k < receive.size(); ++k) {
    row[k] = nodes.row_of(static_cast<Index>(receive[k].node.global));
    arriving += row[k] < 0;
  }
  // Each array grown once (not doubled as it fills: the first rebuild brings in most of a region).
  nodes.reserve(nodes.size() + arriving);
  const std::size_t particles = static_cast<std::size_t>(particle_count() + arriving);
  node_.reserve(particles);
  density_.reserve(particles);
  for (auto* array : {&mass_, &rate_, &previous_rate_}) array->reserve(particles);
  current.reserve(particles);
  slot.reserve(slot.size() + arriving);
  for (std::size_t k = 0; k < receive.size(); ++k) {
    const Arrival& arrival = receive[k];
    if (row[k] < 0) {  // a node this rank does not hold
      row[k] = nodes.add(arrival.node, nodes.regions.rank_of(arrival.node.x));
      slot.push_back(particle_count());
      node_.push_back(row[k]);
      mass_.push_back(static_cast<float>(arrival.node.mass));
      density_.push_back(0);
      rate_.push_back(0);
      previous_rate_.push_back(0);
      current.push_back(0);
      if (binned_) binned_->key.push_back(0);
    }
    const Index i = row[k], a = slot[i];
    nodes.x[i] = arrival.node.x;
    nodes.v[i] = arrival.node.v;
    density_[a] = arrival.density;
    rate_[a] = arrival.rate;
    previous_rate_[a] = arrival.previous_rate;
    current[a] = 1;
    if (binned_) binned_->key[a] = keys_in[k];
  }
  // Binned here: the particles within reach of this rank's region (its own among them); the others
  // are dropped.
  std::vector<Index> local;
  for (Index a = 0; a < particle_count(); ++a)
    if (current[a] && near_region.contains(nodes.x[node_[a]])) local.push_back(a);
  const Index m = static_cast<Index>(local.size());
  std::vector<Id> id(m);
  for (Index k = 0; k < m; ++k) id[k] = nodes.id[node_[local[k]]];
  if (binned_) {
    std::vector<neighbors::CellKey> key(m);
    for (Index k = 0; k < m; ++k) key[k] = binned_->key[local[k]];
    cells_.build_from_keys(key, id, binned_->lower, binned_->cell_size, binned_->along);
  } else {
    std::vector<Vec3> x(m);
    for (Index k = 0; k < m; ++k) x[k] = nodes.x[node_[local[k]]];
    cells_.build(x, asked, id, &grid);
  }
  std::vector<Index> order = cells_.take_order();
  for (Index& k : order) k = local[k];
  keep_rows_near(nodes, local);
  take_cell_order(nodes, order);
  complete_ = false;  // the particles out of reach are stale here
  if (binned_)
    binned_.reset();  // the grid's corner, margin and travel are the restart file's
  else
    finish_build();
}

void FluidFormulation::drop_beyond(discretization::NodeStore& nodes, const BoundingBox& near,
                                   std::vector<std::uint8_t>& current) {
  std::vector<Index> particles;
  for (Index a = 0; a < particle_count(); ++a)
    if (near.contains(nodes.x[node_[a]])) particles.push_back(a);
  if (static_cast<Index>(particles.size()) == particle_count()) return;
  keep_rows_of(nodes, particles);
  reorder(node_, particles);
  reorder(mass_, particles);
  reorder(density_, particles);
  reorder(rate_, particles);
  reorder(previous_rate_, particles);
  reorder(current, particles);
  if (binned_) reorder(binned_->key, particles);
  share_.reorder();
}

// Each particle near this rank's region is computed by the rank whose region holds it (the
// migration: every rank takes it alike from the same positions), and the node store keeps their
// rows and the rows of the nodes this rank computes that carry no particle; the particles keep
// their slots (take_cell_order drops the others).
void FluidFormulation::keep_rows_near(discretization::NodeStore& nodes, std::span<const Index> near) {
  for (const Index a : near) {
    const Index i = node_[a];
    nodes.owner[i] = nodes.regions.rank_of(nodes.x[i]);
  }
  keep_rows_of(nodes, near);
}

// A particle of this rank's region always comes within its reach: one that did not would be lost
// here.
void FluidFormulation::keep_rows_of(discretization::NodeStore& nodes, std::span<const Index> particles) {
  std::vector<std::uint8_t> carries(nodes.size(), 0), kept(nodes.size(), 0);
  for (const Index i : node_) carries[i] = 1;
  for (const Index a : particles) kept[node_[a]] = 1;
  std::vector<Index> rows, new_row(nodes.size(), -1);
  for (Index i = 0; i < nodes.size(); ++i) {
    if (carries[i] && !kept[i] && nodes.regions.rank_of(nodes.x[i]) == nodes.rank && nodes.owns(i))
      throw std::logic_error("SPH fluid: a particle of this rank's region is beyond the reach of its rebuild");
    if (kept[i] || (!carries[i] && nodes.owns(i))) {
      new_row[i] = static_cast<Index>(rows.size());
      rows.push_back(i);
    }
  }
  nodes.keep(rows);
  for (Index& i : node_) i = new_row[i];
  share_.bind(nodes);
}

// Every particle with the key of the cell its rank binned it in: the cells every rank would have
// built from every particle at the last rebuild (same grid, same keys, same in-cell order by node
// ID).
void FluidFormulation::make_cells_whole(const discretization::NodeStore& nodes,
                                        std::span<const neighbors::CellKey> key, const Vec3& lower, Real cell_size,
                                        const std::array<std::int64_t, 3>& along) {
  const Index n = particle_count();
  std::vector<Id> id(n);
  for (Index a = 0; a < n; ++a) id[a] = nodes.id[node_[a]];
  cells_.build_from_keys(key, id, lower, cell_size, along);
  const std::vector<Index> order = cells_.take_order();
  take_cell_order(nodes, order);
  // The last pass's records and forces follow their particles (read by the output's neighbour
  // counts and the energies before the next pass).
  std::vector<FluidRecord> records(record_);
  std::vector<float> pressure(pressure_force_), viscous(viscous_force_);
  for (Index k = 0; k < n; ++k) {
    record_[k] = records[order[k]];
    for (int d = 0; d < 3; ++d) {
      pressure_force_[3 * k + d] = pressure[3 * order[k] + d];
      viscous_force_[3 * k + d] = viscous[3 * order[k] + d];
    }
  }
}

// Copies positions and velocities in cell order, predicts the densities and evaluates the
// equation of state once per particle. The density terms only in the active cells: the walls of
// a cell without a moving particle in its block (far from the fluid) are read by no pair until
// the next rebuild (for_each_particle_candidates), and their density does not change. Under MPI
// only the cells near this rank's particles: no pair it computes reads the others.
void FluidFormulation::gather(const discretization::NodeStore& nodes, Real dt) {
  const Index n = particle_count();
  const auto& m = parameters_.material;
  // The emptied particle (density no longer positive) of the lowest node ID, named alike by every
  // rank and thread count: its ID (none_emptied when none) and its slot here.
  constexpr Id none_emptied = std::numeric_limits<Id>::max();
  struct Found {
    Real max_density;
    Id empty_id;
    Index empty;
  };
  const Index cell_count = cells_.cell_count();
  const auto cell_records = [&](Index c) {
    Found found{m.density, none_emptied, n};
    if (!near_owned_cell_.empty() && !near_owned_cell_[c]) return found;
    const bool active = active_cell_[c];
    const neighbors::ParticleRange own = cells_.cell(c);
    for (Index a = own.begin; a < own.end; ++a) {
      const Index i = node_[a];
      const Vec3 p = nodes.x[i] - origin_;
      const Vec3& v = nodes.v[i];
      FluidRecord& record = record_[a];
      record.x = static_cast<float>(p.x());
      record.y = static_cast<float>(p.y());
      record.z = static_cast<float>(p.z());
      record.vx = static_cast<float>(v.x());
      record.vy = static_cast<float>(v.y());
      record.vz = static_cast<float>(v.z());
      if (!active) continue;
      // rho~^n = rho^{n-1} + dt (2 rho'^{n-1} - rho'^{n-2})
      Real rho = density_[a] + dt * (2 * Real(rate_[a]) - Real(previous_rate_[a]));
      if (nodes.fixed[i] == all_translations) rho = std::max(rho, m.density);
      if (!(rho > 0) && nodes.id[i] < found.empty_id) found.empty_id = nodes.id[i], found.empty = a;
      record.inverse_density = static_cast<float>(1 / rho);
      record.pressure_term = static_cast<float>(m.pressure(rho) / (rho * rho));
      found.max_density = std::max(found.max_density, rho);
    }
    return found;
  };
  const Found found = parallel::reduce_exact(
      cell_count, Found{m.density, none_emptied, n}, cell_records, [](const Found& x, const Found& y) {
        return Found{std::max(x.max_density, y.max_density), std::min(x.empty_id, y.empty_id),
                     x.empty_id <= y.empty_id ? x.empty : y.empty};
      });
  // Over the ranks (MPI): every particle is in a cell near its own rank's particles.
  const double none = std::numeric_limits<double>::infinity();
  double extremes[2] = {-found.max_density, found.empty_id == none_emptied ? none : static_cast<double>(found.empty_id)};
  parallel::world().minimum(extremes);
  const Real max_density = -extremes[0];
  // Continuity can empty a particle that a splash tears from its neighbours under tension; its
  // pressure and volume then mean nothing, so the run stops rather than carry on.
  if (extremes[1] != none) {
    // Its predicted density from a rank that gathered it (whose copy of its state is current; NaN
    // travels as a flag, since no minimum takes it).
    const Id emptied = static_cast<Id>(extremes[1]);
    double found_rho[2] = {none, none};
    if (found.empty_id == emptied) {
      const Index a = found.empty;
      const Real rho = density_[a] + dt * (2 * Real(rate_[a]) - Real(previous_rate_[a]));
      found_rho[0] = std::isnan(rho) ? 1 : 0, found_rho[1] = std::isnan(rho) ? 0 : rho;
    }
    parallel::world().minimum(found_rho);
    throw InstabilityError(fmt::format(
        "SPH fluid: the particle on node {} has density {:.6g}: it was torn from its neighbours "
        "(a pressure cutoff PC on the *MAT_NULL, e.g. 0, keeps a liquid from taking tension)",
        emptied, found_rho[0] == 1 ? std::numeric_limits<Real>::quiet_NaN() : found_rho[1]));
  }
  max_sound_speed_ = m.sound_speed_at(max_density);
}

template <bool pair_pass, typename Visit, typename VisitWalls>
void FluidFormulation::for_each_particle_candidates(const parallel::Team& team, Visit&& visit,
                                                   VisitWalls&& visit_walls) const {
  neighbors::TrimmedStencil stencil(cells_, stencil_reach);
  neighbors::TrimmedStencil::Ranges ranges;
  std::vector<Index> cluster, walls;
  // A neighbour within the support now was binned within support + travelled_ of this
  // particle's position now, which is within travelled_ of its own cell: the 5 x 5 x 5 cells of
  // edge (support + skin) / 2 hold it while 2 travelled_ + margin <= skin support (compute_forces).
  const Real radius = support_ + travelled_ + rounding_margin_;
  const Index cell_count = cells_.cell_count();
  // Chunks of consecutive cells, so that the stencil mostly slides along a row of cells.
  team.for_each(cell_count, [&](Index c) {
    const neighbors::ParticleRange own = cells_.cell(c);
    // Under MPI a cell of other ranks' particles alone is theirs (and its records may be stale).
    if (!near_owned_cell_.empty()) {
      Index a = own.begin;
      while (a < own.end && !owns(a)) ++a;
      if (a == own.end) return;
    }
    if constexpr (!pair_pass) {
      stencil.prepare(c);
      for (Index a = own.begin; a < own.end; ++a) {
        if (!owns(a)) continue;
        const FluidRecord& r = record_[a];
        visit(a, ranges, stencil.trimmed(Vec3(r.x, r.y, r.z), radius, ranges));
      }
    } else {
      // The cell's moving particles (the cluster), its walls, and the bounding box of them all.
      cluster.clear(), walls.clear();
      Vec3 lower = Vec3::Constant(std::numeric_limits<Real>::infinity()), upper = -lower;
      // Another rank's particles bound the box (the runs are those of the serial run) but are its to compute.
      for (Index a = own.begin; a < own.end; ++a) {
        const FluidRecord& r = record_[a];
        lower = lower.cwiseMin(Vec3(r.x, r.y, r.z)), upper = upper.cwiseMax(Vec3(r.x, r.y, r.z));
        if (!owns(a)) continue;
        (moving_lanes(moving_.data(), a) & 1u ? cluster : walls).push_back(a);
      }
      // Inactive cells (walls only) have no moving particle within reach.
      int range_count = 0;
      if (active_cell_[c]) {
        stencil.prepare(c);
        range_count = stencil.trimmed(lower, upper, radius, ranges);
      }
      if (!cluster.empty()) visit(cluster.data(), static_cast<int>(cluster.size()), ranges, range_count);
      if (walls.empty()) return;
      // The walls share the cell's runs (the moving particles are done with them), each cut in
      // place to the span from its first to its last moving particle, and come wall_group at a
      // time: cheaper than trimming runs per wall (docs/PERFORMANCE.md, sessions 13, 18 and 19).
      const int span_count = moving_spans(moving_.data(), ranges, range_count);
      for (std::size_t w = 0; w < walls.size(); w += wall_group)
        visit_walls(walls.data() + w, static_cast<int>(std::min<std::size_t>(wall_group, walls.size() - w)), ranges,
                    span_count);
    }
  }, {.chunk = 16});
}

void FluidFormulation::pair_pass(discretization::NodeStore& nodes, Real dt) {
  kernels::with_kernel(parameters_.kernel, parameters_.dimension,
                       [&](auto kernel) { pair_pass<decltype(kernel)>(nodes, dt); });
}

template <typename Kernel>
void FluidFormulation::pair_pass(discretization::NodeStore& nodes, Real dt) {
  const auto& m = parameters_.material;
  const auto& av = parameters_.viscosity;
  const Real H = support_;
  const Real h = parameters_.smoothing_length;
  const PairConstants constants{static_cast<float>(H * H),
                                static_cast<float>(1 / H),
                                static_cast<float>(h),
                                static_cast<float>(av.eta * av.eta * h * h),
                                static_cast<float>(av.alpha * m.reference_sound_speed()),
                                static_cast<float>(av.beta),
                                static_cast<float>(2 * m.dynamic_viscosity)};
  const PairInputs in{record_.data(), mass_.data(), uniform_mass_, moving_.data()};
  Real max_acceleration = 0, max_mu = 0;

  parallel::region([&](const parallel::Team& team) {
    Real max_acceleration_here = 0, max_mu_here = 0;
    std::vector<Index> found;
    // rho^n = rho^{n-1} + dt rho'^n.
    const auto update_density = [&](Index a, Real rate) {
      density_[a] += dt * rate;
      previous_rate_[a] = first_pass_ ? static_cast<float>(rate) : rate_[a];
      rate_[a] = static_cast<float>(rate);
    };
    const auto moving_particle = [&](Index a, Index* neighbours, Index count) {
      while (count % simd_width != 0) neighbours[count++] = a;
      const PairSums sums = uniform_mass_ > 0
                                ? interact<Kernel, Lanes, WideLanes, true>(in, constants, a, neighbours, count)
                                : interact<Kernel, Lanes, WideLanes, false>(in, constants, a, neighbours, count);
      const Vec3 f(sums.fx, sums.fy, sums.fz), fv(sums.fvx, sums.fvy, sums.fvz);
      nodes.f[node_[a]] += f;
      for (int d = 0; d < 3; ++d) {
        pressure_force_[3 * a + d] = static_cast<float>(f[d] - fv[d]);
        viscous_force_[3 * a + d] = static_cast<float>(fv[d]);
      }
      max_acceleration_here = std::max(max_acceleration_here, f.norm() / Real(mass_[a]));
      max_mu_here = std::max(max_mu_here, Real(sums.max_mu));
      update_density(a, sums.rate);
    };
    std::vector<Index> counts;
    const auto moving_cluster = [&](const Index* cluster, int k, const auto& ranges, int range_count) {
      Index candidates = 0;
      for (int r = 0; r < range_count; ++r) candidates += ranges[r].end - ranges[r].begin;
      const Index stride = candidates + 2 * simd_width;
      if (found.size() < static_cast<std::size_t>(stride) * k) found.resize(static_cast<std::size_t>(stride) * k);
      if (counts.size() < static_cast<std::size_t>(k)) counts.resize(k);
      screen_cluster<Lanes>(in, constants.support_squared, cluster, k, ranges, range_count, found.data(), stride,
                            counts.data());
      for (int i = 0; i < k; ++i) moving_particle(cluster[i], found.data() + i * stride, counts[i]);
    };

    // Walls rest and feel no force; their density follows continuity and never goes below rho0.
    const auto walls = [&](const Index* w, int count, const auto& spans, int span_count) {
      Real rates[wall_group];
      wall_rates<Kernel, WallLanes>(in, constants, w, count, spans, span_count, rates);
      for (int k = 0; k < count; ++k) {
        const Index a = w[k];
        for (int d = 0; d < 3; ++d) pressure_force_[3 * a + d] = viscous_force_[3 * a + d] = 0;
        update_density(a, rates[k]);
        density_[a] = std::max(density_[a], m.density);
      }
    };
    for_each_particle_candidates<true>(team, moving_cluster, walls);
    team.one_at_a_time([&] {
      max_acceleration = std::max(max_acceleration, max_acceleration_here);
      max_mu = std::max(max_mu, max_mu_here);
    });
  });
  // Over every rank's particles (MPI): the step is global.
  double maxima[2] = {max_acceleration, max_mu};
  parallel::world().maximum(maxima);
  max_acceleration_ = maxima[0];
  max_mu_ = maxima[1];
  first_pass_ = false;
}

// The halo by reach: the velocity v^{n+1/2} and the continuity state of the particles in the cells
// near another rank's particles, from their rank to that one. A rank's pair pass reads nothing
// else of the other ranks' particles until the cells are rebuilt or the nodes dealt anew, when
// complete() brings in the rest (positions included: the others' went stale with their velocities).
void FluidFormulation::share_state(discretization::NodeStore& nodes) {
  if (parallel::world().size() == 1 || !halo_.planned()) return;
  halo_.records<HaloRecord>(
      [&](Index a) { return HaloRecord{nodes.v[node_[a]], density_[a], rate_[a], previous_rate_[a]}; },
      [&](Index a, const HaloRecord& record) {
        nodes.v[node_[a]] = record.v;
        density_[a] = record.density;
        rate_[a] = record.rate;
        previous_rate_[a] = record.previous_rate;
      });
  complete_ = false;
}

// Dealt by region nothing: each rank writes its own particles into a restart file (checkpoint)
// and an output.
void FluidFormulation::complete_state(discretization::NodeStore& nodes) {
  if (!complete_ && !nodes.by_region()) complete(nodes);
}

void FluidFormulation::complete(discretization::NodeStore& nodes) {
  if (nodes.by_region())
    throw std::logic_error("FluidFormulation::complete: dealt by region, a rank holds its region's particles alone");
  share_.complete_nodes(node_, nodes, density_, rate_, previous_rate_);
  complete_ = true;
}

// This rank's pair pass reads the particles of the cells near its own.
void FluidFormulation::plan_halo(const discretization::NodeStore& nodes) {
  std::vector<std::uint8_t> reads(particle_count(), 0);
  for (Index c = 0; c < cells_.cell_count(); ++c) {
    if (!near_owned_cell_[c]) continue;
    const neighbors::ParticleRange own = cells_.cell(c);
    std::fill(reads.begin() + own.begin, reads.begin() + own.end, std::uint8_t{1});
  }
  halo_.plan(reads, node_, share_, nodes);
}

void FluidFormulation::compute_forces(discretization::NodeStore& nodes, Real dt) {
  const bool distributed = parallel::world().size() > 1;
  // Nodes dealt anew: the state is brought in from the ranks it is current on, the old blocks'.
  if (distributed && !complete_ && share_.stale(nodes)) complete(nodes);
  share_.bind(nodes);
  // Every particle moved by dt v^{n-1/2} since the last call (under MPI each rank's own, the
  // velocities it holds current, then over the ranks).
  const Index n = particle_count();
  max_speed_ = parallel::world().largest(parallel::reduce_exact(
      n, Real(0), [&](Index a) { return owns(a) ? nodes.v[node_[a]].norm() : Real(0); },
      [](Real x, Real y) { return std::max(x, y); }));
  travelled_ += dt * max_speed_;
  // Two particles approach each other by at most twice the bound; the search also widens by the
  // rounding margin, and all of it must stay within the skin (see for_each_particle_candidates).
  if (!cells_built_ || 2 * travelled_ + rounding_margin_ > parameters_.skin * support_) {
    binned_.reset();  // binned anew from the positions
    if (distributed && nodes.by_region()) {
      rebuild_near_region(nodes);
    } else {
      if (distributed && !complete_) complete(nodes);  // every rank bins every particle alike
      rebuild_cells(nodes);
    }
  } else if (binned_) {
    rebuild_near_region(nodes);  // the cells of the last rebuild, from a restart file read in blocks
  }
  if (distributed && near_owned_partition_ != nodes.partition) {
    near_owned_cell_ = cells_near([&](Index a) { return owns(a); });
    near_owned_partition_ = nodes.partition;
    plan_halo(nodes);
  }
  gather(nodes, dt);
  pair_pass(nodes, dt);
}

Real FluidFormulation::stable_time_step(const discretization::NodeStore&) const {
  const Real h = parameters_.smoothing_length;
  // Monaghan 1992: the artificial viscosity adds the signal speed 1.2 (alpha c + beta max mu_ab).
  const auto& av = parameters_.viscosity;
  const Real viscous_signal = 1.2 * (av.alpha * max_sound_speed_ + av.beta * max_mu_);
  Real dt = courant_factor_ * h / (max_sound_speed_ + max_speed_ + viscous_signal);
  if (max_acceleration_ > 0) dt = std::min(dt, force_factor * std::sqrt(h / max_acceleration_));
  const auto& m = parameters_.material;
  if (m.dynamic_viscosity > 0)
    dt = std::min(dt, viscous_factor * h * h * m.density / m.dynamic_viscosity);
  return dt;
}

discretization::InternalPower FluidFormulation::internal_power(std::span<const Vec3> v) const {
  // Stored (compression) energy grows by -f_pressure . v; viscosity dissipates -f_viscous . v.
  // Exact sums over every rank's own particles: independent of threads, ranks and the particles' order.
  const Sums<2> sums = parallel::exact_sum(
      particle_count(),
      [&](Index a) {
        const Vec3& va = v[node_[a]];
        Sums<2> term;
        if (!owns(a)) return term;  // another rank's
        for (int d = 0; d < 3; ++d) {
          term[0] += Real(pressure_force_[3 * a + d]) * va[d];
          term[1] += Real(viscous_force_[3 * a + d]) * va[d];
        }
        return term;
      },
      &parallel::world());
  discretization::InternalPower p;
  p.stored = -sums[0];
  p.dissipated = -sums[1];
  return p;
}

std::vector<Index> FluidFormulation::neighbour_counts() const {
  std::vector<Index> counts(particle_count(), 0);
  if (!cells_built_) return counts;
  const float H2 = static_cast<float>(support_ * support_);
  const auto no_walls = [](const Index*, int, const auto&, int) {};  // pair_pass false: none
  parallel::region([&](const parallel::Team& team) {
    for_each_particle_candidates<false>(team, [&](Index a, const auto& ranges, int range_count) {
      Index count = 0;
      for (int r = 0; r < range_count; ++r)
        for (Index b = ranges[r].begin; b < ranges[r].end; ++b) {
          const float dx = record_[a].x - record_[b].x, dy = record_[a].y - record_[b].y,
                      dz = record_[a].z - record_[b].z;
          count += (dx * dx + dy * dy + dz * dz < H2) & (b != a);
        }
      counts[a] = count;
    }, no_walls);
  });
  return counts;
}

void FluidFormulation::book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore&,
                                     std::span<const Vec3> v, Real dt) const {
  discretization::book_internal_power(ledger, internal_power(v), dt);
}

void FluidFormulation::sum_parts(discretization::PartSummary& parts, const discretization::NodeStore& nodes) const {
  // Five-point Gauss-Legendre on [rho0, rho]: the integrand is smooth over the percent or so that
  // a weakly compressible liquid is compressed (exact to 1e-12 for Tait's gamma 7 at 1 %).
  static constexpr Real node[5] = {-0.9061798459386640, -0.5384693101056831, 0, 0.5384693101056831,
                                   0.9061798459386640};
  static constexpr Real weight[5] = {0.2369268850561891, 0.4786286704993665, 0.5688888888888889,
                                     0.4786286704993665, 0.2369268850561891};
  const Real rho0 = parameters_.material.density;
  for (Index a = 0; a < particle_count(); ++a) {
    if (!owns(a) || nodes.fixed[node_[a]] == all_translations) continue;
    const Real half = Real(0.5) * (density_[a] - rho0), middle = Real(0.5) * (density_[a] + rho0);
    Real e = 0;
    for (int k = 0; k < 5; ++k) {
      const Real r = middle + half * node[k];
      e += weight[k] * parameters_.material.pressure(r) / (r * r);
    }
    parts.add(nodes.part[node_[a]], discretization::PartSummary::internal_energy, Real(mass_[a]) * half * e);
  }
}

void FluidFormulation::write_fields(discretization::FieldSet& fields, const discretization::NodeStore&) const {
  const auto pressure = fields.node_real("pressure"), density = fields.node_real("density"),
             smoothing = fields.node_real("smoothing_length");
  const auto neighbour_count = fields.node_integer("neighbour_count");
  const auto counts = neighbour_counts();
  for (Index a = 0; a < particle_count(); ++a) {
    const Index i = node_[a];
    pressure[i] = parameters_.material.pressure(density_[a]);
    density[i] = density_[a];
    smoothing[i] = parameters_.smoothing_length;
    neighbour_count[i] = counts[a];
  }
}

std::size_t FluidFormulation::memory_bytes() const {
  std::size_t total = bytes(node_) + bytes(mass_) + bytes(density_) + bytes(rate_) +
                      bytes(previous_rate_) + bytes(record_) + bytes(pressure_force_) +
                      bytes(viscous_force_) + bytes(moving_) + bytes(active_cell_) + bytes(near_owned_cell_);
  return total + cells_.memory_bytes();
}

Real FluidFormulation::max_wave_speed() const { return max_sound_speed_; }

namespace {
// A particle in a checkpoint: the key of the cell it was binned in at the last rebuild, its node's
// place in the deck, its continuity state, its last record and forces.
struct SavedParticle {
  neighbors::CellKey bin;
  std::int64_t global;
  Real density;
  float rate, previous_rate;
  float record[8];
  float pressure_force[3], viscous_force[3];
};
static_assert(sizeof(FluidRecord) == sizeof(SavedParticle::record));
}  // namespace

// What decides the next rebuild, the cells' grid, then the particles in pieces (core/pieces.hpp):
// dealt by region each rank's own, else rank 0's every particle (complete there). Read back on
// every rank into the whole set-up's particles, which take the cells every rank would have built
// at the last rebuild from the keys their ranks binned them at (make_cells_whole).
void FluidFormulation::checkpoint(Archive& a, const discretization::NodeStore& nodes) {
  a.section("sph fluid");
  Vec3 lower = cells_.lower();
  Real cell_size = cells_.cell_size();
  std::array<std::int64_t, 3> along = cells_.cells_along();
  a(support_, uniform_mass_, origin_, rounding_margin_, cells_built_, first_pass_, travelled_, max_speed_,
    max_sound_speed_, max_acceleration_, max_mu_, lower, cell_size, along);
  const parallel::Communicator& ranks = parallel::world();
  if (!a.reading()) {
    // Its own particles in their nodes' order in the deck, each with its cell's key (none while no
    // cell is built yet): the cells hold the particles in their order, one run after the other.
    const bool each_own = nodes.by_region();
    std::vector<std::pair<Index, Index>> written;  // (place in the deck, particle), sorted
    for (Index p = 0; p < particle_count(); ++p)
      if (each_own ? owns(p) : ranks.rank() == 0) written.emplace_back(nodes.deck_index(node_[p]), p);
    std::sort(written.begin(), written.end());
    std::vector<Index> cell_of(cells_built_ ? particle_count() : 0);
    for (Index c = 0; cells_built_ && c < cells_.cell_count(); ++c)
      std::fill(cell_of.begin() + cells_.cell(c).begin, cell_of.begin() + cells_.cell(c).end, c);
    const auto save = [&](Index k) {
      const auto [place, p] = written[k];
      SavedParticle saved{cells_built_ ? cells_.cell_key(cell_of[p]) : 0, place, density_[p], rate_[p],
                          previous_rate_[p], {}, {}, {}};
      std::memcpy(saved.record, &record_[p], sizeof saved.record);
      for (int d = 0; d < 3; ++d) {
        saved.pressure_force[d] = pressure_force_[3 * p + d];
        saved.viscous_force[d] = viscous_force_[3 * p + d];
      }
      return saved;
    };
    parallel::write_pieces<SavedParticle>(a, static_cast<Index>(written.size()), save,
                                          [&](Index k) { return written[k].first; }, ranks);
    return;
  }
  // Into the set-up's particles, each on its node's row: every particle, or those on the block of
  // rows that the set-up in blocks built (the others are read past), which then go to their
  // regions' ranks with their keys (rebuild_near_region). A particle on a node that carries none
  // here, or given twice, or one missing, stops every rank alike.
  const bool block = !nodes.holds_every_node();
  const Index n = particle_count();
  std::vector<Index> slot(nodes.size(), -1);
  for (Index k = 0; k < n; ++k) slot[node_[k]] = k;
  std::vector<neighbors::CellKey> key(n);
  std::vector<std::uint8_t> filled(n, 0);
  record_.resize(n + simd_width + 1);
  Index mismatch = -1;
  const auto [first, end] = nodes.places_held();
  parallel::read_pieces<SavedParticle>(a, [&](const SavedParticle& p) {
    const Index place = static_cast<Index>(p.global);
    const bool in_deck = place >= 0 && place < nodes.deck_node_count();
    const Index i = in_deck ? nodes.row_of(place) : -1;
    if (block && in_deck && i < 0) return;  // another rank's block
    const Index k = i < 0 ? -1 : slot[i];
    if (k < 0 || filled[k]++) {
      if (mismatch < 0) mismatch = std::max<Index>(place, 0);
      return;
    }
    mass_[k] = static_cast<float>(nodes.mass[i]);
    density_[k] = p.density;
    rate_[k] = p.rate;
    previous_rate_[k] = p.previous_rate;
    key[k] = p.bin;
    std::memcpy(&record_[k], p.record, sizeof p.record);
    for (int d = 0; d < 3; ++d) {
      pressure_force_[3 * k + d] = p.pressure_force[d];
      viscous_force_[3 * k + d] = p.viscous_force[d];
    }
  }, first, end, block ? &ranks : nullptr);
  const auto unfilled = std::find(filled.begin(), filled.end(), 0);
  Index missing = unfilled == filled.end() ? -1 : nodes.deck_index(node_[static_cast<Index>(unfilled - filled.begin())]);
  parallel::check_read(a, "SPH fluid particle on the node", mismatch, missing, block ? &ranks : nullptr);
  complete_ = true;
  if (!cells_built_) return;
  if (block)
    binned_ = BinnedAt{std::move(key), lower, cell_size, along};
  else
    make_cells_whole(nodes, key, lower, cell_size, along);
}

}  // namespace spall::sph
