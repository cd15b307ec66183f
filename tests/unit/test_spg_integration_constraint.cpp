// The integration-constraint correction of SPG's nodal gradient operator (THEORY §9.4) as a solve
// on its own: on irregular particles the corrected operator meets its defining equations, the
// integration constraint sum_J V_J (D + C)_JK = 0 at interior particles (Chen, Wu, Yoon & You
// 2001), zero row sums and zero first moments of C (momentum, exact constant strain); and a solve
// stopped short, the conjugate-residual method's iterate (Saad 2003, Iterative Methods for Sparse
// Linear Systems), never leaves the constraint further from met than no correction at all.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <vector>

#include "spall/spg/integration_constraint.hpp"

using namespace spall;
using namespace spall::spg;

namespace {

// Particles on a jittered n^3 lattice of spacing h with nodal volumes about h^3, bonded within 2.2
// spacings; interior: three layers or more inside the surface. The defect e_K of the uncorrected
// operator is what the correction removes; any field of its size (h^2) will do for the solve (a
// random one here, at interior particles).
struct Cloud {
  static constexpr int n = 10;
  std::vector<Vec3> x;
  RangeArray<Real> volume;
  RangeArray<std::uint8_t> interior, active;
  RangeArray<Vec3> defect;
  BondList bonds;

  explicit Cloud(Real h) {
    std::mt19937 random(2001);
    std::uniform_real_distribution<Real> jitter(-0.25, 0.25);
    const Index count = n * n * n;
    volume.hold_afresh(0, count), interior.hold_afresh(0, count), active.hold_afresh(0, count, 1);
    defect.hold_afresh(0, count, Vec3::Zero());
    for (int i = 0; i < n; ++i)
      for (int j = 0; j < n; ++j)
        for (int k = 0; k < n; ++k) {
          const Index a = static_cast<Index>(x.size());
          x.push_back(h * Vec3(i + jitter(random), j + jitter(random), k + jitter(random)));
          volume[a] = h * h * h * (1 + 0.2 * jitter(random));
          const auto inside = [](int c) { return c >= 3 && c < n - 3; };
          interior[a] = inside(i) && inside(j) && inside(k);
          if (interior[a]) defect[a] = h * h * Vec3(jitter(random), jitter(random), jitter(random));
        }
    neighbors::NeighborList list;
    list.offsets.push_back(0);
    for (Index a = 0; a < count; ++a) {
      for (Index b = 0; b < count; ++b)
        if (b != a && (x[a] - x[b]).norm() < 2.2 * h) list.neighbors.push_back(b);
      list.offsets.push_back(static_cast<Index>(list.neighbors.size()));
    }
    bonds = make_bonds(list, x, [](Index, Index) { return true; }, nullptr, {});
  }
  Index size() const { return static_cast<Index>(x.size()); }

  IntegrationCorrection correct(int max_iterations) const {
    IntegrationCorrection c;
    c.self.hold_afresh(0, size(), Vec3::Zero()), c.alpha.hold_afresh(0, size(), Vec3::Zero());
    c.beta.hold_afresh(0, size(), Mat3::Zero()), c.reference.hold_afresh(0, size(), Vec3::Zero());
    c.lambda.hold_afresh(0, size(), Vec3::Zero()), c.mu.hold_afresh(0, size(), Mat3::Zero());
    correct_integration(bonds, x, volume.view(size()), interior.view(size()), active.view(size()), defect.view(size()),
                        max_iterations, {0, size()}, {}, {}, c);
    return c;
  }

  // C_JK of bond k in row J (every bond is usable here).
  Vec3 bond(const IntegrationCorrection& c, Index J, Index k) const {
    const Index K = bonds.neighbour[k];
    return correction_flux(c.alpha[J], c.beta[J], c.reference[J], c.lambda[K], c.mu[K], c.reference[K]) / volume[J];
  }

