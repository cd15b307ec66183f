#include "spall/spg/integration_constraint.hpp"

#include "spall/spg/parallel.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

#include <Eigen/LU>

namespace spall::spg {

namespace {

using Vec4 = Eigen::Matrix<Real, 4, 1>;

using Mat4 = Eigen::Matrix<Real, 4, 4>;

// The unknowns (or a residual) of the normal equations, per particle: of the particles a stretch
// holds (under MPI a rank's own, and for the vectors whose bond partners' values a rank reads,
// those partners too; every particle on one process), zero to start.
struct Multipliers {
  RangeArray<Vec3> lambda;
  RangeArray<Mat3> mu;
  explicit Multipliers(parallel::Range held) {
    lambda.hold_afresh(held.begin, held.end, Vec3::Zero());
    mu.hold_afresh(held.begin, held.end, Mat3::Zero());
  }
};

// Which particles this rank computes, and the ranks a sum over them is taken across.
struct Ownership {
  parallel::Range particles;
  const parallel::Communicator* across;
};

// Per gradient component i: sum over the particles of lambda_i lambda'_i + mu_i . mu'_i, for each
// of the K pairs (a, b), as exact sums over every rank's particles (one reduction for all K).
template <std::size_t K>
std::array<Vec3, K> dots(const std::array<std::pair<const Multipliers*, const Multipliers*>, K>& pairs,
                         const Ownership& own) {
  const auto sums = parallel::exact_sum(own.particles, [&](Index j) {
    Sums<3 * static_cast<int>(K)> t{};
    for (std::size_t p = 0; p < K; ++p) {
      const Multipliers& a = *pairs[p].first;
      const Multipliers& b = *pairs[p].second;
      const Vec3 s = a.lambda[j].cwiseProduct(b.lambda[j]) + a.mu[j].cwiseProduct(b.mu[j]).rowwise().sum();
      for (int i = 0; i < 3; ++i) t[3 * p + i] = s[i];
    }
    return t;
  }, own.across);
  std::array<Vec3, K> result;
  for (std::size_t p = 0; p < K; ++p) result[p] = Vec3(sums[3 * p], sums[3 * p + 1], sums[3 * p + 2]);
  return result;
}

// The root mean square length of row j's bonds that `counts` (1 where it has none).
template <typename Counts>
Real row_length(const BondList& bonds, StretchView<Vec3> X, Index j, Counts&& counts) {
  Real sum = 0;
  Index count = 0;
  for (Index k = bonds.offsets[j]; k < bonds.offsets[j + 1]; ++k)
    if (counts(k)) sum += (X[bonds.neighbour[k]] - X[j]).squaredNorm(), ++count;
  return count > 0 && sum > 0 ? std::sqrt(sum / count) : Real(1);
}

class NormalEquations {
 public:
  NormalEquations(const BondList& bonds, StretchView<Vec3> X, StretchView<std::uint8_t> interior,
                  StretchView<std::uint8_t> active, const Ownership& own)
      : bonds_(bonds),
        neighbour_(bonds.neighbour.view(bonds.entry_count())),
        broken_(bonds.broken.view(bonds.entry_count())),
        X_(X),
        interior_(interior),
        active_(active),
        own_(own) {
    // Block-Jacobi preconditioner: the particle's own 4 x 4 block sum_L [1; d][1; d]^T (3 x 3
    // without the divergence row where the particle is not interior), the same for every
    // gradient component. Of a rank's own particles.
    preconditioner_.hold_afresh(own.particles.begin, own.particles.end, Mat4::Zero());
    parallel::for_each(own.particles, [&](Index j) {
      if (!active_[j]) return;
      // In the row's length scale l (the block is T P~ T with T = diag(1, l, l, l)), so that the
      // ridge below, and the preconditioner, do not depend on the deck's units.
      const Real l = row_length(bonds, X_, j, [&](Index k) { return usable(j, k); });
      Mat4 P = Mat4::Zero();
      for (Index k = bonds.offsets[j]; k < bonds.offsets[j + 1]; ++k) {
        if (!usable(j, k)) continue;
        Vec4 h;
        h << 1, (X_[neighbour_[k]] - X_[j]) / l;
        P += h * h.transpose();
      }
      if (!interior_[j]) {
        P.row(0).setZero();
        P.col(0).setZero();
        P(0, 0) = 1;
      }
      // A particle with its bonds in a plane leaves P singular: a small ridge keeps the
      // preconditioner positive definite (it only changes the convergence speed).
      P += 1e-12 * P.trace() * Mat4::Identity();
      const Vec4 t_inverse(1, 1 / l, 1 / l, 1 / l);
      Mat4 inverse = t_inverse.asDiagonal() * P.inverse() * t_inverse.asDiagonal();
      if (!interior_[j]) {
        inverse.row(0).setZero();
        inverse.col(0).setZero();
      }
      preconditioner_[j] = inverse;
    }, particle_loops);
  }

