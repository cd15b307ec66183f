#include "spall/sph/solid.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numeric>
#include <type_traits>

#include <fmt/core.h>

#include "spall/core/cube_root.hpp"
#include "spall/core/error.hpp"
#include "spall/core/bounding_box.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/simd.hpp"
#include "spall/discretization/particle_pieces.hpp"
#include "spall/neighbors/near_particles.hpp"
#include "spall/materials/elastic.hpp"
#include "spall/materials/radial_return.hpp"

namespace spall::sph {

namespace {
// Support radius of the pair: the mean of both particles' supports 2h keeps W_ab symmetric
// (T = Real or simd::Pack).
template <typename T>
inline T pair_support(T ha, T hb) {
  return ha + hb;
}

// Verlet skin as a fraction of the largest pair cutoff: a rebuild every few tens of steps at most.
constexpr Real skin_fraction = 0.1;
// Each particle's reach in the list exceeds its h by this factor, so that a growing smoothing
// length does not force a rebuild at every step.
constexpr Real cutoff_margin = 1.05;

// Below this the moment matrix is too ill-conditioned to invert (an isolated particle, or one
// whose neighbours lie in a plane): the particle keeps the uncorrected gradient.
constexpr Real min_moment_determinant = 1e-3;

// The force pass takes each pair once when the particles fall into at least this many blocks
// (compute_pair_forces): half of them at a time run side by side.
constexpr Index min_force_blocks = 8;

// A B and A B^T of 3x3 matrices, element by element. Eigen's two-lane forms of these products
// store single lanes of their temporaries and reload them as pairs, which stalls store forwarding
// (a third of update_state in perf annotate, when the Jaumann rotation still took two products).
Mat3 product(const Mat3& A, const Mat3& B) {
  Mat3 C;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) C(i, j) = A(i, 0) * B(0, j) + A(i, 1) * B(1, j) + A(i, 2) * B(2, j);
  return C;
}
Mat3 product_transposed(const Mat3& A, const Mat3& B) {
  Mat3 C;
  for (int j = 0; j < 3; ++j)
    for (int i = 0; i < 3; ++i) C(i, j) = A(i, 0) * B(j, 0) + A(i, 1) * B(j, 1) + A(i, 2) * B(j, 2);
  return C;
}

// The symmetric matrix of the six independent entries xx, yy, zz, xy, yz, zx at s, times sign.
Mat3 symmetric(const Real* s, Real sign) {
  Mat3 m;
  m(0, 0) = sign * s[0], m(1, 1) = sign * s[1], m(2, 2) = sign * s[2];
  m(0, 1) = m(1, 0) = sign * s[3];
  m(1, 2) = m(2, 1) = sign * s[4];
  m(0, 2) = m(2, 0) = sign * s[5];
  return m;
}

// The inverse of a symmetric 3x3 matrix by its cofactors, if its determinant exceeds `least`
// (else `inverse` is left as it is).
bool invert_symmetric(const Mat3& m, Real least, Mat3& inverse) {
  const Real c00 = m(1, 1) * m(2, 2) - m(1, 2) * m(1, 2);
  const Real c01 = m(0, 2) * m(1, 2) - m(0, 1) * m(2, 2);
  const Real c02 = m(0, 1) * m(1, 2) - m(0, 2) * m(1, 1);
  const Real det = m(0, 0) * c00 + m(0, 1) * c01 + m(0, 2) * c02;
  if (!(det > least)) return false;
  const Real c11 = m(0, 0) * m(2, 2) - m(0, 2) * m(0, 2);
  const Real c12 = m(0, 1) * m(0, 2) - m(0, 0) * m(1, 2);
  const Real c22 = m(0, 0) * m(1, 1) - m(0, 1) * m(0, 1);
  // Element by element (the comma initializer and /= det went through the stack in two-lane
  // pieces, a store-forwarding stall).
  const Real cofactor[9] = {c00, c01, c02, c01, c11, c12, c02, c12, c22};
  const Real inverse_det = 1 / det;
  for (int k = 0; k < 9; ++k) inverse.data()[k] = cofactor[k] * inverse_det;
  return true;
}

}  // namespace

// The pair loops run on eight single-precision lanes, a pair per lane (simd::Float8), from the
// particles' records (PairRecord, StressRecord): the geometry, the velocity gradient and the pair
// forces in float, the sums that must cancel pair by pair (forces, viscosity) widened to double.
// Every pair term is computed by the same operations whichever side computes it, so that (a, b)
// gets exactly the opposite of (b, a) (docs/THEORY.md §3).
using simd::Float8;
constexpr int pair_lanes = Float8::width;
constexpr int record_stride = sizeof(PairRecord) / sizeof(float);
constexpr int viscosity_stride = sizeof(ViscosityRecord) / sizeof(float);
constexpr int stress_stride = sizeof(StressRecord) / sizeof(float);
constexpr int plain_stress_stride = sizeof(PlainStressRecord) / sizeof(float);
static_assert(record_stride == 8 && viscosity_stride == 2 && stress_stride == 12 && plain_stress_stride == 8);

// The pairs of one Verlet row inside their support (r < H_ab = h_a + h_b), per thread, padded with
// the particle itself to a multiple of the pack width (a pair at r = 0 has no gradient, so the
// padding adds exact zeros): neighbour, x_a - x_b, r, H_ab, the gradient factor F = (dW/dr) / r
// (grad_a W_ab = F (x_a - x_b); 0 at r = 0), the weight V_b F and v_b - v_a, for the rates
// pass's later loops, and the viscosity's m_a m_b Pi_ab F and 1/2 m_b Pi_ab F v_ab . x_ab. About
// a third of a Verlet row lies outside the support (the skin and the reach margin).
struct RowTerms {
  std::vector<Index> neighbour;  // the pairs kept
  std::vector<float> dx, dy, dz, r, support, factor, weight, dvx, dvy, dvz, viscous, heating;
  // Room for n pairs and a pack past them; taken at every row, so the test is inlined and the
  // growth, rare after the first rows, is not.
  void resize(std::size_t n) {
    if (r.size() < n + pair_lanes) [[unlikely]]
      grow(n + pair_lanes);
  }
  [[gnu::noinline]] void grow(std::size_t size) {
    neighbour.resize(size);
    for (auto* v : {&dx, &dy, &dz, &r, &support, &factor, &weight, &dvx, &dvy, &dvz, &viscous, &heating})
      v->resize(size);
  }
};

// Particle a's side of its pairs, broadcast over a pack, from its record.
struct PackCentre {
  Float8 x, y, z, h;
  explicit PackCentre(const PairRecord& r) : x(r.x), y(r.y), z(r.z), h(r.h) {}
};

// x_a - x_b of a pack of pairs from the neighbours' x, y, z, h (c[0..3]); returns r^2.
[[gnu::always_inline]] inline Float8 pair_difference(const PackCentre& a, const Float8* c, Float8& dx, Float8& dy,
                                                     Float8& dz) {
  dx = a.x - c[0], dy = a.y - c[1], dz = a.z - c[2];
  return fma(dz, dz, fma(dy, dy, dx * dx));
}

// The geometry of a pack of pairs inside their support (or padding, r = 0).
struct PairGeometry {
  Float8 dx, dy, dz, r, support, factor, inverse_r;
};
template <typename Kernel>
[[gnu::always_inline]] inline PairGeometry pair_geometry(const PackCentre& a, const Float8* c) {
  PairGeometry g;
  const Float8 r2 = pair_difference(a, c, g.dx, g.dy, g.dz);
  g.support = pair_support(a.h, c[3]);
  const auto defined = r2 > Float8(0);  // inside the support, by the pick
  g.inverse_r = select(defined, reciprocal_sqrt(r2), Float8(0));
  g.r = r2 * g.inverse_r;
  g.factor = select(defined, Kernel::gradient_factor(g.r, g.inverse_r, reciprocal(g.support)), Float8(0));
  return g;
}

// (v, 0), a row of SolidFormulation::force_.
inline Eigen::Vector4d force_row(const Vec3& v) { return {v.x(), v.y(), v.z(), 0}; }

// m_b of a pack of pairs: the one mass of a lattice broadcast (uniform > 0), else gathered from
// mass (from the first particle the records hold on, as the pair loops index them).
inline Float8 pair_mass(const float* mass, Real uniform, const Index* b) {
  return uniform > 0 ? Float8(static_cast<float>(uniform)) : Float8::gather<1>(mass, b);
}

// The first byte of particle a's support mask: one byte per pack of its Verlet row (bit i: lane i
// is inside the support), each row starting on a byte of its own so that threads never share one.
inline std::size_t mask_start(const neighbors::NeighborList& list, Index a) {
  return static_cast<std::size_t>(list.offsets[a] / pair_lanes) + a;
}
inline std::size_t mask_bytes(const neighbors::NeighborList& list) {
  return mask_start(list, static_cast<Index>(list.offsets.size()) - 1) + 1;
}

// Keeps the entries of particle a's Verlet row that lanes(b, present) selects, a pack b at a time
// (`present` masks the lanes past the row's end), in terms.neighbour, padded with a itself to a
// multiple of the pack width, each less `origin`: the pair loops index the records from the first
// particle they hold (the records' held_begin()). Returns the padded count.
template <typename Lanes>
[[gnu::always_inline]] inline Index keep_row(const neighbors::NeighborList& list, Index a, Index origin,
                                             RowTerms& terms, Lanes&& lanes) {
  constexpr int W = pair_lanes;
  const Index first = list.offsets[a];
  const Index count = list.offsets[a + 1] - first;
  terms.resize(count + W);
  const Index* row = list.neighbors.data() + first;
  // A raw pointer: the vector's own would be reloaded at every store, which may alias anything.
  Index* neighbour = terms.neighbour.data();
  // The row's last, partial pack, padded with the particle itself.
  Index tail[W];
  const Index full = count / W * W;
  Float8::padded_indices(row + full, static_cast<int>(count - full), a, tail);
  Index kept = 0;
  const auto keep = [&](const Index* b, int present) {
    const int selected = lanes(b, present);
    Float8::compress_indices(b, selected, neighbour + kept);
    kept += std::popcount(static_cast<unsigned>(selected));
  };
  for (Index k = 0; k < full; k += W) keep(row + k, (1 << W) - 1);
  if (full < count) keep(tail, (1 << (count - full)) - 1);
  const Index padded = (kept + W - 1) / W * W;
  std::fill(neighbour + kept, neighbour + padded, a);
  if (origin != 0)  // under MPI; one process holds every particle
    for (Index k = 0; k < padded; ++k) neighbour[k] -= origin;
  return padded;
}

// Asks for the Verlet row of the particle `row_lead` rows after a, every sixteenth index (a cache
// line's worth) from its first. The pick reads the list (some 80 indices a particle, over 300
// bytes) once a step, too large for the caches, and the processor's own prefetch missed it: the
// loads of each row's first pack and of its last, partial pack (which comes first) waited on
// memory, a quarter of the pick's time (perf). Six or twelve rows ahead measured the same within
// the noise, every line to the row's exact end 1.3 % slower, and the force pass's pick gained
// nothing from it (docs/PERFORMANCE.md, session 25).
constexpr std::size_t row_lead = 3;
[[gnu::always_inline]] inline void prefetch_row_ahead(const neighbors::NeighborList& list, Index a) {
  constexpr Index line = 64 / sizeof(Index);
  const std::size_t next = static_cast<std::size_t>(a) + row_lead;
  if (next + 1 >= list.offsets.size()) return;
  for (Index k = list.offsets[next]; k < list.offsets[next + 1]; k += line) __builtin_prefetch(list.neighbors.data() + k);
}