  // e_K + sum_J V_J C_JK at each interior particle K: what is left of the integration constraint.
  std::vector<Vec3> constraint_left(const IntegrationCorrection& c) const {
    std::vector<Vec3> column(size());
    for (Index K = 0; K < size(); ++K) column[K] = defect[K] + volume[K] * c.self[K];
    for (Index J = 0; J < size(); ++J)
      for (Index k = bonds.offsets[J]; k < bonds.offsets[J + 1]; ++k)
        column[bonds.neighbour[k]] += volume[J] * bond(c, J, k);
    std::vector<Vec3> left;
    for (Index K = 0; K < size(); ++K)
      if (interior[K]) left.push_back(column[K]);
    return left;
  }
};

Real norm(const std::vector<Vec3>& v) {
  Real sum = 0;
  for (const Vec3& a : v) sum += a.squaredNorm();
  return std::sqrt(sum);
}

Real largest(const std::vector<Vec3>& v) {
  Real m = 0;
  for (const Vec3& a : v) m = std::max(m, a.cwiseAbs().maxCoeff());
  return m;
}

// The largest first moment sum_K C_JK (X_K - X_J) of a row against the row's size sum_K |C_JK| |X_K - X_J|.
Real worst_row_moment(const Cloud& cloud, const IntegrationCorrection& c) {
  Real worst = 0;
  for (Index J = 0; J < cloud.size(); ++J) {
    Mat3 moment = Mat3::Zero();
    Real size = 0;
    for (Index k = cloud.bonds.offsets[J]; k < cloud.bonds.offsets[J + 1]; ++k) {
      const Vec3 d = cloud.x[cloud.bonds.neighbour[k]] - cloud.x[J];
      const Vec3 C = cloud.bond(c, J, k);
      moment += C * d.transpose();
      size += C.norm() * d.norm();
    }
    if (size > 0) worst = std::max(worst, moment.cwiseAbs().maxCoeff() / size);
  }
  return worst;
}

}  // namespace

// Spacings of 1 and of 0.2 mm in metres (the drilling plate's, tools/make_drilling_deck.py).
class SpgIntegrationConstraint : public testing::TestWithParam<Real> {};

TEST_P(SpgIntegrationConstraint, ConvergedCorrectionMeetsTheConstraintAndKeepsRowsExact) {
  const Cloud cloud(GetParam());
  const IntegrationCorrection c = cloud.correct(2000);
  EXPECT_LT(c.iterations, 2000);
  // The solve stops at 1e-13 of the right-hand side; the columns' sums over some hundred bonds add
  // their round-off: 1e-11 of the largest defect.
  const std::vector<Vec3> uncorrected = cloud.constraint_left(cloud.correct(0));
  EXPECT_LT(largest(cloud.constraint_left(c)), 1e-11 * largest(uncorrected));
  EXPECT_LT(worst_row_moment(cloud, c), 1e-14);
}

TEST_P(SpgIntegrationConstraint, UnconvergedSolveNeverLeavesTheConstraintWorseThanNone) {
  const Cloud cloud(GetParam());
  const Real none = norm(cloud.constraint_left(cloud.correct(0)));
  ASSERT_GT(none, 0);
  Real previous = 1;  // the residual of no correction, relative to itself
  for (int cap : {1, 2, 3, 5, 8, 13, 21, 34}) {
    const IntegrationCorrection c = cloud.correct(cap);
    ASSERT_EQ(c.iterations, cap) << "the solve must still be running at the cap";
    // Conjugate residuals lower the residual in the preconditioner's norm at every iteration.
    EXPECT_LE(c.relative_residual, previous) << cap << " iterations";
    previous = c.relative_residual;
    // The rows' first moments are then removed row by row, which moves the columns' sums a little.
    EXPECT_LT(norm(cloud.constraint_left(c)), none) << cap << " iterations";
    // Whatever the solver reached, the rows stay exact for linear fields (to round-off; Eigen's
    // default isZero, an absolute 1e-12, once left them uncorrected in metres).
    EXPECT_LT(worst_row_moment(cloud, c), 1e-14) << cap << " iterations";
  }
}

INSTANTIATE_TEST_SUITE_P(Spacings, SpgIntegrationConstraint, testing::Values(1.0, 2e-4));

// The same cloud in other units: the same iterations and the same correction, to round-off (a ridge
// of 1e-12 of the preconditioner's trace, which mixed a count with squared lengths, once moved the
// correction in metres by 5e-7 of itself).
TEST(SpgIntegrationConstraintUnits, TheSolveDoesNotDependOnTheDecksUnits) {
  const Real h = 2e-4;
  const Cloud unit(1), metres(h);
  for (int cap : {3, 21, 2000}) {
    const IntegrationCorrection a = unit.correct(cap), b = metres.correct(cap);
    EXPECT_EQ(a.iterations, b.iterations) << cap;
    // Stopped at the cap, the residuals agree to round-off (converged, they are round-off).
    if (a.iterations == cap) {
      EXPECT_NEAR(a.relative_residual, b.relative_residual, 1e-12 * a.relative_residual) << cap;
    }
    // C has the units of a gradient, 1 / length.
    Real worst = 0, size = 0;
    for (Index J = 0; J < unit.size(); ++J)
      for (Index k = unit.bonds.offsets[J]; k < unit.bonds.offsets[J + 1]; ++k) {
        worst = std::max(worst, (unit.bond(a, J, k) - h * metres.bond(b, J, k)).norm());
        size = std::max(size, unit.bond(a, J, k).norm());
      }
    EXPECT_LT(worst, 1e-12 * size) << cap;
  }
}