  bool usable(Index j, Index k) const { return !broken_[k] && active_[neighbour_[k]] && active_[j]; }

  // (M^-1 r)_j: its divergence part returned, its first-moment part in `mu`.
  Vec3 preconditioned(const Multipliers& r, Index j, Mat3& mu) const {
    Vec3 lambda;
    for (int i = 0; i < 3; ++i) {
      Vec4 b;
      b << r.lambda[j][i], r.mu[j].row(i).transpose();
      const Vec4 s = preconditioner_[j] * b;
      lambda[i] = s[0];
      mu.row(i) = s.tail<3>().transpose();
    }
    return lambda;
  }

  // The flux of bond k (row j) for multipliers (lambda, mu): c = (lambda_j - lambda_l) + (mu_j + mu_l) d.
  Vec3 flux(StretchView<Vec3> lambda, StretchView<Mat3> mu, Index j, Index k) const {
    const Index l = neighbour_[k];
    return (lambda[j] - lambda[l]) + (mu[j] + mu[l]) * (X_[l] - X_[j]);
  }

  // y = R R^T z: per particle the divergence (interior only) and first moment of the fluxes (this
  // rank's particles; z of them and their bond partners).
  void apply(const Multipliers& z, Multipliers& y) const {
    // The multipliers read through views held by the pass (a RangeArray's first index and data
    // reloaded at every bond cost the solve a tenth of its time).
    const StretchView<Vec3> lambda = z.lambda.view(bonds_.size());
    const StretchView<Mat3> mu = z.mu.view(bonds_.size());
    parallel::for_each(own_.particles, [&, lambda, mu](Index j) {
      Vec3 div = Vec3::Zero();
      Mat3 moment = Mat3::Zero();
      if (active_[j])
        for (Index k = bonds_.offsets[j]; k < bonds_.offsets[j + 1]; ++k) {
          if (!usable(j, k)) continue;
          const Vec3 c = flux(lambda, mu, j, k);
          div += c;
          moment.noalias() += c * (X_[neighbour_[k]] - X_[j]).transpose();
        }
      y.lambda[j] = interior_[j] ? div : Vec3::Zero();
      y.mu[j] = moment;
    }, particle_loops);
  }

  void precondition(const Multipliers& r, Multipliers& z) const {
    parallel::for_each(own_.particles, [&](Index j) { z.lambda[j] = preconditioned(r, j, z.mu[j]); }, particle_loops);
  }

  // Per gradient component, r . M^-1 r over every rank's particles (an exact sum), M^-1 r not kept.
  Vec3 preconditioned_norm(const Multipliers& r) const {
    const auto sums = parallel::exact_sum(own_.particles, [&](Index j) {
      Mat3 mu;
      const Vec3 lambda = preconditioned(r, j, mu);
      const Vec3 s = r.lambda[j].cwiseProduct(lambda) + r.mu[j].cwiseProduct(mu).rowwise().sum();
      return Sums<3>{s[0], s[1], s[2]};
    }, own_.across);
    return Vec3(sums[0], sums[1], sums[2]);
  }