// Picks the neighbours of particle a inside their support (keep_row) and records the pick in
// mask (mask_start); records from particle `origin` on.
Index pick_support(const neighbors::NeighborList& list, Index a, const PairRecord* records, Index origin,
                   std::uint8_t* mask, RowTerms& terms) {
  const PackCentre centre(records[a - origin]);
  mask += mask_start(list, a);
  prefetch_row_ahead(list, a);
  return keep_row(list, a, origin, terms, [&](const Index* b, int present) {
    Float8 c[4];
    if (origin == 0) {  // one process holds every particle
      simd::load_rows<record_stride>(&records->x, b, 0, c);
    } else {
      Index held[pair_lanes];
      for (int i = 0; i < pair_lanes; ++i) held[i] = b[i] - origin;
      simd::load_rows<record_stride>(&records->x, held, 0, c);
    }
    Float8 dx, dy, dz;
    const Float8 r2 = pair_difference(centre, c, dx, dy, dz);
    const Float8 H = pair_support(centre.h, c[3]);
    const int inside = (r2 < H * H).lanes() & present;
    *mask++ = static_cast<std::uint8_t>(inside);
    return inside;
  });
}

// The pick that pick_support recorded in mask, again (the force pass, at the rates pass's h):
// every pair of the row, or (half) only those with b > a, each pair once.
template <bool half>
Index picked_support(const neighbors::NeighborList& list, Index a, Index origin, const std::uint8_t* mask,
                     RowTerms& terms) {
  mask += mask_start(list, a);
  return keep_row(list, a, origin, terms, [&](const Index* b, int) {
    if constexpr (half) return *mask++ & Float8::indices_above(b, a);
    return int(*mask++);
  });
}

SolidFormulation::SolidFormulation(std::vector<materials::Material> materials,
                                   const std::vector<ParticleSetup>& particles,
                                   SolidOptions options, const discretization::NodeStore& nodes,
                                   const parallel::Communicator* across)
    : materials_(std::move(materials)), options_(options), set_up_in_blocks_(across != nullptr) {
  // This rank's particles are [first, end) of every particle (all of them but in blocks).
  const auto held = static_cast<Index>(particles.size());
  Index first = 0, n = held;
  if (across) {
    const std::vector<Index> counts = across->each(held);
    first = std::accumulate(counts.begin(), counts.begin() + across->rank(), Index(0));
    n = std::accumulate(counts.begin(), counts.end(), Index(0));
  }
  const Index end = first + held;
  // Particles in node order: the node store is in cell order, so that neighbours are close in
  // memory, and a formulation owning a contiguous run of nodes reads their x and v in place.
  std::vector<std::size_t> by_node(held);
  std::iota(by_node.begin(), by_node.end(), std::size_t{0});
  std::stable_sort(by_node.begin(), by_node.end(),
                   [&](std::size_t i, std::size_t j) { return particles[i].node < particles[j].node; });
  node_.resize(held);
  for (Index k = 0; k < held; ++k) node_[k] = particles[by_node[k]].node;
  if (across) node_ = across->all(std::span<const Index>(node_));  // each node's place, every rank's block
  list_reach_.resize(0);
  list_reach_.hold(first, end);
  // The set-up's constants of this rank's particles: every particle's, which under MPI each rank
  // cuts to its own at the first list build; in blocks its own from the start.
  constants_held_ = across && across->size() > 1;
  for (auto* constant : {&mass_, &initial_smoothing_length_, &spacing_}) {
    constant->resize(0);
    constant->hold(first, end);
  }
  material_.resize(0);
  material_.hold(first, end);
  std::vector<std::uint8_t> used(materials_.size(), 0);
  h_bounds_.resize(materials_.size());
  full_support_gradient_ = kernels::with_kernel(options_.kernel, options_.dimension, [](auto kernel) {
    return kernels::gradient_norm_integral<decltype(kernel)>();
  });
  for (Index a = first; a < end; ++a) {
    const auto& p = particles[by_node[a - first]];
    material_[a] = p.material;
    used[p.material] = 1;
    mass_[a] = nodes.mass[nodes.row_of(p.node)];
    initial_smoothing_length_[a] = p.smoothing_length;
    h_bounds_[p.material] = {p.h_min_factor, p.h_max_factor};
    spacing_[a] = p.spacing;
  }
  for (const auto& m : materials_)
    if (std::holds_alternative<materials::JohnsonCook>(m.strength)) has_temperature_ = true;
  // Whether every particle has one mass (a lattice): the pair loops then broadcast it instead of
  // gathering it (masses never change). In blocks over the ranks, as minima: the least mass, the
  // largest negated, and each material's use and bounds on h negated (a rank knows those of the
  // materials of its particles).
  std::vector<double> least{std::numeric_limits<double>::infinity(), std::numeric_limits<double>::infinity()};
  for (Index a = first; a < end; ++a) least = {std::min(least[0], mass_[a]), std::min(least[1], -mass_[a])};
  for (std::size_t k = 0; k < materials_.size(); ++k)
    least.insert(least.end(), {-double(used[k]), -h_bounds_[k].lower, -h_bounds_[k].upper});
  if (across) across->minimum(least);
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    used[k] = least[2 + 3 * k] < 0;
    h_bounds_[k] = {-least[3 + 3 * k], -least[4 + 3 * k]};
  }
  if (n > 0 && least[0] == -least[1]) {
    uniform_mass_ = least[0];
  } else {
    record_mass_.resize(0);
    record_mass_.hold(first, end);
    for (Index a = first; a < end; ++a) record_mass_[a] = static_cast<float>(mass_[a]);
  }
  // The set-up's state (set_up_state) of every material a particle has.
  for (std::size_t k = 0; k < materials_.size(); ++k) {
    const materials::Material& m = materials_[k];
    if (used[k])
      max_wave_speed_ = std::max(max_wave_speed_, materials::sound_speed(m, m.density, m.initial_specific_energy));
  }
  bool contiguous = n > 0;
  for (Index a = 1; a < n && contiguous; ++a) contiguous = node_[a] == node_[0] + a;
  first_node_ = contiguous ? node_[0] : -1;

  // The state's arrays that the options ask for, holding no particle until set_up_state.
  const auto on = [](auto&... arrays) { (arrays.resize(0), ...); };
  on(smoothing_length_, record_, viscosity_record_, density_, volume_, updated_volume_, pressure_, sound_speed_,
     updated_sound_speed_, internal_energy_, state_, gradient_amplification_, strain_rate_squared_, viscous_heating_,
     force_, viscous_force_);
  if (options_.gradient_correction)
    on(stress_);
  else
    on(plain_stress_);
  if (options_.artificial_stress.enabled) on(artificial_stress_);
  if (std::any_of(materials_.begin(), materials_.end(), materials::keeps_back_stress)) on(back_stress_);
  const bool colour = std::any_of(options_.colour_field.begin(), options_.colour_field.end(),
                                  [](const ColourField& c) { return c.enabled; });
  if (colour) {
    on(colour_, colour_normal_, support_count_, category_, density_rate_, velocity_gradient_, correction_);
    if (std::any_of(options_.colour_field.begin(), options_.colour_field.end(),
                    [](const ColourField& c) { return c.enabled && c.treat && !c.literal; }))
      on(exported_deviator_);
    full_support_count_.resize(0);
    full_support_count_.hold(first, end);
    // Particles of spacing dp in a sphere (circle) of radius 2h, less the particle itself.
    for (Index a = first; a < end; ++a) {
      const Real ratio = 2 * initial_smoothing_length_[a] / spacing_[a];
      full_support_count_[a] = options_.dimension == 2 ? M_PI * ratio * ratio - 1
                                                       : 4 * M_PI / 3 * ratio * ratio * ratio - 1;
    }
  }
  // One process sets up every particle's state now; under MPI each rank its own particles' once
  // the nodes are dealt (compute_forces), so that no rank builds every particle's.
  if (parallel::world().size() == 1) set_up_state({0, n});
}

void SolidFormulation::set_up_state(neighbors::ParticleRange range) {
  hold_own_state(range);
  hold_read_state(range);
  for (Index a = range.begin; a < range.end; ++a) {
    const auto& m = materials_[material_[a]];
    smoothing_length(a) = initial_smoothing_length_[a];
    density_[a] = m.density;
    volume_[a] = mass_[a] / density_[a];
    updated_volume_[a] = volume_[a];
    state_[a] = materials::initial_state(m);
    internal_energy_[a] = m.initial_specific_energy;
    pressure_[a] = materials::eos_pressure(m, m.density, internal_energy_[a]);
    sound_speed_[a] = materials::sound_speed(m, m.density, internal_energy_[a]);
    updated_sound_speed_[a] = sound_speed_[a];
    gradient_amplification_[a] = 1;
    strain_rate_squared_[a] = 0;
    viscous_heating_[a] = 0;
    force_[a] = Eigen::Vector4d::Zero();
    viscous_force_[a] = Vec3::Zero();
    if (!artificial_stress_.empty()) artificial_stress_[a] = Mat3::Zero();
    if (!back_stress_.empty()) back_stress_[a] = Mat3::Zero();
    if (!colour_.empty()) {
      colour_[a] = 0;
      colour_normal_[a] = Vec3::Zero();
      support_count_[a] = 0;
      category_[a] = Category::interior;
      density_rate_[a] = 0;
      velocity_gradient_[a] = Mat3::Zero();
      correction_[a] = Mat3::Identity();
    }
    if (!exported_deviator_.empty()) exported_deviator_[a] = state_[a].deviatoric_stress;
    record_stress(a, Mat3::Zero(), Mat3::Identity());
  }
  set_up_ = true;
}

bool SolidFormulation::active(Real time) const {
  return time >= options_.start_time && time <= options_.death_time;
}

void SolidFormulation::gather_kinematics(const discretization::NodeStore& nodes) {
  const Index n = particle_count();
  if (first_node_ >= 0 && !nodes.windowed()) {
    x_ = std::span<const Vec3>(nodes.x).subspan(first_node_, n);
    v_ = std::span<const Vec3>(nodes.v).subspan(first_node_, n);
    return;
  }
  // Copies of the stretch of particles whose nodes the store holds (every particle but for a window).
  const Index held = nodes.window_first();  // the place of the first row (0 but for a window)
  const auto particle_at = [&](Index place) {
    return static_cast<Index>(std::lower_bound(node_.begin(), node_.end(), place) - node_.begin());
  };
  const Index first = particle_at(held), end = particle_at(held + nodes.size());
  for (auto* copy : {&x_copy_, &v_copy_}) {
    if (copy->empty()) copy->resize(0);  // on
    copy->hold(first, end);
  }
  parallel::for_each(parallel::Range{first, end}, [&](Index a) {
    x_copy_[a] = nodes.x[row(nodes, a)];
    v_copy_[a] = nodes.v[row(nodes, a)];
  });
  x_ = StretchView<Vec3>(x_copy_.data(), first, end - first, n);
  v_ = StretchView<Vec3>(v_copy_.data(), first, end - first, n);
}

// The particles of this step into the records of the pair loops.
void SolidFormulation::update_records() {
  const neighbors::ParticleRange reads = read_state_held();
  parallel::for_each(reads, [&](Index a) {
    if (!current(a)) return;  // read by no row this rank computes
    const Vec3 x = x_[a] - record_origin_;
    const Vec3& v = v_[a];
    record_[a] = {static_cast<float>(x[0]), static_cast<float>(x[1]), static_cast<float>(x[2]),
                  static_cast<float>(smoothing_length(a)), static_cast<float>(v[0]), static_cast<float>(v[1]),
                  static_cast<float>(v[2]), static_cast<float>(volume_[a])};
    viscosity_record_[a] = {static_cast<float>(sound_speed_[a]), static_cast<float>(density_[a])};
  });
}

