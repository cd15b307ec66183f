#include "spall/sph/solid.hpp"

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <numeric>
#if defined(__AVX2__)
#include <immintrin.h>
#endif

#include <fmt/core.h>

#include "spall/core/error.hpp"
#include "spall/materials/elastic.hpp"

namespace spall::sph {

namespace {
// Support radius of the pair: the mean of both particles' supports 2h keeps W_ab symmetric.
inline Real pair_support(Real ha, Real hb) { return ha + hb; }

// Verlet skin as a fraction of the largest pair cutoff: a rebuild every few tens of steps at most.
constexpr Real skin_fraction = 0.1;
// Each particle's reach in the list exceeds its h by this factor, so that a growing smoothing
// length does not force a rebuild at every step.
constexpr Real cutoff_margin = 1.05;

// Below this the moment matrix is too ill-conditioned to invert (an isolated particle, or one
// whose neighbours lie in a plane): the particle keeps the uncorrected gradient.
constexpr Real min_moment_determinant = 1e-3;
}  // namespace

// The geometry of one Verlet row's pairs, per thread: x_a - x_b, r, 1/r, 1/H_ab and whether the
// pair is inside its support.
struct RowTerms {
  std::vector<Real> dx, dy, dz, r, inverse_r, inverse_support;
  std::vector<std::uint8_t> inside;
  void resize(std::size_t n) {
    if (r.size() >= n + 4) return;
    for (auto* v : {&dx, &dy, &dz, &r, &inverse_r, &inverse_support}) v->resize(n + 4);
    inside.resize(n + 4);
  }
};

// Fills terms[k] for the pairs (a, neighbour[k]), k in [0, count): four pairs at a time with AVX2
// (the square root and the two divisions are the pair loops' slowest operations), the rest one at
// a time by the same operations in the same order, so that every pair gets the same bits either
// way and (a, b) the same as (b, a).
inline void row_geometry(const Index* neighbour, Index count, const Real* position, const Real* h,
                         Index a, RowTerms& terms) {
  const Real xa = position[3 * a], ya = position[3 * a + 1], za = position[3 * a + 2], ha = h[a];
  Index k = 0;
#if defined(__AVX2__) && defined(__FMA__)
  for (; k + 4 <= count; k += 4) {
    const __m128i b = _mm_loadu_si128(reinterpret_cast<const __m128i*>(neighbour + k));
    const __m128i b3 = _mm_add_epi32(b, _mm_add_epi32(b, b));
    const auto gather = [](const Real* base, __m128i index) {
      const __m256d all = _mm256_castsi256_pd(_mm256_set1_epi64x(-1));
      return _mm256_mask_i32gather_pd(_mm256_setzero_pd(), base, index, all, 8);
    };
    const __m256d dx = _mm256_sub_pd(_mm256_set1_pd(xa), gather(position, b3));
    const __m256d dy = _mm256_sub_pd(_mm256_set1_pd(ya), gather(position + 1, b3));
    const __m256d dz = _mm256_sub_pd(_mm256_set1_pd(za), gather(position + 2, b3));
    const __m256d r2 = _mm256_fmadd_pd(dz, dz, _mm256_fmadd_pd(dy, dy, _mm256_mul_pd(dx, dx)));
    const __m256d H = _mm256_add_pd(_mm256_set1_pd(ha), gather(h, b));
    const __m256d r = _mm256_sqrt_pd(r2);
    const __m256d one = _mm256_set1_pd(1);
    _mm256_storeu_pd(&terms.dx[k], dx);
    _mm256_storeu_pd(&terms.dy[k], dy);
    _mm256_storeu_pd(&terms.dz[k], dz);
    _mm256_storeu_pd(&terms.r[k], r);
    _mm256_storeu_pd(&terms.inverse_r[k], _mm256_div_pd(one, r));
    _mm256_storeu_pd(&terms.inverse_support[k], _mm256_div_pd(one, H));
    const int mask = _mm256_movemask_pd(_mm256_cmp_pd(r2, _mm256_mul_pd(H, H), _CMP_LT_OQ));
    for (int lane = 0; lane < 4; ++lane) terms.inside[k + lane] = (mask >> lane) & 1;
  }
#endif
  for (; k < count; ++k) {
    const Index b = neighbour[k];
    const Real dx = xa - position[3 * b], dy = ya - position[3 * b + 1], dz = za - position[3 * b + 2];
    const Real r2 = std::fma(dz, dz, std::fma(dy, dy, dx * dx));
    const Real H = ha + h[b];
    const Real r = std::sqrt(r2);
    terms.dx[k] = dx;
    terms.dy[k] = dy;
    terms.dz[k] = dz;
    terms.r[k] = r;
    terms.inverse_r[k] = 1 / r;
    terms.inverse_support[k] = 1 / H;
    terms.inside[k] = r2 < H * H;
  }
}

// Calls visit(b, x_a - x_b, r, H_ab, grad_a W_ab) for every neighbour b of a inside the pair's
// support, in the fixed order of a's Verlet row, so that each particle's sums are added in the
// same order whatever the thread count.
template <typename Kernel, typename Visit>
inline void for_each_neighbour_in_support(const neighbors::NeighborList& list, Index a,
                                          std::span<const Vec3> x, std::span<const Real> h,
                                          Visit&& visit) {
  thread_local RowTerms terms;
  const Index first = list.offsets[a];
  const Index count = list.offsets[a + 1] - first;
  const Index* neighbour = list.neighbors.data() + first;
  terms.resize(count);
  row_geometry(neighbour, count, x.data()->data(), h.data(), a, terms);
  for (Index k = 0; k < count; ++k) {
    if (!terms.inside[k]) continue;
    const Index b = neighbour[k];
    const Vec3 xab(terms.dx[k], terms.dy[k], terms.dz[k]);
    const Real r = terms.r[k];
    // H_ab = pair_support(h_a, h_b) = h_a + h_b, the sum the geometry pass took.
    const Real H = pair_support(h[a], h[b]);
    const Vec3 grad = r > 0 ? Vec3(Kernel::gradient_factor(r, terms.inverse_r[k], terms.inverse_support[k]) * xab)
                            : Vec3::Zero();
    visit(b, xab, r, H, grad);
  }
}

SolidFormulation::SolidFormulation(std::vector<materials::Material> materials,
                                   const std::vector<ParticleSetup>& particles,
                                   SolidOptions options, const solver::NodeStore& nodes)
    : materials_(std::move(materials)), options_(options) {
  const std::size_t n = particles.size();
  node_.resize(n);
  material_.resize(n);
  mass_.resize(n);
  smoothing_length_.resize(n);
  list_reach_.resize(n);
  initial_smoothing_length_.resize(n);
  h_min_.resize(n);
  h_max_.resize(n);
  spacing_.resize(n);
  density_.resize(n);
  volume_.resize(n);
  pressure_.assign(n, 0);
  sound_speed_.resize(n);
  internal_energy_.assign(n, 0);
  state_.resize(n);
  gradient_amplification_.assign(n, 1);
  full_support_gradient_ = kernels::with_kernel(options_.kernel, options_.dimension, [](auto kernel) {
    return kernels::gradient_norm_integral<decltype(kernel)>();
  });
  corrected_stress_.assign(n, Mat3::Identity());
  if (options_.artificial_stress.enabled) artificial_stress_.assign(n, Mat3::Zero());
  density_rate_.assign(n, 0);
  viscous_heating_.assign(n, 0);
  velocity_gradient_.assign(n, Mat3::Zero());
  force_.assign(n, Vec3::Zero());
  viscous_force_.assign(n, Vec3::Zero());
  // Particles in node order: the node store is in cell order, so that neighbours are close in
  // memory, and a formulation owning a contiguous run of nodes reads their x and v in place.
  std::vector<std::size_t> by_node(n);
  std::iota(by_node.begin(), by_node.end(), std::size_t{0});
  std::stable_sort(by_node.begin(), by_node.end(),
                   [&](std::size_t i, std::size_t j) { return particles[i].node < particles[j].node; });
  for (std::size_t a = 0; a < n; ++a) {
    const auto& p = particles[by_node[a]];
    node_[a] = p.node;
    material_[a] = p.material;
    mass_[a] = nodes.mass[p.node];
    smoothing_length_[a] = initial_smoothing_length_[a] = p.smoothing_length;
    h_min_[a] = p.h_min;
    h_max_[a] = p.h_max;
    spacing_[a] = p.spacing;
    const auto& m = materials_[material_[a]];
    density_[a] = m.density;
    volume_[a] = mass_[a] / density_[a];
    state_[a] = materials::initial_state(m);
    internal_energy_[a] = m.initial_specific_energy;
    pressure_[a] = materials::eos_pressure(m, m.density, internal_energy_[a]);
    sound_speed_[a] = materials::sound_speed(m, m.density, internal_energy_[a]);
  }
  for (const auto& m : materials_)
    if (std::holds_alternative<materials::JohnsonCook>(m.strength)) has_temperature_ = true;
  bool contiguous = n > 0;
  for (std::size_t a = 1; a < n && contiguous; ++a) contiguous = node_[a] == node_[0] + Index(a);
  first_node_ = contiguous ? node_[0] : -1;
  const bool colour = std::any_of(options_.colour_field.begin(), options_.colour_field.end(),
                                  [](const ColourField& c) { return c.enabled; });
  if (colour) {
    colour_.assign(n, 0);
    colour_normal_.assign(n, Vec3::Zero());
    if (std::any_of(options_.colour_field.begin(), options_.colour_field.end(),
                    [](const ColourField& c) { return c.enabled && c.treat && !c.literal; })) {
      exported_deviator_.resize(n);
      for (std::size_t a = 0; a < n; ++a) exported_deviator_[a] = state_[a].deviatoric_stress;
    }
    support_count_.assign(n, 0);
    category_.assign(n, Category::interior);
    full_support_count_.resize(n);
    // Particles of spacing dp in a sphere (circle) of radius 2h, less the particle itself.
    for (std::size_t a = 0; a < n; ++a) {
      const Real ratio = 2 * smoothing_length_[a] / spacing_[a];
      full_support_count_[a] = options_.dimension == 2 ? M_PI * ratio * ratio - 1
                                                       : 4 * M_PI / 3 * ratio * ratio * ratio - 1;
    }
  }
}

bool SolidFormulation::active(Real time) const {
  return time >= options_.start_time && time <= options_.death_time;
}

void SolidFormulation::gather_kinematics(const solver::NodeStore& nodes) {
  const Index n = particle_count();
  if (first_node_ >= 0) {
    x_ = std::span<const Vec3>(nodes.x).subspan(first_node_, n);
    v_ = std::span<const Vec3>(nodes.v).subspan(first_node_, n);
    return;
  }
  x_copy_.resize(n);
  v_copy_.resize(n);
#pragma omp parallel for schedule(static)
  for (Index a = 0; a < n; ++a) {
    x_copy_[a] = nodes.x[node_[a]];
    v_copy_[a] = nodes.v[node_[a]];
  }
  x_ = x_copy_;
  v_ = v_copy_;
}

// The list holds every pair within reach_a + reach_b + skin at the build, reach = cutoff_margin h
// of that build; it stays complete while no two particles within the cutoff have moved by more
// than the skin relative to each other (VerletList::needs_rebuild) and no h_a has outgrown its
// reach. A per-pair reach keeps the rows of particles with the common h short when a few others
// (the rim of a splashing foot) expand.
void SolidFormulation::update_neighbour_list() {
  const Index n = particle_count();
  bool outgrown = !list_built_;
  for (Index a = 0; a < n && !outgrown; ++a) outgrown = smoothing_length_[a] > list_reach_[a];
  if (!outgrown && !verlet_.needs_rebuild(x_)) return;
  Real h_largest = 0;
  for (Index a = 0; a < n; ++a) {
    list_reach_[a] = cutoff_margin * smoothing_length_[a];
    h_largest = std::max(h_largest, smoothing_length_[a]);
  }
  verlet_.build(x_, list_reach_, skin_fraction * cutoff_margin * 2 * h_largest);
  list_built_ = true;
}

// Continuity and velocity gradient, gathered per particle over its full neighbour row.
template <typename Kernel>
void SolidFormulation::compute_rates() {
  const auto& list = verlet_.list();
  const Index n = particle_count();
  const bool plane = Kernel::dimension == 2;
  const bool colour_on = !category_.empty();
  // LS-DYNA's step (RULE 1) needs no row sums: the per-pair outer product is skipped.
  const bool row_sums = options_.time_step_rule != TimeStepRule::plain;
#pragma omp parallel for schedule(static)
  for (Index a = 0; a < n; ++a) {
    Real drho = 0;
    Mat3 L = Mat3::Zero();
    Mat3 moment = Mat3::Zero();  // sum_b V_b (x_b - x_a) (x) grad_a W_ab, = I for a full support
    Mat3 spread = Mat3::Zero();  // sum_b V_b grad (x) grad / |grad|, for the stable step
    Vec3 normal = Vec3::Zero();  // sum_b V_b grad_a W_ab (seed 000 eq. 9: n = grad c_s)
    Real colour = 0;
    std::int32_t count = 0;
    for_each_neighbour_in_support<Kernel>(list, a, x_, smoothing_length_,
                                          [&](Index b, const Vec3& xab, Real r, Real H, const Vec3& grad) {
      const Vec3 vba = v_[b] - v_[a];
      const Real volume = volume_[b];
      drho -= mass_[b] * vba.dot(grad);
      L.noalias() += volume * vba * grad.transpose();
      moment.noalias() -= volume * xab * grad.transpose();
      normal.noalias() += volume * grad;
      if (const Real g = row_sums ? grad.norm() : 0; g > 0) spread.noalias() += (volume / g) * grad * grad.transpose();
      if (colour_on) {
        colour += volume * Kernel::value(r, H);  // seed 000 eq. 10
        ++count;
      }
    });
    if (colour_on) {
      colour_[a] = colour + volume_[a] * Kernel::value(0, 2 * smoothing_length_[a]);
      colour_normal_[a] = normal;
      support_count_[a] = count;
    }
    // In plane strain nothing varies along z: the moment is the identity there.
    if (plane) moment(2, 2) = 1;
    Mat3 correction = Mat3::Identity();
    if (options_.gradient_correction) {
      // Randles & Libersky 1996: L B with B = moment^{-1} is exact for linear velocity fields,
      // also where the support is cut by a free surface; the density follows from tr(L).
      const Real det = moment.determinant();
      if (det > min_moment_determinant) {
        correction = moment.inverse();
        L = L * correction;
        drho = -density_[a] * L.trace();
      }
    }
    corrected_stress_[a] = correction;  // B_a, until update_state turns it into sigma_a B_a^T
    // Row sum of the gradient operator v -> L_a, sum_b V_b |B^T grad_a W_ab| + |B^T n_a| (the
    // second term: the weight of v_a itself), relative to a full support's; the first term by
    // Cauchy-Schwarz, sqrt(tr T tr(B^T T B)) with T = spread (exact when B = I).
    if (row_sums) {
      const Real row_sum = std::sqrt(spread.trace() * (correction.transpose() * spread * correction).trace()) +
                           (correction.transpose() * normal).norm();
      gradient_amplification_[a] = row_sum * 2 * smoothing_length_[a] / full_support_gradient_;
    }
    density_rate_[a] = drho;
    velocity_gradient_[a] = L;
  }
}

// Seed 000 §4: a particle is on the surface when it has fewer neighbours than a fraction of a full
// support AND its colour-field normal is large (|n| h above a threshold); the inner layers are the
// particles within 1.5 spacings of the previous layer. Each layer is found from the previous
// layer's flags only, so the result does not depend on the thread count.
void SolidFormulation::categorize() {
  const auto& list = verlet_.list();
  const Index n = particle_count();
  int layers = 0;
#pragma omp parallel for schedule(static)
  for (Index a = 0; a < n; ++a) {
    const ColourField& c = options_.colour_field[material_[a]];
    const bool surface = c.enabled &&
                         support_count_[a] < c.neighbour_fraction * full_support_count_[a] &&
                         colour_normal_[a].norm() * smoothing_length_[a] > c.normal_threshold;
    category_[a] = surface ? Category::surface : Category::interior;
  }
  for (const ColourField& c : options_.colour_field)
    if (c.enabled) layers = std::max(layers, c.layers);
  std::vector<std::uint8_t> previous(n), next(n);
  for (Index a = 0; a < n; ++a) previous[a] = category_[a] == Category::surface;
  for (int layer = 1; layer <= layers; ++layer) {
#pragma omp parallel for schedule(static)
    for (Index a = 0; a < n; ++a) {
      next[a] = 0;
      const ColourField& c = options_.colour_field[material_[a]];
      if (!c.enabled || layer > c.layers || category_[a] != Category::interior) continue;
      // The current spacing: the initial one scaled as h has been.
      const Real scale = smoothing_length_[a] / initial_smoothing_length_[a];
      const Real reach = Real(1.5) * spacing_[a] * scale;
      for (Index k = list.offsets[a]; k < list.offsets[a + 1]; ++k) {
        const Index b = list.neighbors[k];
        if (previous[b] && (x_[a] - x_[b]).squaredNorm() < reach * reach) {
          next[a] = 1;
          break;
        }
      }
    }
    for (Index a = 0; a < n; ++a)
      if (next[a]) category_[a] = Category::inner_layer;
    previous.swap(next);
  }
}

void SolidFormulation::update_state(Real dt) {
  const Index n = particle_count();
  const Real inverse_dimension = Real(1) / options_.dimension;
  const auto& stress_options = options_.artificial_stress;
  const bool relaxed = !exported_deviator_.empty();
#pragma omp parallel for schedule(static)
  for (Index a = 0; a < n; ++a) {
    const auto& m = materials_[material_[a]];
    const ColourField& colour = options_.colour_field.empty() ? ColourField{} : options_.colour_field[material_[a]];
    const bool treated = !category_.empty() && category_[a] != Category::interior && colour.treat;
    materials::PointState& state = state_[a];
    if (dt > 0) {
      const Mat3& L = velocity_gradient_[a];
      // The stress whose power the pair forces delivered: energy-consistent (docs/THEORY.md §3).
      const Mat3& S_power = relaxed ? exported_deviator_[a] : state.deviatoric_stress;
      const Mat3 sigma_old = S_power - pressure_[a] * Mat3::Identity();
      internal_energy_[a] += dt * (sigma_old.cwiseProduct(L).sum() / density_[a] + viscous_heating_[a]);
      density_[a] += dt * density_rate_[a];
      volume_[a] = mass_[a] / density_[a];
      // Objective (Jaumann) rotation of the stress deviator and back stress, then the material.
      const Mat3 W = Real(0.5) * (L - L.transpose());
      state.deviatoric_stress += dt * (W * state.deviatoric_stress - state.deviatoric_stress * W);
      state.back_stress += dt * (W * state.back_stress - state.back_stress * W);
      const Mat3 D = Real(0.5) * (L + L.transpose());
      pressure_[a] = materials::update_stress(m, state, D, dt, density_[a], internal_energy_[a]).pressure;
      if (relaxed) relax_exported_deviator(a, W, D, treated, colour.relaxation, dt);
      smoothing_length_[a] =
          std::clamp(initial_smoothing_length_[a] * std::pow(m.density / density_[a], inverse_dimension),
                     h_min_[a], h_max_[a]);
    }
    sound_speed_[a] = materials::sound_speed(m, density_[a], internal_energy_[a]);
    // The stress as the pair force uses it: sigma B^T (seed 000 eq. 8 for sigma).
    const Mat3 sigma = state.deviatoric_stress - pressure_[a] * Mat3::Identity();
    // Seed 000 §4: treated surface and inner-layer particles pass only their pressure on
    // (TFORM 2), or their relaxed deviator (TFORM 1).
    const Mat3 exported = relaxed ? Mat3(exported_deviator_[a] - pressure_[a] * Mat3::Identity())
                          : treated ? Mat3(-pressure_[a] * Mat3::Identity())
                                    : sigma;
    const Mat3 correction = corrected_stress_[a];  // B_a from compute_rates
    corrected_stress_[a] = exported * correction.transpose();
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
}

// Relaxed treatment (TFORM 1): the exported deviator S* is a Maxwell element with the material's
// shear modulus, dS*/dt = 2G dev D - (S* - target) / tau, tau = TAU h / c, that relaxes toward 0
// on a treated particle and toward the material's S on the others, and is kept within the
// yield surface (the larger of the static yield stress and |S|). A treated particle is thus as
// stiff and as strong as the material against motion faster than tau and under plastic flow at a
// strain rate above sigma_y / (2 G tau); a stress that persists at a lower rate (residual stress)
// is not passed on after a few tau, while the material's own S stays in the output. A failed
// particle exports no deviator.
void SolidFormulation::relax_exported_deviator(Index a, const Mat3& W, const Mat3& D, bool treated,
                                               Real relaxation, Real dt) {
  const auto& m = materials_[material_[a]];
  const materials::PointState& state = state_[a];
  Mat3& exported = exported_deviator_[a];
  if (state.failed) {
    exported = state.deviatoric_stress;
    return;
  }
  const Mat3 D_dev = D - D.trace() / 3 * Mat3::Identity();
  exported += dt * (W * exported - exported * W + 2 * m.shear_modulus * D_dev);
  const Mat3 target = treated ? Mat3::Zero() : state.deviatoric_stress;
  const Real tau = relaxation * smoothing_length_[a] / sound_speed_[a];
  exported = target + std::exp(-dt / tau) * (exported - target);  // exact decay over the step
  const Real bound = std::max(materials::static_yield_stress(m, state), materials::von_mises(state.deviatoric_stress));
  const Real size = materials::von_mises(exported);
  if (size > bound) exported *= bound / size;
}

void SolidFormulation::check_state(const solver::NodeStore& nodes) const {
  for (Index a = 0; a < particle_count(); ++a) {
    if (density_[a] > 0 && std::isfinite(density_[a]) && std::isfinite(smoothing_length_[a])) continue;
    throw InstabilityError(fmt::format(
        "SPH solid: node {} has density {:.6g} and smoothing length {:.6g}: its particle's "
        "neighbourhood has collapsed or torn apart (a smaller TSSFAC, or the artificial stress "
        "against the tensile instability, may help)",
        nodes.id[node_[a]], density_[a], smoothing_length_[a]));
  }
}

// Momentum, dual to the (corrected) velocity gradient: with P = sigma B^T,
//   f_a = sum_b V_a V_b (P_a + P_b) grad_a W_ab  -  sum_b m_a m_b Pi_ab grad_a W_ab
//         + sum_b m_a m_b f_ab^n (R_a + R_b) grad_a W_ab.
// Stress power sum_a V_a sigma_a : L_a equals -sum_a f_a . v_a exactly, and the pair term is
// antisymmetric, so linear momentum is conserved to round-off. Without correction (B = I) this is
// the symmetric SPH form of seed 000 eq. 7 with V_a V_b in place of m_a m_b / (rho_a rho_b).
template <typename Kernel>
void SolidFormulation::compute_pair_forces() {
  const auto& list = verlet_.list();
  const Index n = particle_count();
  const Real alpha = options_.viscosity.alpha, beta = options_.viscosity.beta;
  const Real eta2 = options_.viscosity.eta * options_.viscosity.eta;
  const bool stress_on = options_.artificial_stress.enabled;
  const Real exponent = options_.artificial_stress.exponent;
#pragma omp parallel for schedule(static)
  for (Index a = 0; a < n; ++a) {
    const Real rho_a = density_[a];
    const Real volume_a = volume_[a];
    const Mat3& P_a = corrected_stress_[a];
    Vec3 f = Vec3::Zero();
    Vec3 f_visc = Vec3::Zero();
    Real heating = 0;
    for_each_neighbour_in_support<Kernel>(list, a, x_, smoothing_length_,
                                          [&](Index b, const Vec3& xab, Real r, Real H, const Vec3& grad) {
      const Real rho_b = density_[b];
      // (P_a + P_b) and grad are exactly opposite for the pair (b, a): momentum is conserved
      // to round-off although each particle gathers its own sum.
      f.noalias() += (volume_a * volume_[b]) * ((P_a + corrected_stress_[b]) * grad);
      if (stress_on) {
        const Real dp = Real(0.5) * (spacing_[a] + spacing_[b]);
        const Real ratio = Kernel::value(r, H) / Kernel::value(dp, H);
        f.noalias() += (mass_[a] * mass_[b] * std::pow(ratio, exponent)) *
                       ((artificial_stress_[a] + artificial_stress_[b]) * grad);
      }
      const Vec3 vab = v_[a] - v_[b];
      const Real vr = vab.dot(xab);
      if (vr < 0) {
        const Real h = Real(0.5) * H;  // mean smoothing length
        const Real mu = h * vr / (r * r + eta2 * h * h);
        const Real c = Real(0.5) * (sound_speed_[a] + sound_speed_[b]);
        const Real rho = Real(0.5) * (rho_a + rho_b);
        const Real Pi = (-alpha * c * mu + beta * mu * mu) / rho;
        f_visc.noalias() -= (mass_[a] * mass_[b] * Pi) * grad;
        heating += Real(0.5) * mass_[b] * Pi * vab.dot(grad);
      }
    });
    viscous_force_[a] = f_visc;
    viscous_heating_[a] = heating;
    force_[a] = f + f_visc;
  }
}

void SolidFormulation::compute_forces(solver::NodeStore& nodes, Real dt) {
  time_ += dt;
  const Index n = particle_count();
  if (!active(time_)) {
    std::fill(force_.begin(), force_.end(), Vec3::Zero());
    std::fill(viscous_force_.begin(), viscous_force_.end(), Vec3::Zero());
    return;
  }
  gather_kinematics(nodes);
  update_neighbour_list();
  kernels::with_kernel(options_.kernel, options_.dimension,
                       [&](auto kernel) { compute_rates<decltype(kernel)>(); });
  if (!category_.empty()) {
    int interval = 1 << 30;
    for (const ColourField& c : options_.colour_field)
      if (c.enabled) interval = std::min(interval, c.interval);
    if (step_ % interval == 0) categorize();
  }
  ++step_;
  update_state(dt);
  check_state(nodes);
  kernels::with_kernel(options_.kernel, options_.dimension,
                       [&](auto kernel) { compute_pair_forces<decltype(kernel)>(); });
#pragma omp parallel for schedule(static)
  for (Index a = 0; a < n; ++a) nodes.f[node_[a]] += force_[a];
}

// CFL condition dt <= h / (c s + |v|) per particle (docs/THEORY.md §3): the highest frequency of
// the linearized scheme, K = G^T (V D) G with G the velocity-gradient operator, is bounded by c
// times G's row sums (Gershgorin), so s = max(1, row sum of G at a / that of a full plain support)
// keeps the margin that LS-DYNA's h / (c + |v|) has for plain SPH on a lattice, also where the
// correction B or a cut or disordered support makes G larger. RULE 1 of *SPALL_SPH_TIMESTEP: s = 1.
Real SolidFormulation::stable_time_step(const solver::NodeStore& nodes) const {
  const Index n = particle_count();
  const bool plain = options_.time_step_rule == TimeStepRule::plain;
  Real dt = std::numeric_limits<Real>::infinity();
#pragma omp parallel for reduction(min : dt) schedule(static)
  for (Index a = 0; a < n; ++a) {
    const Real s = plain ? Real(1) : std::max(Real(1), gradient_amplification_[a]);
    dt = std::min(dt, smoothing_length_[a] / (sound_speed_[a] * s + nodes.v[node_[a]].norm()));
  }
  return dt;
}

solver::Formulation::Power SolidFormulation::internal_power(std::span<const Vec3> v) const {
  // Work of the internal forces on the nodes: strain energy grows by -f_stress . v, and the
  // artificial viscosity dissipates -f_visc . v >= 0. Reduced in index order (deterministic).
  Power p;
  const Index n = particle_count();
  for (Index a = 0; a < n; ++a) {
    const Vec3& va = v[node_[a]];
    p.stored -= (force_[a] - viscous_force_[a]).dot(va);
    p.dissipated -= viscous_force_[a].dot(va);
  }
  return p;
}

void SolidFormulation::add_fields(std::vector<io::output::PointField>& fields,
                                  const solver::NodeStore& nodes) const {
  const std::size_t n_nodes = nodes.id.size();
  std::vector<double> pressure(n_nodes, 0), von_mises(n_nodes, 0), density(n_nodes, 0),
      smoothing(n_nodes, 0), mass(n_nodes, 0), energy(n_nodes, 0), plastic_strain(n_nodes, 0), temperature(n_nodes, 0),
      stress(6 * n_nodes, 0);
  std::vector<std::int64_t> neighbour_count(n_nodes, 0), failed(n_nodes, 0);
  const auto& list = verlet_.list();
  for (Index a = 0; a < particle_count(); ++a) {
    const Index i = node_[a];
    const Mat3& S = state_[a].deviatoric_stress;
    plastic_strain[i] = state_[a].plastic_strain;
    failed[i] = state_[a].failed;
    temperature[i] = state_[a].temperature;
    pressure[i] = pressure_[a];
    von_mises[i] = materials::von_mises(S);
    density[i] = density_[a];
    smoothing[i] = smoothing_length_[a];
    mass[i] = mass_[a];
    energy[i] = internal_energy_[a];
    const Mat3 sigma = S - pressure_[a] * Mat3::Identity();
    const double components[6] = {sigma(0, 0), sigma(1, 1), sigma(2, 2),
                                  sigma(0, 1), sigma(1, 2), sigma(2, 0)};
    std::copy(components, components + 6, stress.begin() + 6 * i);
    if (list_built_) neighbour_count[i] = list.count(a);
  }
  fields.push_back({"pressure", 1, std::move(pressure)});
  fields.push_back({"von_mises", 1, std::move(von_mises)});
  fields.push_back({"density", 1, std::move(density)});
  fields.push_back({"stress", 6, std::move(stress)});
  fields.push_back({"smoothing_length", 1, std::move(smoothing)});
  // With density, the particle's volume m / rho: what `spall surface` needs for the colour field.
  fields.push_back({"mass", 1, std::move(mass)});
  fields.push_back({"internal_energy", 1, std::move(energy)});
  fields.push_back({"effective_plastic_strain", 1, std::move(plastic_strain)});
  // 1 once the material point has failed (spall, damage, FS): no deviatoric stress, no tension.
  fields.push_back({"failed", 1, std::move(failed)});
  if (has_temperature_) fields.push_back({"temperature", 1, std::move(temperature)});
  if (!category_.empty()) {
    std::vector<double> colour(n_nodes, 0), normal(3 * n_nodes, 0);
    std::vector<std::int64_t> category(n_nodes, 0);
    for (Index a = 0; a < particle_count(); ++a) {
      const Index i = node_[a];
      colour[i] = colour_[a];
      for (int d = 0; d < 3; ++d) normal[3 * i + d] = colour_normal_[a][d];
      category[i] = static_cast<std::int64_t>(category_[a]);
    }
    fields.push_back({"colour_field", 1, std::move(colour)});
    fields.push_back({"colour_normal", 3, std::move(normal)});
    fields.push_back({"category", 1, std::move(category)});
  }
  if (!exported_deviator_.empty()) {
    // What the relaxed treatment passes on (docs/THEORY.md §3); von_mises is the material's own.
    std::vector<double> exported(n_nodes, 0);
    for (Index a = 0; a < particle_count(); ++a) exported[node_[a]] = materials::von_mises(exported_deviator_[a]);
    fields.push_back({"exported_von_mises", 1, std::move(exported)});
  }
  fields.push_back({"neighbour_count", 1, std::move(neighbour_count)});
}

namespace {
template <typename T>
std::size_t bytes(const std::vector<T>& v) {
  return v.capacity() * sizeof(T);
}
}  // namespace

std::size_t SolidFormulation::memory_bytes() const {
  const auto& list = verlet_.list();
  return bytes(node_) + bytes(material_) + bytes(mass_) + bytes(smoothing_length_) + bytes(list_reach_) +
         bytes(initial_smoothing_length_) + bytes(h_min_) + bytes(h_max_) + bytes(spacing_) +
         bytes(density_) + bytes(volume_) + bytes(pressure_) + bytes(sound_speed_) + bytes(internal_energy_) +
         bytes(state_) + bytes(gradient_amplification_) + bytes(corrected_stress_) +
         bytes(artificial_stress_) + bytes(exported_deviator_) + bytes(colour_) + bytes(colour_normal_) +
         bytes(support_count_) + bytes(full_support_count_) + bytes(category_) + bytes(x_copy_) + bytes(v_copy_) + bytes(density_rate_) +
         bytes(viscous_heating_) + bytes(velocity_gradient_) + bytes(force_) +
         bytes(viscous_force_) + bytes(list.offsets) + bytes(list.neighbors) +
         verlet_.reference_positions_bytes();
}

Real SolidFormulation::max_wave_speed() const {
  Real c = 0;
  for (Real s : sound_speed_) c = std::max(c, s);
  return c;
}

}  // namespace spall::sph