  // z -= a M^-1 r per gradient component (a_i scales component i), M^-1 r not kept.
  void subtract_preconditioned(const Vec3& a, const Multipliers& r, Multipliers& z) const {
    parallel::for_each(own_.particles, [&](Index j) {
      Mat3 mu;
      const Vec3 lambda = preconditioned(r, j, mu);
      z.lambda[j] += (-a).cwiseProduct(lambda);
      z.mu[j] += (-a).asDiagonal() * mu;
    }, particle_loops);
  }

 private:
  const BondList& bonds_;
  // The rows' neighbours and flags through views (as the multipliers in apply).
  StretchView<Index> neighbour_;
  StretchView<std::uint8_t> broken_;
  StretchView<Vec3> X_;
  StretchView<std::uint8_t> interior_;
  StretchView<std::uint8_t> active_;
  const Ownership& own_;
  RangeArray<Mat4> preconditioner_;
};

// z += a r per gradient component (a_i scales component i), for this rank's particles.
void axpy(const Vec3& a, const Multipliers& r, Multipliers& z, const Ownership& own) {
  parallel::for_each(own.particles, [&](Index j) {
    z.lambda[j] += a.cwiseProduct(r.lambda[j]);
    z.mu[j] += a.asDiagonal() * r.mu[j];
  }, particle_loops);
}

// Stop when the residual is 1e-13 of the right-hand side, or at round-off (1e-15) of the natural
// size of the column sums (a regular lattice needs no iteration at all).
constexpr Real tolerance = 1e-13;
constexpr Real natural_tolerance = 1e-15;

}  // namespace

// Removes the first moment that an unconverged solve leaves in row j of the correction, by the
// smallest change that keeps the row sum: delta_L = a + B d_L per gradient component, with
// sum_L delta_L [1, d_L] = [0, moment] (the 4 x 4 system of the row's bond geometry). The row then
// reproduces linear fields exactly whatever the solver reached; only its column sums (the
// integration constraint) carry the solver's residual. Returns (a, B), row i of each gradient
// component i's; the system is taken in the row's length scale l (d / l for d), so that its rank
// test does not depend on the deck's units.
std::pair<Vec3, Mat3> row_moment_removal(const BondList& bonds, StretchView<Vec3> X, Index j, std::span<const Vec3> row,
                                         const std::vector<std::uint8_t>& usable) {
  const Real l = row_length(bonds, X, j, [&](Index k) { return usable[k - bonds.offsets[j]] != 0; });
  Mat4 M = Mat4::Zero();
  Mat3 moment = Mat3::Zero();  // row i: gradient component i, over l
  for (Index k = bonds.offsets[j]; k < bonds.offsets[j + 1]; ++k) {
    if (!usable[k - bonds.offsets[j]]) continue;
    const Vec3 d = (X[bonds.neighbour[k]] - X[j]) / l;
    Vec4 h;
    h << 1, d;
    M += h * h.transpose();
    moment.noalias() += row[k - bonds.offsets[j]] * d.transpose();
  }
  Vec3 a = Vec3::Zero();
  Mat3 B = Mat3::Zero();
  // Exactly zero only: Eigen's isZero() compares with an absolute 1e-12, below which every moment
  // of a deck in metres falls (a flux times a spacing, of order h^3).
  if (moment.isZero(0)) return {a, B};
  const Eigen::FullPivLU<Mat4> lu(M);
  if (lu.rank() < 4) return {a, B};  // bonds in a plane: the particle is degraded and has no row
  for (int i = 0; i < 3; ++i) {
    Vec4 rhs;
    rhs << 0, moment.row(i).transpose();
    const Vec4 ab = lu.solve(rhs);
    a[i] = ab[0];
    B.row(i) = ab.tail<3>().transpose() / l;
  }
  return {a, B};
}

void correct_integration(const BondList& bonds, StretchView<Vec3> X, StretchView<Real> volume,
                         StretchView<std::uint8_t> interior, StretchView<std::uint8_t> active,
                         StretchView<Vec3> defect, int max_iterations, parallel::Range own_particles,
                         const discretization::ParticleShare& share, const discretization::ReachShare& reach,
                         IntegrationCorrection& correction) {
  const Index n = bonds.size();
  const Ownership own{own_particles, share.across()};
  const NormalEquations equations(bonds, X, interior, active, own);
  // The fluxes of a rank's rows read the multipliers and the preconditioned residual of the bond
  // partners of its own particles (brought in by `reach`): those two hold the stretch from the
  // first of them to the last, the others a rank's own particles.
  parallel::Range read = own.particles;
  for (Index j = own.particles.begin; j < own.particles.end; ++j)
    for (Index k = bonds.offsets[j]; k < bonds.offsets[j + 1]; ++k)
      read = parallel::hull(read, {bonds.neighbour[k], bonds.neighbour[k] + 1});
  // Six vectors of multipliers (96 B a particle each; the solve's scratch sets SPG's peak memory).
  Multipliers z(read), r(own.particles), s(read), As(own.particles), p(own.particles), Ap(own.particles);
  for (Index j = read.begin; j < read.end; ++j) z.lambda[j] = correction.lambda[j], z.mu[j] = correction.mu[j];
  reach(z.lambda, z.mu);
  // Right-hand side b (in r until the residual r = b - A z is formed): sum_L c_JL = e_J / 2 at
  // interior particles (then the column sums of D' are zero there), zero first moments everywhere.
  for (Index j = own.particles.begin; j < own.particles.end; ++j)
    if (interior[j] && active[j]) r.lambda[j] = Real(0.5) * defect[j];
  // Sizes are taken in the preconditioner's norm, |r|^2 = r . M^-1 r: the norm the solve below
  // lowers at every iteration, and one the deck's units do not change (a residual's divergence
  // and first moment differ by a length; M^-1 scales them alike).
  const Vec3 b_norm = equations.preconditioned_norm(r).cwiseSqrt();
  equations.apply(z, As);
  for (Index j = own.particles.begin; j < own.particles.end; ++j) {
    r.lambda[j] = r.lambda[j] - As.lambda[j];
    r.mu[j] = -As.mu[j];
  }
  // The natural size of the column sums, V_J / h_J ~ V_J^(2/3) per particle: an exact sum over
  // every rank's own particles, whose volumes are current there (a rank's copies of the others'
  // are stale between new deals), so that every rank stops the solve at the same iteration.
  const Real reference =
      parallel::exact_sum(own.particles, [&](Index j) { return std::pow(volume[j], Real(4) / 3); }, own.across);
  const Real floor = natural_tolerance * std::sqrt(reference);
  auto converged = [&](const Vec3& rs) {
    for (int i = 0; i < 3; ++i)
      if (std::sqrt(rs[i]) > std::max(tolerance * b_norm[i], floor)) return false;
    return true;
  };
  // Preconditioned conjugate residuals (Saad 2003, Iterative Methods for Sparse Linear Systems, the
  // conjugate residual method applied to M^-1 A in the M inner product): of the Krylov space's
  // iterates it takes the one whose residual is least in the M^-1 norm, which therefore never rises.
  // Conjugate gradients' residual does, and on a body too large for the solve to converge it ended
  // at 4.8 times its start (THEORY §9.4). The preconditioned residual s is the one vector whose
  // neighbours' values a rank reads (apply).
  auto next_residual = [&] {
    reach(s.lambda, s.mu);
    equations.apply(s, As);
    return dots<2>({{{&s, &As}, {&r, &s}}}, own);
  };
  equations.precondition(r, s);
  auto [sAs, rs] = next_residual();
  for (Index j = own.particles.begin; j < own.particles.end; ++j)
    p.lambda[j] = s.lambda[j], p.mu[j] = s.mu[j], Ap.lambda[j] = As.lambda[j], Ap.mu[j] = As.mu[j];
  int iteration = 0;
  while (!converged(rs) && iteration < max_iterations) {
    const Vec3 Ap_q = equations.preconditioned_norm(Ap);  // Ap . M^-1 Ap
    Vec3 alpha = Vec3::Zero();
    for (int i = 0; i < 3; ++i) alpha[i] = Ap_q[i] > 0 ? sAs[i] / Ap_q[i] : 0;
    axpy(alpha, p, z, own);
    axpy(-alpha, Ap, r, own);
    equations.subtract_preconditioned(alpha, Ap, s);
    const auto [sAs_next, rs_next] = next_residual();
    Vec3 beta = Vec3::Zero();
    for (int i = 0; i < 3; ++i) beta[i] = sAs[i] > 0 ? sAs_next[i] / sAs[i] : 0;
    sAs = sAs_next;
    rs = rs_next;
    parallel::for_each(own.particles, [&](Index j) {
      p.lambda[j] = s.lambda[j] + beta.cwiseProduct(p.lambda[j]);
      p.mu[j] = s.mu[j] + beta.asDiagonal() * p.mu[j];
      Ap.lambda[j] = As.lambda[j] + beta.cwiseProduct(Ap.lambda[j]);
      Ap.mu[j] = As.mu[j] + beta.asDiagonal() * Ap.mu[j];
    }, particle_loops);
    ++iteration;
  }
  correction.iterations = iteration;
  Real worst = 0;
  for (int i = 0; i < 3; ++i)
    if (b_norm[i] > 0) worst = std::max(worst, std::sqrt(rs[i]) / b_norm[i]);
  correction.relative_residual = worst;
  reach(z.lambda, z.mu);
  for (Index j = read.begin; j < read.end; ++j) correction.lambda[j] = z.lambda[j], correction.mu[j] = z.mu[j];

  // Per particle: the row's moment removal folded into alpha and beta (correction_flux), and C_JJ.
  const StretchView<Vec3> lambda = z.lambda.view(n);
  const StretchView<Mat3> mu = z.mu.view(n);
  parallel::region([&](const parallel::Team& team) {
    std::vector<Vec3> row;
    std::vector<std::uint8_t> usable;
    team.for_each(own.particles, [&](Index j) {
      const Index count = bonds.count(j);
      row.assign(count, Vec3::Zero());
      usable.assign(count, 0);
      for (Index k = bonds.offsets[j]; k < bonds.offsets[j + 1]; ++k) {
        if (!equations.usable(j, k)) continue;
        usable[k - bonds.offsets[j]] = 1;
        row[k - bonds.offsets[j]] = equations.flux(lambda, mu, j, k);
      }
      const auto [a, B] = row_moment_removal(bonds, X, j, row, usable);
      correction.alpha[j] = lambda[j] - a;
      correction.beta[j] = mu[j] - B;
      correction.reference[j] = X[j];
      Vec3 sum = Vec3::Zero();
      for (Index k = bonds.offsets[j]; k < bonds.offsets[j + 1]; ++k)
        if (usable[k - bonds.offsets[j]])
          sum += correction_flux(correction.alpha[j], correction.beta[j], X[j], lambda[bonds.neighbour[k]],
                                 mu[bonds.neighbour[k]], X[bonds.neighbour[k]]);
      correction.self[j] = -sum / volume[j];
    });
  }, n > parallel_threshold);
  // What a rank's forces read of the partners' (their multipliers came in above).
  reach(correction.alpha, correction.beta, correction.reference);
}

}  // namespace spall::spg