// The list holds every pair within reach_a + reach_b + skin at the build, reach = cutoff_margin h
// of that build; it stays complete while no two particles within the cutoff have moved by more
// than the skin relative to each other (VerletList::needs_rebuild) and no h_a has outgrown its
// reach. A per-pair reach keeps the rows of particles with the common h short when a few others
// (the rim of a splashing foot) expand.
void SolidFormulation::update_neighbour_list(discretization::NodeStore& nodes) {
  const Index n = particle_count();
  // Under MPI each rank tests its own particles' motion (the others' may be stale), the answer
  // every rank's (as h_outgrown_ is).
  const parallel::Communicator& ranks = parallel::world();
  const auto moved_apart = [&] {
    return ranks.size() > 1 ? verlet_.needs_rebuild(x_, own_particles(), ranks) : verlet_.needs_rebuild(x_);
  };
  if (list_built_ && !h_outgrown_ && !moved_apart()) return;
  // One process, or the first build of a set-up whole (every particle's position is current on
  // every rank then): every particle binned; every row searched by one process, a rank's own under
  // MPI (the rows it computes are known once the force blocks' length is, below), each rank's
  // reaches of its own particles to every rank. Under MPI after that, and from the first build when
  // set up in blocks, a rank searches the rows it computes, from its own particles and the others'
  // within reach of those rows (search_near_rows).
  const bool distributed = ranks.size() > 1, whole_state = !distributed || (!list_built_ && !set_up_in_blocks_);
  const bool first_near = distributed && !list_built_ && set_up_in_blocks_;
  BoundingBox box;
  if (whole_state) {
    const neighbors::ParticleRange rows = distributed ? own_particles() : neighbors::ParticleRange{0, n};
    Real h_largest = parallel::reduce_exact(
        rows, Real(0),
        [&](Index a) {
          list_reach_[a] = cutoff_margin * smoothing_length(a);
          return smoothing_length(a);
        },
        [](Real a, Real b) { return std::max(a, b); });
    if (distributed) {
      // The constants from now on as the state: a rank's own, and its read stretch's (its own
      // particles until the list says which others its rows read, plan_reach).
      constants_held_ = true;
      hold_own_state(rows);
      hold_read_state({smoothing_length_.held_begin(), smoothing_length_.held_end()});
      h_largest = ranks.largest(h_largest);
      share_(node_, list_reach_);
    }
    verlet_.build(x_, list_reach(), list_skin(h_largest), neighbors::RowOrder::search, rows);
    box = verlet_.grid();  // every particle's box, which the build binned them in
  } else {
    box = search_near_rows(nodes);
  }
  list_built_ = true;
  // The records' origin: the middle of the particles' bounding box.
  if (!box.empty()) record_origin_ = box.centre();
  // The force pass's blocks (compute_pair_forces): as long as the largest b - a of any pair (every
  // row is some rank's own: over the ranks, the largest of their own rows').
  const auto& list = verlet_.list();
  const neighbors::ParticleRange own = own_particles();
  Index span = parallel::reduce_exact(
      own.end - own.begin, Index(1),
      [&](Index j) {
        const Index a = own.begin + j;
        Index longest = 1;
        for (Index k = list.offsets[a]; k < list.offsets[a + 1]; ++k) longest = std::max(longest, list.neighbors[k] - a);
        return longest;
      },
      [](Index a, Index b) { return std::max(a, b); });
  if (distributed) {
    span = static_cast<Index>(parallel::world().largest(static_cast<double>(span)));
  }
  force_block_length_ = span;
  force_blocks_ = (n + span - 1) / span;
  if (force_blocks_ < min_force_blocks) force_blocks_ = 0;
  choose_force_blocks(nodes);
  if (!distributed) return;
  // The first build under MPI searched a rank's own rows: now those its force blocks may run too,
  // from every particle's position at the build, or set up in blocks, searched again from the
  // particles near them.
  if (whole_state) verlet_.search_rows(list_reach().every(), rows_searched(own_particles()));
  if (first_near && force_blocks_ > 0) search_near_rows(nodes);
  // Blocks longer than the last build's reach rows it did not search: every row then, from every
  // particle's position at the build, and its rows' particles' positions, velocities and h, which
  // the ranks complete together when one needs them.
  const bool unsearched = !verlet_.searched(computed_rows());
  if (ranks.any(unsearched)) {
    complete_list();
    if (nodes.window_by_reads) {  // every node is read now
      nodes.hold_window(0, nodes.deck_node_count());
      gather_kinematics(nodes);
    }
    complete_kinematics(nodes);
    // Every particle's h and the constants the rows read, each rank's own (held already) in.
    hold_read_state({0, n});
    share_(node_, smoothing_length_, material_, initial_smoothing_length_, mass_, spacing_, record_mass_);
  }
  if (unsearched) verlet_.search_every_row(list_reach().every());
  keep_own_list_state();
}

Real SolidFormulation::list_skin(Real h_largest) { return skin_fraction * cutoff_margin * 2 * h_largest; }

namespace {
// A particle that comes in at a list build from its rank (search_near_rows).
struct NearParticle {
  std::int64_t particle;  // 64 bits: no padding travels
  Vec3 x, v;
  Real h;
};
// A box as it travels between the ranks (no padding bytes).
using BoxBounds = std::array<double, 6>;
BoxBounds bounds_of(const BoundingBox& box) {
  return {box.lower[0], box.lower[1], box.lower[2], box.upper[0], box.upper[1], box.upper[2]};
}
BoundingBox box_of(const BoxBounds& b) {
  BoundingBox box;
  box.lower = Vec3(b[0], b[1], b[2]);
  box.upper = Vec3(b[3], b[4], b[5]);
  return box;
}

}  // namespace

// Rank r searches the rows of its own particles and, with pair-once blocks, those within 0.75 L of
// them (L the last build's block length): each force block is run by the owner of its middle
// particle, so no rank computes rows further than half a block from its own, and 0.75 L holds the
// rows of blocks up to 1.5 L long (they grow as a body deforms; longer ones have every row searched,
// update_neighbour_list: with 0.625 L the 10^5-particle Taylor bar's blocks outgrew it once a rank).
neighbors::ParticleRange SolidFormulation::rows_searched(neighbors::ParticleRange own) const {
  if (force_blocks_ == 0 || own.begin >= own.end) return own;
  const Index margin = (3 * force_block_length_ + 3) / 4;
  return {std::max<Index>(0, own.begin - margin), std::min(particle_count(), own.end + margin)};
}

// The ranks own blocks of the node order, in which the particles are stored: rank r's particles
// are those from the first whose node's rank is r to the first whose node's rank is above.
neighbors::ParticleRange SolidFormulation::particles_of(int r, const discretization::ParticleShare& share) const {
  const auto first_of_rank_above = [&](int q) {
    Index low = 0, high = particle_count();
    while (low < high) {
      const Index mid = low + (high - low) / 2;
      if (share.rank_of(node_[mid]) < q)
        low = mid + 1;
      else
        high = mid;
    }
    return low;
  };
  return {first_of_rank_above(r), first_of_rank_above(r + 1)};
}

// Every pair a row holds is within reach_a + reach_b + skin <= the list radius of the row's
// particle, so a rank's rows need the particles within that radius of its rows' box (with a margin
// for the rounding of the search's distances): those come in from their ranks with their velocities
// and h, in place of every particle's position, velocity and h completed on every rank. The grid is
// that of every particle's box (one minimum): cells, their order and the particles in each (by
// index) are then the whole build's, and so is every row searched. Returns that box.
BoundingBox SolidFormulation::search_near_rows(discretization::NodeStore& nodes) {
  const parallel::Communicator& ranks = parallel::world();
  const neighbors::ParticleRange own = own_particles();
  list_reach_.hold(own.begin, own.end);  // those that come in below too, once known
  struct Own {
    BoundingBox box;
    Real h = 0;
  };
  const Own mine = parallel::fold_exact(
      own, Own{},
      [&](Own& o, Index a) {
        list_reach_[a] = cutoff_margin * smoothing_length(a);
        o.box.include(x_[a]);
        o.h = std::max(o.h, smoothing_length(a));
      },
      [](Own& o, const Own& other) {
        o.box.include(other.box);
        o.h = std::max(o.h, other.h);
      });
  const BoundingBox grid = over_ranks(mine.box, ranks);
  if (!grid.finite) {
    Index worst = -1;
    for (Index a = own.begin; a < own.end && worst < 0; ++a)
      if (!x_[a].allFinite()) worst = a;
    throw InstabilityError(
        fmt::format("neighbour search: particle {} has a non-finite position", ranks.lowest(worst)));
  }
  const Real h_largest = ranks.largest(mine.h), largest_reach = cutoff_margin * h_largest, skin = list_skin(h_largest);
  const neighbors::ParticleRange rows = rows_searched(own);
  const std::vector<BoundingBox> near = near_rows(x_, 2 * largest_reach + skin, grid);

  // This rank's particles within each other rank's reach, to it.
  std::vector<Index> binned;
  const std::vector<NearParticle> receive = neighbors::near_particles(
      own, x_, near, [&](Index a) { return NearParticle{a, x_[a], v_[a], smoothing_length(a)}; }, binned);
  neighbors::ParticleRange held{smoothing_length_.held_begin(), smoothing_length_.held_end()};
  for (const NearParticle& p : receive) {
    const auto a = static_cast<Index>(p.particle);
    held = parallel::hull(held, {a, a + 1});
  }
  hold_read_state(held);  // the stretch grown to the particles that came in, whose h is written below
  if (nodes.window_by_reads) {  // and the window of the nodes to their nodes
    auto [first, end] = nodes.window();
    for (const NearParticle& p : receive) {
      first = std::min(first, node_[p.particle]);
      end = std::max(end, node_[p.particle] + 1);
    }
    nodes.hold_window(first, end);  // x_ and v_ gathered again below
  }
  if (!binned.empty()) list_reach_.hold(binned.front(), binned.back() + 1);
  for (const NearParticle& p : receive) {
    const auto a = static_cast<Index>(p.particle);
    nodes.x[row(nodes, a)] = p.x;
    nodes.v[row(nodes, a)] = p.v;
    smoothing_length(a) = p.h;
    list_reach_[a] = cutoff_margin * p.h;
  }
  gather_kinematics(nodes);  // x_ and v_ may be copies
  const neighbors::BinnedSubset subset{.particles = binned, .grid = grid, .largest_reach = largest_reach};
  verlet_.build(x_, list_reach(), skin, neighbors::RowOrder::search, rows, &subset);
  return grid;
}

// Each rank's rows' box, from every rank's box of its own particles among them at `x`, grown by the
// list radius and the rounding of distances in `grid`: where the particles its rows may list lie.
std::vector<BoundingBox> SolidFormulation::near_rows(StretchView<Vec3> x, Real radius, const BoundingBox& grid) const {
  const parallel::Communicator& ranks = parallel::world();
  const int size = ranks.size();
  const neighbors::ParticleRange own = own_particles();
  std::vector<Index> one_each(size + 1);
  std::iota(one_each.begin(), one_each.end(), 0);
  std::vector<BoxBounds> part_of_rows(size), rows_parts(size);
  for (int r = 0; r < size; ++r) {
    const neighbors::ParticleRange theirs = rows_searched(particles_of(r));
    const Index first = std::max(own.begin, theirs.begin), last = std::min(own.end, theirs.end);
    part_of_rows[r] = bounds_of(bounding_box(std::max<Index>(last - first, 0), [&](Index k) { return x[first + k]; }));
  }
  ranks.exchange(std::span<const BoxBounds>(part_of_rows), one_each, std::span(rows_parts), one_each);
  BoundingBox rows_box;
  for (const BoxBounds& b : rows_parts) rows_box.include(box_of(b));
  const Real rounding = 1e-12 * std::max(grid.lower.cwiseAbs().maxCoeff(), grid.upper.cwiseAbs().maxCoeff());
  std::vector<BoundingBox> near;
  for (const BoxBounds& b : ranks.each(bounds_of(rows_box.grown(1.001 * radius + rounding)))) near.push_back(box_of(b));
  return near;
}

namespace {
// A particle's position at the last list build and its reach, as they travel between the ranks.
struct AtBuild {
  std::int64_t particle;  // 64 bits: no padding travels
  Vec3 x;
  Real reach;
};
}  // namespace

// After a new deal, the rows this rank now computes, searched as one process would have at the
// last build: from the positions at that build and the reaches of its new own particles, which
// come in from their old ranks, and of the others' near its rows, from their new ranks, in that
// build's grid (as search_near_rows), in place of every particle's completed on every rank.
void SolidFormulation::search_dealt_rows(const discretization::ParticleShare& dealt_before) {
  const parallel::Communicator& ranks = parallel::world();
  const int size = ranks.size(), self = ranks.rank();
  const neighbors::ParticleRange was = particles_of(self, dealt_before), own = own_particles();
  StretchView<Vec3> at_build = verlet_.positions_at_build();
  std::vector<std::vector<AtBuild>> to(size);
  for (int r = 0; r < size; ++r) {
    const neighbors::ParticleRange theirs = particles_of(r);
    for (Index a = std::max(was.begin, theirs.begin); r != self && a < std::min(was.end, theirs.end); ++a)
      to[r].push_back({a, at_build[a], list_reach_[a]});
  }
  const std::vector<AtBuild> arrived = ranks.deliver(to);
  keep_own_list_state();
  for (const AtBuild& p : arrived) {
    verlet_.set_position_at_build(p.particle, p.x);
    list_reach_[p.particle] = p.reach;
  }

  // This rank's particles within each other rank's reach, to it.
  at_build = verlet_.positions_at_build();
  const std::vector<BoundingBox> near = near_rows(at_build, verlet_.cutoff() + verlet_.skin(), verlet_.grid());
  std::vector<Index> binned;
  const std::vector<AtBuild> came = neighbors::near_particles(
      own, at_build, near, [&](Index a) { return AtBuild{a, at_build[a], list_reach_[a]}; }, binned);
  if (!binned.empty()) {
    verlet_.hold_positions({binned.front(), binned.back() + 1});
    list_reach_.hold(binned.front(), binned.back() + 1);
  }
  for (const AtBuild& p : came) {
    verlet_.set_position_at_build(p.particle, p.x);
    list_reach_[p.particle] = p.reach;
  }
  verlet_.search_binned_rows(list_reach(), rows_searched(own), binned);
}

void SolidFormulation::complete_list() {
  verlet_.complete_positions([&](RangeArray<Vec3>& x) {
    list_reach_.hold(0, particle_count());
    share_(node_, x, list_reach_);
  });
}

void SolidFormulation::keep_own_list_state() {
  if (!list_built_) return;  // a deal before the first build: nothing held yet
  const neighbors::ParticleRange own = own_particles();
  verlet_.hold_positions(own);
  list_reach_.hold(own.begin, own.end);
}

// From this rank's first particle to its last (the particles are in node order, so its own are
// these): every particle until the nodes are dealt.
neighbors::ParticleRange SolidFormulation::own_particles() const {
  return share_.dealt() ? particles_of(share_.rank()) : neighbors::ParticleRange{0, particle_count()};
}

// The rows this rank computes: from the first of its own particles' rows and its force blocks' to
// the last (choose_force_blocks).
neighbors::ParticleRange SolidFormulation::computed_rows() const {
  const neighbors::ParticleRange own = own_particles();
  if (blocks_.last_row() == 0) return own;
  if (own.begin == own.end) return {blocks_.first_row(), blocks_.last_row()};
  return {std::min(own.begin, blocks_.first_row()), std::max(own.end, blocks_.last_row())};
}

// Continuity and velocity gradient, gathered per particle over its full neighbour row, a pack of
// pairs at a time; each particle's lanes are summed in one fixed order, whatever the thread count.
template <typename Kernel, bool corrected>
Index SolidFormulation::compute_rates(Real dt) {
  constexpr int W = pair_lanes;
  const auto& list = verlet_.list();
  const Index n = particle_count();
  const bool plane = Kernel::dimension == 2;
  const bool colour_on = categorizing();
  // LS-DYNA's step (RULE 1) needs no row sums: the per-pair outer product is skipped.
  const bool row_sums = options_.time_step_rule != TimeStepRule::plain;
  // The colour-field normal serves the categorization and the row sums only.
  const bool normal_on = colour_on || row_sums;
  // The records from the first particle they hold on; the rows' neighbours less `origin` (keep_row).
  const Index origin = record_.held_begin();
  // None on a rank without particles (a member of a null record would be undefined, even unread).
  const float* records = record_.data() ? &record_.data()->x : nullptr;
  const float* masses = record_mass_.empty() ? nullptr : record_mass_.data() + (origin - record_mass_.held_begin());
  const float alpha = static_cast<float>(options_.viscosity.alpha), beta = static_cast<float>(options_.viscosity.beta);
  const float eta2 = static_cast<float>(options_.viscosity.eta * options_.viscosity.eta);
  support_mask_.resize(mask_bytes(list));
  std::uint8_t* mask = support_mask_.data();
  const neighbors::ParticleRange rows = computed_rows();  // under MPI the rest are no row of this rank's
  parallel::LowestIndex unsound;
  parallel::region([&](const parallel::Team& team) {
    RowTerms terms;  // this thread's pair terms, reused row after row
    // Inlined into the seam's loop, as the loop body it was: called as a function, it reloaded
    // what it captures after every pack store (they may alias), 7 % of this pass (measured).
    team.for_each(rows, [&](Index a) __attribute__((always_inline)) {
      if (!owns(a)) {  // another rank's, whose pick the force pass may still need
        if (blocks_.runs_row(a)) pick_support(list, a, record_.data(), origin, mask, terms);
        return;
      }
      const Index padded = pick_support(list, a, record_.data(), origin, mask, terms);
      const Index* neighbour = terms.neighbour.data();
      float *dx_k = terms.dx.data(), *dy_k = terms.dy.data(), *dz_k = terms.dz.data(), *factor_k = terms.factor.data(),
            *r_k = terms.r.data(), *support_k = terms.support.data(),
            *weight_k = terms.weight.data(), *dvx_k = terms.dvx.data(), *dvy_k = terms.dvy.data(),
            *dvz_k = terms.dvz.data(), *viscous_k = terms.viscous.data(), *heating_k = terms.heating.data();
      const PairRecord& own = record_[a];
      const PackCentre centre(own);
      const Float8 vax(own.vx), vay(own.vy), vaz(own.vz);
      // With g = V_b grad_a W_ab = V_b F x_ab:
      //   normal n = sum g (seed 000 eq. 9: n = grad c_s)
      //   moment   = -sum g (x) x_ab, = I for a full support (symmetric: 6 sums)
      //   spread   = sum_b V_b grad (x) grad / |grad| = sum V_b |F| / r x_ab (x) x_ab, for the stable step
      //   L        = sum (v_b - v_a) (x) g,  drho = -sum m_b F (v_b - v_a) . x_ab
      // Three loops over the pairs, each with no more sums than registers: the geometry, the moment
      // and the spread; then L and the viscosity's pair terms; then the normal and the viscosity's
      // sums, in double.
      Float8 m_xx, m_yy, m_zz, m_xy, m_yz, m_zx, s_xx, s_yy, s_zz, s_xy, s_yz, s_zx;
      for (Index k = 0; k < padded; k += W) {
        Float8 c[8];  // x, y, z, h, vx, vy, vz, V of the neighbours
        simd::load_rows<record_stride>(records, neighbour + k, 0, c);
        const PairGeometry g = pair_geometry<Kernel>(centre, c);
        const Float8 volume = c[7], w = volume * g.factor;
        g.dx.store(dx_k + k), g.dy.store(dy_k + k), g.dz.store(dz_k + k);
        g.r.store(r_k + k), g.support.store(support_k + k), g.factor.store(factor_k + k);
        w.store(weight_k + k);
        (c[4] - vax).store(dvx_k + k), (c[5] - vay).store(dvy_k + k), (c[6] - vaz).store(dvz_k + k);
        if constexpr (corrected) {  // plain SPH needs no moment (its lanes stay zero)
          const Float8 gx = w * g.dx, gy = w * g.dy, gz = w * g.dz;
          m_xx = fma(gx, g.dx, m_xx), m_yy = fma(gy, g.dy, m_yy), m_zz = fma(gz, g.dz, m_zz);
          m_xy = fma(gx, g.dy, m_xy), m_yz = fma(gy, g.dz, m_yz), m_zx = fma(gz, g.dx, m_zx);
        }
        if (row_sums) {
          const Float8 spread = volume * abs(g.factor) * g.inverse_r;
          const Float8 sx = spread * g.dx, sy = spread * g.dy, sz = spread * g.dz;
          s_xx = fma(sx, g.dx, s_xx), s_yy = fma(sy, g.dy, s_yy), s_zz = fma(sz, g.dz, s_zz);
          s_xy = fma(sx, g.dy, s_xy), s_yz = fma(sy, g.dz, s_yz), s_zx = fma(sz, g.dx, s_zx);
        }
      }
      // v_b - v_a and x_a - x_b of the pack of pairs at k.
      const auto pair_kinematics = [&](Index k, Float8& vx, Float8& vy, Float8& vz, Float8& dx, Float8& dy, Float8& dz) {
        vx = Float8::load(dvx_k + k), vy = Float8::load(dvy_k + k), vz = Float8::load(dvz_k + k);
        dx = Float8::load(dx_k + k), dy = Float8::load(dy_k + k), dz = Float8::load(dz_k + k);
      };
      // Monaghan's viscosity, -m_a m_b Pi_ab grad_a W_ab on the pairs approaching each other, here
      // where v_ab and the pair geometry are at hand, with rho and c of the step start (the records).
      Float8 L_lanes[9];
      const Float8 m_a(static_cast<float>(mass_[a])), rho_a(viscosity_record_[a].density),
          c_a(viscosity_record_[a].sound_speed);
      for (Index k = 0; k < padded; k += W) {
        Float8 vx, vy, vz, dx, dy, dz;
        pair_kinematics(k, vx, vy, vz, dx, dy, dz);
        const Float8 w = Float8::load(weight_k + k);
        const Float8 gx = w * dx, gy = w * dy, gz = w * dz;
        // Column-major like Mat3: L(i, j) = L_lanes[i + 3 j].
        L_lanes[0] = fma(vx, gx, L_lanes[0]), L_lanes[1] = fma(vy, gx, L_lanes[1]), L_lanes[2] = fma(vz, gx, L_lanes[2]);
        L_lanes[3] = fma(vx, gy, L_lanes[3]), L_lanes[4] = fma(vy, gy, L_lanes[4]), L_lanes[5] = fma(vz, gy, L_lanes[5]);
        L_lanes[6] = fma(vx, gz, L_lanes[6]), L_lanes[7] = fma(vy, gz, L_lanes[7]), L_lanes[8] = fma(vz, gz, L_lanes[8]);
        // v_ab . x_ab, bit for bit that of (b, a): v_b - v_a and x_a - x_b change sign exactly.
        const Float8 vr = Float8(0) - fma(vz, dz, fma(vy, dy, vx * dx));
        const auto approaching = vr < Float8(0);
        if (approaching.lanes() == 0) {
          Float8(0).store(viscous_k + k), Float8(0).store(heating_k + k);
          continue;
        }
        // Pi = (-alpha c mu + beta mu^2) / rho_ab with mu = h v_ab . x_ab / d, d = r^2 + eta^2 h^2, as
        // (-alpha c d + beta h v.x) h v.x / (d^2 rho_ab) with one reciprocal, c and rho the pair's
        // means: every product and sum is commutative, so that (a, b) and (b, a) get the same Pi.
        const Index* b = neighbour + k;
        const Float8 h_ab = Float8(0.5f) * Float8::load(support_k + k);  // mean smoothing length
        const Float8 hv = h_ab * vr;
        const Float8 r = Float8::load(r_k + k);
        const Float8 d = fma(Float8(eta2) * h_ab, h_ab, r * r);
        Float8 c_rho[2];  // c_b, rho_b
        simd::load_rows<viscosity_stride>(&viscosity_record_.data()->sound_speed, b, 0, c_rho);
        const Float8 c = Float8(0.5f) * (c_a + c_rho[0]);
        const Float8 rho = Float8(0.5f) * (rho_a + c_rho[1]);
        const Float8 Pi =
            select(approaching, fma(Float8(-alpha) * c, d, Float8(beta) * hv) * hv * reciprocal(d * d * rho), Float8(0));
        const Float8 m_b = pair_mass(masses, uniform_mass_, b);
        const Float8 mPF = m_b * Pi * Float8::load(factor_k + k);
        (m_a * mPF).store(viscous_k + k);
        (Float8(0.5f) * mPF * vr).store(heating_k + k);
      }
      // The viscosity's sums are widened to double: each side of a pair sums its own terms, and
      // momentum is conserved to the round-off of those sums.
      Float8 n_x, n_y, n_z;
      simd::WideSum8 visc_x, visc_y, visc_z, heating;
      for (Index k = 0; k < padded; k += W) {
        const Float8 dx = Float8::load(dx_k + k), dy = Float8::load(dy_k + k), dz = Float8::load(dz_k + k);
        if (normal_on) {
          const Float8 w = Float8::load(weight_k + k);
          n_x = fma(w, dx, n_x), n_y = fma(w, dy, n_y), n_z = fma(w, dz, n_z);
        }
        const Float8 s = Float8::load(viscous_k + k);
        visc_x.add(s * dx), visc_y.add(s * dy), visc_z.add(s * dz);
        heating.add(Float8::load(heating_k + k));
      }
      // The continuity sum, for a particle whose velocity gradient is not corrected (with the
      // correction its density follows from tr(L) instead).
      const auto continuity = [&] {
        Float8 drho_lanes;
        for (Index k = 0; k < padded; k += W) {
          Float8 vx, vy, vz, dx, dy, dz;
          pair_kinematics(k, vx, vy, vz, dx, dy, dz);
          const Float8 mass = pair_mass(masses, uniform_mass_, neighbour + k);
          drho_lanes -= mass * Float8::load(factor_k + k) * fma(vz, dz, fma(vy, dy, vx * dx));
        }
        return drho_lanes.sum();
      };
      // The 24 sums eight at a time: L's nine, then the normal, the moment and the spread.
      const Float8 lanes[3][8] = {{L_lanes[0], L_lanes[1], L_lanes[2], L_lanes[3], L_lanes[4], L_lanes[5], L_lanes[6],
                                   L_lanes[7]},
                                  {L_lanes[8], n_x, n_y, n_z, m_xx, m_yy, m_zz, m_xy},
                                  {m_yz, m_zx, s_xx, s_yy, s_zz, s_xy, s_yz, s_zx}};
      Real sums[24];
      for (int i = 0; i < 3; ++i) simd::sum_lanes(lanes[i], sums + 8 * i);
      viscous_force_[a] = Vec3(-visc_x.sum(), -visc_y.sum(), -visc_z.sum());
      viscous_heating_[a] = heating.sum();
      Real drho;
      Mat3 L;
      for (int i = 0; i < 9; ++i) L.data()[i] = sums[i];
      const Vec3 normal(sums[9], sums[10], sums[11]);
      Mat3 moment = symmetric(sums + 12, Real(-1));
      if (colour_on) {
        // seed 000 eq. 10, self included
        Real colour = volume_[a] * Kernel::value(0, 2 * smoothing_length(a));
        std::int32_t count = 0;
        for (Index k = 0; k < padded; ++k) {
          if (terms.neighbour[k] == a - origin) continue;  // the padding
          colour += volume_[origin + terms.neighbour[k]] * Kernel::value(terms.r[k], terms.support[k]);
          ++count;
        }
        colour_[a] = colour;
        colour_normal_[a] = normal;
        support_count_[a] = count;
      }
      // In plane strain nothing varies along z: the moment is the identity there.
      if (plane) moment(2, 2) = 1;
      Mat3 correction = Mat3::Identity();
      // Randles & Libersky 1996: L B with B = moment^{-1} is exact for linear velocity fields,
      // also where the support is cut by a free surface; the density follows from tr(L).
      if (corrected && invert_symmetric(moment, min_moment_determinant, correction)) {
        L = product(L, correction);
        drho = -density_[a] * L.trace();
      } else {
        drho = continuity();
      }
      // Row sum of the gradient operator v -> L_a, sum_b V_b |B^T grad_a W_ab| + |B^T n_a| (the
      // second term: the weight of v_a itself), relative to a full support's; the first term by
      // Cauchy-Schwarz, sqrt(tr T tr(B^T T B)) with T = spread (exact when B = I).
      if (row_sums) {
        const Mat3 spread = symmetric(sums + 18, Real(1));
        // tr(B^T T B) = sum_ij (T B)_ij B_ij: one product, not two and a diagonal. Written out in
        // scalars: Eigen's two-lane forms of these 3x3 products store single lanes to the stack and
        // reload them as pairs, which stalls store forwarding (a tenth of this pass, measured).
        Real quadratic = 0, transposed_normal = 0;
        for (int j = 0; j < 3; ++j) {
          Real normal_j = 0;
          for (int i = 0; i < 3; ++i) {
            const Real TB_ij = spread(i, 0) * correction(0, j) + spread(i, 1) * correction(1, j) + spread(i, 2) * correction(2, j);
            quadratic += TB_ij * correction(i, j);
            normal_j += correction(i, j) * normal[i];
          }
          transposed_normal += normal_j * normal_j;
        }
        const Real row_sum = std::sqrt(spread.trace() * quadratic) + std::sqrt(transposed_normal);
        gradient_amplification_[a] = row_sum * 2 * smoothing_length(a) / full_support_gradient_;
      }
      if (colour_on) {
        density_rate_[a] = drho;
        velocity_gradient_[a] = L;
        correction_[a] = correction;
      } else {
        update_particle(a, L, correction, drho, dt);  // its own data only: the neighbours' rates
                                                       // read the step start's volume_
        if (!sound(a)) unsound.report(a);
      }
    }, {.chunk = 512});
  });
  return unsound.value() < 0 ? n : unsound.value();
}

// Seed 000 §4: a particle is on the surface when it has fewer neighbours than a fraction of a full
// support AND its colour-field normal is large (|n| h above a threshold); the inner layers are the
// particles within 1.5 spacings of the previous layer. Each layer is found from the previous
// layer's flags only, so the result does not depend on the thread count.
void SolidFormulation::categorize() {
  const auto& list = verlet_.list();
  const Index n = particle_count();
  int layers = 0;
  // Under MPI each rank its own particles, with the flags of the others' that its rows read
  // brought in before each layer (reach_).
  const neighbors::ParticleRange own = own_particles();
  parallel::for_each(own, [&](Index a) {
    const ColourField& c = options_.colour_field[material_[a]];
    const bool surface = c.enabled &&
                         support_count_[a] < c.neighbour_fraction * full_support_count_[a] &&
                         colour_normal_[a].norm() * smoothing_length(a) > c.normal_threshold;
    category_[a] = surface ? Category::surface : Category::interior;
  });
  for (const ColourField& c : options_.colour_field)
    if (c.enabled) layers = std::max(layers, c.layers);
  std::vector<std::uint8_t> previous(n), next(n);
  for (Index a = own.begin; a < own.end; ++a) previous[a] = category_[a] == Category::surface;
  for (int layer = 1; layer <= layers; ++layer) {
    reach_(previous);
    parallel::for_each(own, [&](Index a) {
      next[a] = 0;
      const ColourField& c = options_.colour_field[material_[a]];
      if (!c.enabled || layer > c.layers || category_[a] != Category::interior) return;
      // The current spacing: the initial one scaled as h has been.
      const Real scale = smoothing_length(a) / initial_smoothing_length_[a];
      const Real reach = Real(1.5) * spacing_[a] * scale;
      for (Index k = list.offsets[a]; k < list.offsets[a + 1]; ++k) {
        const Index b = list.neighbors[k];
        if (previous[b] && (x_[a] - x_[b]).squaredNorm() < reach * reach) {
          next[a] = 1;
          break;
        }
      }
    });
    for (Index a = own.begin; a < own.end; ++a)
      if (next[a]) category_[a] = Category::inner_layer;
    previous.swap(next);
  }
}

Index SolidFormulation::update_state(Real dt) {
  const neighbors::ParticleRange own = own_particles();
  const Index first_unsound = parallel::first_failure(
      own,
      [&](Index a) {
        update_particle(a, velocity_gradient_[a], correction_[a], density_rate_[a], dt);
        return !sound(a);
      },
      {.chunk = 512});
  return first_unsound < 0 ? particle_count() : first_unsound;
}

void SolidFormulation::update_particle(Index a, const Mat3& L, const Mat3& correction, Real density_rate, Real dt) {
  const auto& stress_options = options_.artificial_stress;
  const bool relaxed = !exported_deviator_.empty();
  const auto& m = materials_[material_[a]];
  const ColourField& colour = options_.colour_field.empty() ? ColourField{} : options_.colour_field[material_[a]];
  const bool treated = categorizing() && category_[a] != Category::interior && colour.treat;
  materials::PointState& state = state_[a];
  if (dt > 0) {
    // The stress whose power the pair forces delivered: energy-consistent (docs/THEORY.md §3).
    const Mat3& S_power = relaxed ? exported_deviator_[a] : state.deviatoric_stress;
    const Mat3 sigma_old = S_power - pressure_[a] * Mat3::Identity();
    internal_energy_[a] += dt * (sigma_old.cwiseProduct(L).sum() / density_[a] + viscous_heating_[a]);
    density_[a] += dt * density_rate;
    updated_volume_[a] = mass_[a] / density_[a];
    // Objective (Jaumann) rotation of the stress deviator and back stress, then the material.
    state.deviatoric_stress += dt * materials::jaumann_rotation(L, state.deviatoric_stress);
    Mat3* back_stress = materials::kept_back_stress(back_stress_, a);
    if (back_stress) *back_stress += dt * materials::jaumann_rotation(L, *back_stress);
    const Mat3 D = Real(0.5) * (L + L.transpose());
    const Mat3 D_dev = materials::deviator(D);
    // For residual_stress, squared: its square root is taken there, not at every step.
    strain_rate_squared_[a] = materials::effective_strain_rate_squared(D_dev);
    const materials::StressUpdate update =
        materials::update_stress(m, state, D, dt, density_[a], internal_energy_[a], back_stress);
    pressure_[a] = update.pressure;
    if (relaxed) relax_exported_deviator(a, L, D_dev, treated, colour.relaxation, dt);  // with the c of the step start
    updated_sound_speed_[a] = update.sound_speed;
  } else {
    updated_volume_[a] = volume_[a];
    updated_sound_speed_[a] = materials::sound_speed(m, density_[a], internal_energy_[a]);
  }
  // The stress as the pair force uses it: sigma B^T (seed 000 eq. 8 for sigma).
  const Mat3 sigma = state.deviatoric_stress - pressure_[a] * Mat3::Identity();
  // Seed 000 §4: treated surface and inner-layer particles pass only their pressure on
  // (TFORM 2), or their relaxed deviator (TFORM 1).
  const Mat3 exported = relaxed ? Mat3(exported_deviator_[a] - pressure_[a] * Mat3::Identity())
                        : treated ? Mat3(-pressure_[a] * Mat3::Identity())
                                  : sigma;
  record_stress(a, exported, correction);
  if (stress_options.enabled) {
    // Monaghan 2000: a repulsive stress -eps sigma_i / rho^2 along each tensile principal axis.
    // From the stress the particle passes on, so that a treated particle's deviator stays out.
    const Eigen::SelfAdjointEigenSolver<Mat3> principal(exported);
    Vec3 r = Vec3::Zero();
    for (int i = 0; i < 3; ++i)
      if (principal.eigenvalues()[i] > 0)
        r[i] = -stress_options.epsilon * principal.eigenvalues()[i] / (density_[a] * density_[a]);
    artificial_stress_[a] = principal.eigenvectors() * r.asDiagonal() * principal.eigenvectors().transpose();
  }
}

void SolidFormulation::record_stress(Index a, const Mat3& exported, const Mat3& correction) {
  const auto volume = static_cast<float>(updated_volume_[a]);
  if (!options_.gradient_correction) {  // plain SPH: B = I, P = sigma
    PlainStressRecord& record = plain_stress_[a];
    const Real components[6] = {exported(0, 0), exported(1, 1), exported(2, 2),
                                exported(0, 1), exported(1, 2), exported(2, 0)};
    for (int k = 0; k < 6; ++k) record.sigma[k] = static_cast<float>(components[k]);
    record.volume = volume;
    return;
  }
  const Mat3 P = product_transposed(exported, correction);
  StressRecord& record = stress_[a];
  for (int k = 0; k < 9; ++k) record.P[k] = static_cast<float>(P.data()[k]);
  record.volume = volume;
}

// Relaxed treatment (TFORM 1): the exported deviator S* is a Maxwell element with the material's
// shear modulus, dS*/dt = 2G dev D - (S* - target) / tau, tau = TAU h / c, that relaxes toward 0
// on a treated particle and toward the material's S on the others, and is kept within the
// yield surface (the larger of the static yield stress and |S|). A treated particle is thus as
// stiff and as strong as the material against motion faster than tau and under plastic flow at a
// strain rate above sigma_y / (2 G tau); a stress that persists at a lower rate (residual stress)
// is not passed on after a few tau, while the material's own S stays in the output. A failed
// particle exports no deviator.
void SolidFormulation::relax_exported_deviator(Index a, const Mat3& L, const Mat3& D_dev, bool treated,
                                               Real relaxation, Real dt) {
  const auto& m = materials_[material_[a]];
  const materials::PointState& state = state_[a];
  Mat3& exported = exported_deviator_[a];
  if (state.failed) {
    exported = state.deviatoric_stress;
    return;
  }
  exported += dt * (materials::jaumann_rotation(L, exported) + 2 * m.shear_modulus * D_dev);
  const Mat3 target = treated ? Mat3::Zero() : state.deviatoric_stress;
  const Real tau = relaxation * smoothing_length(a) / sound_speed_[a];
  exported = target + std::exp(-dt / tau) * (exported - target);  // exact decay over the step
  const Real bound = std::max(materials::static_yield_stress(m, state), materials::von_mises(state.deviatoric_stress));
  const Real size = materials::von_mises(exported);
  if (size > bound) exported *= bound / size;
}

bool SolidFormulation::sound(Index a) const {
  return density_[a] > 0 && std::isfinite(density_[a]) && std::isfinite(smoothing_length(a));
}

void SolidFormulation::check_state(const discretization::NodeStore& nodes, Index first_unsound) const {
  if (first_unsound >= particle_count()) return;
  // Under MPI the particle's state is current on its own rank alone, which tells every rank.
  struct Unsound {
    double density, h;
    std::int64_t id;  // its node's
  };
  const Index a = first_unsound;
  const Unsound mine = owns(a) ? Unsound{density_[a], smoothing_length(a), nodes.id[row(nodes, a)]} : Unsound{};
  const Unsound found = parallel::world().all(std::span<const Unsound>(&mine, owns(a) ? 1 : 0)).at(0);
  throw InstabilityError(fmt::format(
      "SPH solid: node {} has density {:.6g} and smoothing length {:.6g}: its particle's "
      "neighbourhood has collapsed or torn apart (a smaller TSSFAC, or the artificial stress "
      "against the tensile instability, may help)",
      found.id, found.density, found.h));
}

void SolidFormulation::share_updated_state() {
  if (parallel::world().size() == 1) return;
  reach_(updated_volume_, updated_sound_speed_, density_, stress_, plain_stress_, artificial_stress_);
}

void SolidFormulation::plan_reach(const discretization::NodeStore& nodes) {
  const auto& list = verlet_.list();
  const neighbors::ParticleRange rows = computed_rows();
  current_ = reach_.plan_rows(list.offsets, list.neighbors, [&](Index a) {
    return owns(a) || blocks_.runs_row(a);
  }, node_, share_, nodes, {rows.begin, rows.end});
  reach_partition_ = nodes.partition;
}

namespace {
// A particle's node's position and velocity as they travel between the ranks.
struct Kinematics {
  Vec3 x, v;
};
}  // namespace

// The rows this rank computes now are searched from the particles' positions and reaches at the last
// build (as one process would have searched them: search_dealt_rows), and the particles they read
// come in from the ranks that computed them in the old deal, with their whole state and their
// nodes' positions and velocities: a particle's state travels to the ranks that need it, no further.
void SolidFormulation::deal_anew(discretization::NodeStore& nodes) {
  const discretization::ParticleShare dealt_before = share_;
  share_.bind(nodes);
  search_computed_rows(nodes, dealt_before);
  plan_reach(nodes);
  hold_nodes(nodes, true);  // the old own rows, which the arrivals below send from, and the new reads
  discretization::ReachShare arrivals;
  arrivals.plan(current_, node_, dealt_before, nodes);
  // The Own arrays hold the old own particles (what this rank sends) and those it now reads (what
  // it receives) while the state travels, then its new own particles alone.
  // The Read arrays likewise: the old stretch and the new.
  const neighbors::ParticleRange reads = read_stretch();
  hold_own_state(parallel::hull({state_.held_begin(), state_.held_end()}, reads));  // state_ is always on
  hold_read_state(parallel::hull({smoothing_length_.held_begin(), smoothing_length_.held_end()}, reads));
  arrivals(volume_, sound_speed_, density_, smoothing_length_, pressure_, internal_energy_, state_, back_stress_,
           stress_, plain_stress_, artificial_stress_, exported_deviator_, strain_rate_squared_,
           gradient_amplification_, colour_, colour_normal_, support_count_, category_, material_, mass_, spacing_,
           record_mass_, initial_smoothing_length_, full_support_count_);
  hold_own_state(own_particles());
  hold_read_state(reads);
  held_partition_ = nodes.partition;
  arrivals.records<Kinematics>([&](Index a) { return Kinematics{nodes.x[row(nodes, a)], nodes.v[row(nodes, a)]}; },
                               [&](Index a, const Kinematics& k) {
                                 nodes.x[row(nodes, a)] = k.x;
                                 nodes.v[row(nodes, a)] = k.v;
                               });
  hold_nodes(nodes, false);
}

void SolidFormulation::hold_nodes(discretization::NodeStore& nodes, bool keep) {
  if (!nodes.window_by_reads) return;
  parallel::Range held{nodes.rank_begin[nodes.rank], nodes.rank_begin[nodes.rank + 1]};
  const neighbors::ParticleRange reads = parallel::hull(read_stretch(), own_particles());
  if (reads.begin < reads.end) held = parallel::hull(held, {node_[reads.begin], node_[reads.end - 1] + 1});
  if (keep) held = parallel::hull(held, nodes.window());
  nodes.hold_window(held.begin, held.end);
  gather_kinematics(nodes);  // the rows moved: x_ and v_ from them
}

void SolidFormulation::hold_own_state(neighbors::ParticleRange range) {
  const auto hold = [&](auto&... arrays) { (arrays.hold(range.begin, range.end), ...); };
  hold(pressure_, internal_energy_, state_, back_stress_, gradient_amplification_, correction_, exported_deviator_,
       colour_, colour_normal_, support_count_, category_, density_rate_, velocity_gradient_, strain_rate_squared_,
       viscous_heating_, viscous_force_);
  if (constants_held_) hold(full_support_count_);
}

void SolidFormulation::hold_read_state(neighbors::ParticleRange range) {
  const auto hold = [&](auto&... arrays) { (arrays.hold(range.begin, range.end), ...); };
  hold(smoothing_length_, density_, volume_, updated_volume_, sound_speed_, updated_sound_speed_, artificial_stress_,
       record_, viscosity_record_, stress_, plain_stress_, force_);
  if (constants_held_) hold(material_, initial_smoothing_length_, mass_, spacing_, record_mass_);
}

neighbors::ParticleRange SolidFormulation::read_stretch() const {
  if (current_.empty()) return {0, particle_count()};  // one process: every particle
  // The force blocks it runs add to every particle of the next block (ForceBlocks::last_touched).
  const neighbors::ParticleRange blocks =
      blocks_.last_row() > 0 ? neighbors::ParticleRange{blocks_.first_row(), blocks_.last_touched()}
                             : neighbors::ParticleRange{0, 0};
  const auto first = std::find(current_.begin(), current_.end(), 1);
  if (first == current_.end()) return blocks;
  const auto last = std::find(current_.rbegin(), current_.rend(), 1);
  return parallel::hull({static_cast<Index>(first - current_.begin()), static_cast<Index>(current_.rend() - last)},
                        blocks);
}

// The rows this rank computes in the present deal, as the last build would have searched them, and
// the force blocks for the deal: after a new deal from the positions at the build near its rows
// (search_dealt_rows), after a restart likewise (the deal share_ was bound to: a rank's own read back,
// or every particle's).
void SolidFormulation::search_computed_rows(const discretization::NodeStore& nodes,
                                            const discretization::ParticleShare& dealt_before) {
  if (list_built_) search_dealt_rows(dealt_before);
  choose_force_blocks(nodes);
  // Blocks longer than the margin: every row then, from every particle's position at the build,
  // which the ranks complete together when one needs them.
  const bool unsearched = list_built_ && !verlet_.searched(computed_rows());
  if (parallel::world().any(unsearched)) complete_list();
  if (unsearched) verlet_.search_every_row(list_reach().every());
  keep_own_list_state();
}

// Rank 0 writes the nodes whole unless the store is a window (each rank writes its own rows then):
// every particle's position and velocity.
void SolidFormulation::complete_state(discretization::NodeStore& nodes) {
  if (!nodes.windowed()) complete_kinematics(nodes);  // a window's store writes each rank's own rows
}

parallel::Range SolidFormulation::rows_read(const discretization::NodeStore& nodes) const {
  if (!list_built_) return {0, nodes.size()};
  const neighbors::ParticleRange reads = read_state_held();
  if (reads.begin >= reads.end) return {0, 0};
  // Those the store holds: with a window of the nodes, the particles it does not are not read.
  return {std::max<Index>(row(nodes, reads.begin), 0), std::min(row(nodes, reads.end - 1) + 1, nodes.size())};
}

void SolidFormulation::share_state(discretization::NodeStore& nodes) {
  if (!nodes.velocities_by_reach || !reach_.planned()) return;
  reach_.records<Vec3>([&](Index a) { return nodes.v[row(nodes, a)]; },
                       [&](Index a, const Vec3& v) { nodes.v[row(nodes, a)] = v; });
  kinematics_complete_ = false;
}

void SolidFormulation::complete_kinematics(discretization::NodeStore& nodes) {
  if (kinematics_complete_) return;
  share_.complete_nodes(node_, nodes);
  gather_kinematics(nodes);  // x_ and v_ may be copies
  kinematics_complete_ = true;
}

void SolidFormulation::choose_force_blocks(const discretization::NodeStore& nodes) {
  // Every rank's first particle (the particles are in node order): their nodes' ranks.
  std::vector<Index> particle_begin;
  if (parallel::world().size() > 1)
    for (const Index node : nodes.rank_begin)
      particle_begin.push_back(std::lower_bound(node_.begin(), node_.end(), node) - node_.begin());
  blocks_.assign(particle_count(), force_blocks_, force_block_length_, particle_begin, parallel::world().rank());
  blocks_partition_ = nodes.partition;
}

// Momentum, dual to the (corrected) velocity gradient: with P = sigma B^T,
//   f_a = sum_b V_a V_b (P_a + P_b) grad_a W_ab  -  sum_b m_a m_b Pi_ab grad_a W_ab
//         + sum_b m_a m_b f_ab^n (R_a + R_b) grad_a W_ab,
// the viscous term from the rates pass (compute_rates).
// Stress power sum_a V_a sigma_a : L_a equals -sum_a f_a . v_a exactly, and the pair term is
// antisymmetric, so linear momentum is conserved to round-off. Without correction (B = I) this is
// the symmetric SPH form of seed 000 eq. 7 with V_a V_b in place of m_a m_b / (rho_a rho_b).
template <typename Kernel, bool corrected>
void SolidFormulation::compute_pair_forces() {
  constexpr int W = pair_lanes;
  const auto& list = verlet_.list();
  const bool stress_on = options_.artificial_stress.enabled;
  const Real exponent = options_.artificial_stress.exponent;
  // The records and the sums from the first particle they hold on (keep_row).
  const Index origin = record_.held_begin();
  // None on a rank without particles (as in compute_rates).
  const float* records = record_.data() ? &record_.data()->x : nullptr;
  // P_b(i, j) = P[stress_stride b + i + 3 j]; plain SPH: sigma_b's components at
  // plain_stress_stride b.
  const float* P = corrected ? (stress_.data() ? stress_.data()->P : nullptr)
                             : (plain_stress_.data() ? plain_stress_.data()->sigma : nullptr);
  // The pair terms of particle a's row (half: the pairs with b > a, each added to a and taken
  // from b), returned as a's sum; `terms` is the caller's scratch.
  const auto row_force = [&]<bool half>(Index a, RowTerms& terms) {
    const Index padded = picked_support<half>(list, a, origin, support_mask_.data(), terms);
    const Index* neighbour = terms.neighbour.data();
    const PackCentre centre(record_[a]);
    // P_a column-major (plain: sigma_a's six components), and V_a.
    Float8 P_a[9];
    float own_volume;
    if constexpr (corrected) {
      for (int i = 0; i < 9; ++i) P_a[i] = Float8(stress_[a].P[i]);
      own_volume = stress_[a].volume;
    } else {
      for (int i = 0; i < 6; ++i) P_a[i] = Float8(plain_stress_[a].sigma[i]);
      own_volume = plain_stress_[a].volume;
    }
    const Float8 volume_a(own_volume);
    simd::WideSum8 f_x, f_y, f_z;
    for (Index k = 0; k < padded; k += W) {
      const Index* b = neighbour + k;
      Float8 c[4];
      simd::load_rows<record_stride>(records, b, 0, c);
      const PairGeometry g = pair_geometry<Kernel>(centre, c);
      // (P_a + P_b) grad_a W_ab with grad = F x_ab: exactly opposite for the pair (b, a), so
      // momentum is conserved to round-off also where each particle gathers its own sum.
      Float8 Pd[3];
      if constexpr (!corrected) {
        Float8 S[8];  // sigma_b's xx, yy, zz, xy, yz, zx, V_b and an unused lane
        simd::load_rows<plain_stress_stride>(P, b, 0, S);
        const Float8 t = volume_a * S[6] * g.factor;
        const Float8 xx = P_a[0] + S[0], yy = P_a[1] + S[1], zz = P_a[2] + S[2];
        const Float8 xy = P_a[3] + S[3], yz = P_a[4] + S[4], zx = P_a[5] + S[5];
        Pd[0] = t * fma(zx, g.dz, fma(xy, g.dy, xx * g.dx));
        Pd[1] = t * fma(yz, g.dz, fma(yy, g.dy, xy * g.dx));
        Pd[2] = t * fma(zz, g.dz, fma(yz, g.dy, zx * g.dx));
      } else {
        Float8 P_b[8], tail[4];  // P_b's elements 0-7; element 8, V_b and two unused
        simd::load_rows<stress_stride>(P, b, 0, P_b);
        simd::load_rows<stress_stride>(P, b, 8, tail);
        const Float8 t = volume_a * tail[1] * g.factor;
        for (int i = 0; i < 3; ++i) {
          const Float8 p0 = P_a[i] + P_b[i], p1 = P_a[i + 3] + P_b[i + 3];
          const Float8 p2 = P_a[i + 6] + (i == 2 ? tail[0] : P_b[i + 6]);
          Pd[i] = t * fma(p2, g.dz, fma(p1, g.dy, p0 * g.dx));
        }
      }
      f_x.add(Pd[0]), f_y.add(Pd[1]), f_z.add(Pd[2]);
      // The padding (b = a) adds exact zeros (F = 0 at r = 0).
      static_assert(sizeof(Eigen::Vector4d) == 4 * sizeof(double), "force_ rows are four contiguous doubles");
      if constexpr (half) simd::subtract_from_rows(Pd, b, force_.data()->data());
    }
    Vec3 f(f_x.sum(), f_y.sum(), f_z.sum());
    if (stress_on) {
      // Monaghan 2000: m_a m_b f_ab^n (R_a + R_b) grad_a W_ab, f_ab = W(r) / W(dp).
      for (Index k = 0; k < padded; ++k) {
        const Index b = origin + terms.neighbour[k];
        if (b == a) continue;  // the padding
        const Vec3 x_ab = x_[a] - x_[b];
        const Real r = x_ab.norm(), H = pair_support(smoothing_length(a), smoothing_length(b));
        const Real dp = Real(0.5) * (spacing_[a] + spacing_[b]);
        const Real ratio = Kernel::value(r, H) / Kernel::value(dp, H);
        const Vec3 grad = Kernel::gradient(x_ab, r, H);
        const Vec3 f_ab = (mass_[a] * mass_[b] * std::pow(ratio, exponent)) *
                          ((artificial_stress_[a] + artificial_stress_[b]) * grad);
        f += f_ab;
        if constexpr (half) force_[b].head<3>() -= f_ab;
      }
    }
    return f;
  };
  const auto run_block = [&](Index block) {
    RowTerms terms;
    for (Index a = blocks_.begin(block); a < blocks_.end(block); ++a)
      force_[a].head<3>() += row_force.template operator()<true>(a, terms);
  };
  if (blocks_.count() == 0) {
    parallel::region([&](const parallel::Team& team) {
      RowTerms terms;
      const neighbors::ParticleRange own = own_particles();
      team.for_each(own, [&](Index a) {
        force_[a] = force_row(row_force.template operator()<false>(a, terms));
      }, {.chunk = 512});
    });
  } else if (parallel::world().size() == 1) {
    // Each pair once: a block of particles adds to its own and the next block's forces only
    // (ForceBlocks), so the even blocks run side by side without two threads touching one
    // particle, and so do the odd ones; an odd block runs once the even blocks on either side of it
    // are done. (Tasks rather than two sweeps: with about ten blocks a sweep, the sweeps' ends left a
    // thread idle for a block, 3 % of the Taylor bar's step.)
    force_.fill(Eigen::Vector4d::Zero());
    parallel::for_each_alternating_block(blocks_.count(), run_block);
  } else {
    // Each block on one rank, the sums handed between the halves (ForceBlocks). Zeroed first: the
    // rows this rank computes and the particles its blocks add to beyond them (the next block's).
    const neighbors::ParticleRange rows = computed_rows();
    for (Index a = rows.begin; a < std::max(rows.end, blocks_.last_touched()); ++a) force_[a] = Eigen::Vector4d::Zero();
    for (int parity = 0; parity < 2; ++parity) {
      const std::span<const Index> blocks = blocks_.run(parity);
      parallel::for_each(static_cast<Index>(blocks.size()), [&](Index k) { run_block(blocks[k]); }, {.chunk = 1});
      if (parity == 0)
        blocks_.after_even(force_);
      else
        blocks_.after_odd(force_);
    }
  }
}

template <typename F>
void SolidFormulation::with_discretization(F&& f) {
  kernels::with_kernel(options_.kernel, options_.dimension, [&](auto kernel) {
    if (options_.gradient_correction)
      f(kernel, std::true_type{});
    else
      f(kernel, std::false_type{});
  });
}

void SolidFormulation::compute_forces(discretization::NodeStore& nodes, Real dt) {
  time_ += dt;
  const Index n = particle_count();
  // Under MPI each rank sets up its own particles' state once the nodes are dealt, and again at a
  // new deal before the first list (inactive until START: the state is still the set-up's).
  if (!set_up_ || (!list_built_ && share_.stale(nodes))) {
    share_.bind(nodes);
    set_up_state(own_particles());
    held_partition_ = nodes.partition;
  }
  if (!active(time_)) {
    force_.fill(Eigen::Vector4d::Zero());
    viscous_force_.fill(Vec3::Zero());
    stable_step_.reset();
    return;
  }
  const bool distributed = parallel::world().size() > 1;
  if (distributed && share_.stale(nodes)) deal_anew(nodes);
  share_.bind(nodes);
  if (distributed && held_partition_ != nodes.partition) {  // the first deal after a checkpoint (read whole)
    hold_own_state(own_particles());
    // The state of the others' particles that the rows read comes in once the first list says which.
    hold_read_state(own_particles());
    held_partition_ = nodes.partition;
  }
  // A list read from a checkpoint has no rows (VerletList::checkpoint): one process searches every
  // row, a rank under MPI those it computes (as deal_anew), before a test for a rebuild may keep them.
  if (!distributed) verlet_.search_every_row(list_reach().every());
  if (distributed && reach_partition_ != nodes.partition) search_computed_rows(nodes, share_);
  gather_kinematics(nodes);
  const long long builds = verlet_.builds();
  update_neighbour_list(nodes);
  if (blocks_partition_ != nodes.partition) choose_force_blocks(nodes);  // a new deal or a restart
  if (distributed && (verlet_.builds() != builds || reach_partition_ != nodes.partition)) {
    plan_reach(nodes);
    hold_read_state(read_stretch());
    hold_nodes(nodes, false);
    // The step-start state of the particles the new rows read, from their ranks (h came in with the
    // list build's near particles, but not at the first build or after a checkpoint). A particle the
    // old rows did not read lies beyond every support after a rebuild for motion (the skin), but not
    // always after one for an h that outgrew its reach.
    reach_(volume_, sound_speed_, density_, smoothing_length_, material_, initial_smoothing_length_, mass_, spacing_,
           record_mass_);
  }
  update_records();
  Index first_unsound = n;
  with_discretization([&](auto kernel, auto corrected) {
    first_unsound = compute_rates<decltype(kernel), corrected>(dt);
  });
  if (categorizing()) {
    int interval = 1 << 30;
    for (const ColourField& c : options_.colour_field)
      if (c.enabled) interval = std::min(interval, c.interval);
    if (step_ % interval == 0) categorize();
    first_unsound = update_state(dt);
  }
  first_unsound = parallel::world().lowest(first_unsound);  // n (none) on every rank, or one particle
  share_updated_state();
  volume_.swap(updated_volume_);
  sound_speed_.swap(updated_sound_speed_);
  ++step_;
  check_state(nodes, first_unsound);
  with_discretization([&](auto kernel, auto corrected) { compute_pair_forces<decltype(kernel), corrected>(); });
  // h follows the density only now, so that both pair passes of a step use one kernel: the force
  // pass takes the rates pass's pick, and its force is exactly dual to the velocity gradient.
  // The same pass finds the next step's limit and whether an h has outgrown its list reach.
  struct Found {
    bool outgrown = false;
    Real step = std::numeric_limits<Real>::infinity();
  };
  const neighbors::ParticleRange own = own_particles(), passed = parallel::hull(own, read_state_held());
  const Found found = parallel::fold_exact(
      passed, Found{},
      [&](Found& found, Index a) {
        // h on every particle this rank's rows read: under MPI the others' follow the densities
        // that came in (the rest come in when the rows read them, search_near_rows, deal_anew).
        if (dt > 0 && current(a)) {
          const Real compression = materials_[material_[a]].density / density_[a];
          const Real scale = options_.dimension == 3 ? cube_root(compression) : std::sqrt(compression);
          const HBounds& bounds = h_bounds_[material_[a]];
          const Real h0 = initial_smoothing_length_[a];
          smoothing_length(a) = std::clamp(h0 * scale, h0 * bounds.lower, h0 * bounds.upper);
        }
        if (!owns(a)) return;  // another rank's: its rank finds its limit
        force_[a].head<3>() += viscous_force_[a];
        nodes.f[row(nodes, a)] += force_[a].head<3>();
        found.outgrown = found.outgrown || smoothing_length(a) > list_reach_[a];
        found.step = std::min(found.step, stable_step_of(a, nodes.v[row(nodes, a)]));
      },
      [](Found& found, const Found& other) {
        found.outgrown = found.outgrown || other.outgrown;
        found.step = std::min(found.step, other.step);
      });
  // Over the ranks: the smallest step, and whether any h has outgrown its reach (as 0 / -1).
  double global[2] = {found.step, found.outgrown ? -1.0 : 0.0};
  parallel::world().minimum(global);
  stable_step_ = global[0];
  h_outgrown_ = global[1] < 0;
}

// CFL condition dt <= h / (c s + |v|) per particle (docs/THEORY.md §3): the highest frequency of
// the linearized scheme, K = G^T (V D) G with G the velocity-gradient operator, is bounded by c
// times G's row sums (Gershgorin), so s = max(1, row sum of G at a / that of a full plain support)
// keeps the margin that LS-DYNA's h / (c + |v|) has for plain SPH on a lattice, also where the
// correction B or a cut or disordered support makes G larger. RULE 1 of *SPALL_SPH_TIMESTEP: s = 1.
Real SolidFormulation::stable_step_of(Index a, const Vec3& v) const {
  const Real s = options_.time_step_rule == TimeStepRule::plain ? Real(1)
                                                                 : std::max(Real(1), gradient_amplification_[a]);
  return smoothing_length(a) / (sound_speed_[a] * s + v.norm());
}

Real SolidFormulation::stable_time_step(const discretization::NodeStore& nodes) const {
  if (stable_step_) return *stable_step_;  // found by the last compute_forces
  // Under MPI its own particles: the time loop takes the minimum over the ranks.
  const neighbors::ParticleRange own = own_particles();
  return parallel::reduce_exact(
      own, std::numeric_limits<Real>::infinity(),
      [&](Index a) {
        return stable_step_of(a, nodes.v[row(nodes, a)]);
      },
      [](Real x, Real y) { return std::min(x, y); });
}

discretization::InternalPower SolidFormulation::internal_power(const discretization::NodeStore& nodes,
                                                               std::span<const Vec3> v) const {
  // Work of the internal forces on the nodes: strain energy grows by -f_stress . v, and the
  // artificial viscosity dissipates -f_visc . v >= 0. Exact sums (parallel::exact_sum).
  const neighbors::ParticleRange own = own_particles();  // under MPI, summed over the ranks
  const Sums<2> sums = parallel::exact_sum(
      own,
      [&](Index a) {
        const Vec3& va = v[row(nodes, a)];
        return Sums<2>{{(force_[a].head<3>() - viscous_force_[a]).dot(va), viscous_force_[a].dot(va)}};
      },
      &parallel::world());
  discretization::InternalPower p;
  p.stored = -sums[0];
  p.dissipated = -sums[1];
  return p;
}

void SolidFormulation::book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                                     std::span<const Vec3> v, Real dt) const {
  discretization::book_internal_power(ledger, internal_power(nodes, v), dt);
  const std::vector<Id>& parts = ledger.part_ids();
  if (parts.empty()) return;
  // *DATABASE_MATSUM: internal_power's stored share, each particle's under its part (a collective).
  const neighbors::ParticleRange own = own_particles();
  const std::vector<Real> power = parallel::exact_sums_by_group(
      own.size(), static_cast<int>(parts.size()),
      [&](Index k) { return ledger.part_slot(nodes.part[row(nodes, own.begin + k)]); },
      [&](Index k) {
        const Index a = own.begin + k;
        return -(force_[a].head<3>() - viscous_force_[a]).dot(v[row(nodes, a)]);
      },
      &parallel::world());
  for (std::size_t k = 0; k < parts.size(); ++k) ledger.add_part_work(k, dt * power[k]);
}

void SolidFormulation::write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const {
  const auto pressure = fields.node_real("pressure"), von_mises = fields.node_real("von_mises"),
             density = fields.node_real("density"), smoothing = fields.node_real("smoothing_length"),
             energy = fields.node_real("internal_energy"),
             plastic_strain = fields.node_real("effective_plastic_strain"),
             stress = fields.node_real("stress", 6, discretization::symmetric_tensor_components);
  // 1 once the material point has failed (spall, damage, FS): no deviatoric stress, no tension.
  const auto failed = fields.node_integer("failed");
  const auto neighbour_count = fields.node_integer("neighbour_count");
  const auto& list = verlet_.list();
  const neighbors::ParticleRange own = own_particles();  // under MPI each rank writes its own
  for (Index a = own.begin; a < own.end; ++a) {
    const Index i = row(nodes, a);
    const Mat3& S = state_[a].deviatoric_stress;
    plastic_strain[i] = state_[a].plastic_strain;
    failed[i] = state_[a].failed;
    pressure[i] = pressure_[a];
    von_mises[i] = materials::von_mises(S);
    density[i] = density_[a];
    smoothing[i] = smoothing_length(a);
    energy[i] = internal_energy_[a];
    const Mat3 sigma = S - pressure_[a] * Mat3::Identity();
    const double components[6] = {sigma(0, 0), sigma(1, 1), sigma(2, 2),
                                  sigma(0, 1), sigma(1, 2), sigma(2, 0)};
    for (int c = 0; c < 6; ++c) stress[6 * i + c] = components[c];
    neighbour_count[i] = list_built_ ? list.count(a) : 0;
  }
  if (has_temperature_) {
    const auto temperature = fields.node_real("temperature");
    for (Index a = own.begin; a < own.end; ++a) temperature[row(nodes, a)] = state_[a].temperature;
  }
  if (!category_.empty()) {
    const auto colour = fields.node_real("colour_field"), normal = fields.node_real("colour_normal", 3);
    const auto category = fields.node_integer("category");
    for (Index a = own.begin; a < own.end; ++a) {
      const Index i = row(nodes, a);
      colour[i] = colour_[a];
      for (int d = 0; d < 3; ++d) normal[3 * i + d] = colour_normal_[a][d];
      category[i] = static_cast<std::int64_t>(category_[a]);
    }
  }
  if (!exported_deviator_.empty()) {
    // What the relaxed treatment passes on (docs/THEORY.md §3); von_mises is the material's own.
    const auto exported = fields.node_real("exported_von_mises");
    for (Index a = own.begin; a < own.end; ++a)
      exported[row(nodes, a)] = materials::von_mises(exported_deviator_[a]);
  }
}

namespace {
template <typename T, typename Allocator>
std::size_t bytes(const std::vector<T, Allocator>& v) {
  return v.capacity() * sizeof(T);
}
template <typename T>
std::size_t bytes(const RangeArray<T>& v) {
  return v.capacity_bytes();
}
}  // namespace

// Everything but the materials and options (the deck's) and the spans into the node store or the
// copies, which the next compute_forces gathers again: what every rank holds alike (the set-up's,
// how the list searched, not its rows) from rank 0, then each particle's state, its position at the
// list's build and its reach among it, in pieces from the rank that computes it
// (discretization/particle_pieces.hpp).
void SolidFormulation::checkpoint(Archive& a, const discretization::NodeStore& nodes) {
  // 2: the list without its rows; 3: the constants in pieces; 4: no wave speed; 5: no copies of x and v;
  // 6: the list's positions at its build and reaches in pieces
  a.section("sph solid 6");
  a.expect_size("SPH solid particles", node_.size());
  a(node_, uniform_mass_, record_origin_, full_support_gradient_, support_mask_, force_blocks_,
    force_block_length_, verlet_, time_, step_, list_built_, h_outgrown_, stable_step_, has_temperature_);
  // The list's positions at its build, as it holds them (a rank's own under MPI), or none before
  // the first build.
  Own<Vec3> at_build;
  if (!a.reading() && list_built_) {
    const StretchView<Vec3> held = verlet_.positions_at_build();
    at_build.resize(0);
    at_build.hold(held.held_begin(), held.held_end());
    for (Index p = held.held_begin(); p < held.held_end(); ++p) at_build[p] = held[p];
  }
  // Read back under MPI once a list was built (its constants are held by rank then), into nodes
  // dealt already (the time loop deals them before it reads a restart file), each rank keeps its own
  // particles and brings in what its rows read as after a new deal; else every particle's, which
  // the first deal cuts to a rank's own.
  bool by_rank = false;
  if (a.reading() && parallel::world().size() > 1 && list_built_) {
    discretization::ParticleShare dealt;
    dealt.bind(nodes);
    if (dealt.dealt()) share_ = std::move(dealt), by_rank = true;
  }
  const neighbors::ParticleRange keep = by_rank ? own_particles() : neighbors::ParticleRange{0, particle_count()};
  discretization::archive_particle_pieces(
      a, "SPH particle", node_, share_, nodes, keep, list_reach_, at_build, material_, mass_, record_mass_,
      initial_smoothing_length_, spacing_,
      full_support_count_, smoothing_length_, record_, viscosity_record_, stress_, plain_stress_,
      density_, volume_, updated_volume_, pressure_, sound_speed_, updated_sound_speed_, internal_energy_, state_,
      back_stress_, gradient_amplification_, correction_, artificial_stress_, exported_deviator_, colour_,
      colour_normal_, support_count_, category_, density_rate_, velocity_gradient_, strain_rate_squared_,
      viscous_heating_, viscous_force_, force_);
  // Each rank then plans its reach and searches its rows again (search_computed_rows, from its own
  // particles' positions at the build and those near them), and read whole keeps its own particles'
  // state (and constants, once a list was built: else at the first build).
  if (a.reading()) {
    set_up_ = true, reach_partition_ = blocks_partition_ = held_partition_ = -1;
    constants_held_ = list_built_ && parallel::world().size() > 1;
    if (!at_build.empty()) verlet_.restore_positions(std::move(at_build));  // a rank's own, or every particle's
    if (by_rank) held_partition_ = nodes.partition;
  }
}

std::size_t SolidFormulation::memory_bytes() const {
  const auto& list = verlet_.list();
  return bytes(node_) + bytes(material_) + bytes(mass_) + bytes(smoothing_length_) + bytes(record_) + bytes(viscosity_record_) +
         bytes(record_mass_) + bytes(stress_) + bytes(plain_stress_) + bytes(list_reach_) +
         bytes(initial_smoothing_length_) + bytes(h_bounds_) + bytes(spacing_) +
         bytes(density_) + bytes(volume_) + bytes(updated_volume_) + bytes(pressure_) + bytes(sound_speed_) + bytes(updated_sound_speed_) + bytes(internal_energy_) +
         bytes(state_) + bytes(back_stress_) + bytes(gradient_amplification_) + bytes(correction_) +
         bytes(artificial_stress_) + bytes(exported_deviator_) + bytes(colour_) + bytes(colour_normal_) +
         bytes(support_count_) + bytes(full_support_count_) + bytes(category_) + bytes(x_copy_) + bytes(v_copy_) + bytes(density_rate_) + bytes(support_mask_) +
         bytes(viscous_heating_) + bytes(velocity_gradient_) + bytes(strain_rate_squared_) + bytes(force_) +
         bytes(viscous_force_) + bytes(list.offsets) + bytes(list.neighbors) +
         verlet_.reference_positions_bytes();
}

Real SolidFormulation::max_wave_speed() const { return max_wave_speed_; }

}  // namespace spall::sph
