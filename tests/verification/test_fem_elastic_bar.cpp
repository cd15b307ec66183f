// Free-free elastic bar of solid finite elements (20 x 2 x 2 hexahedra) against the closed-form
// first longitudinal mode (support/spg_bar.hpp: Graff, Wave Motion in Elastic Solids, §2.1): the
// kinetic energy vanishes at a quarter period L / (2c), c = sqrt(E / rho), within 2 % (issue 32)
// for ELFORM 1 (each hourglass form) and ELFORM 2, on a regular and on a jittered mesh; the energy
// balance holds to 1 % over a period at TSSFAC 0.9; the result does not depend on the thread count
// (bitwise).
#include <gtest/gtest.h>


#include "spall/core/log.hpp"
#include "support/spg_bar.hpp"

using namespace spall;
using test_support::first_minimum;

namespace {

test_support::SpgBlock fem_bar(int elform, int ihq, Real jitter) {
  auto b = test_support::spg_bar(20);
  b.jitter = jitter;
  b.fem = test_support::FiniteElements{elform, {}};
  if (ihq > 0) {
    model::Hourglass hourglass;
    hourglass.ihq = ihq;
    b.fem->hourglass = hourglass;
  }
  return b;
}

}  // namespace

TEST(FemElasticBar, QuarterPeriodMatchesBarSpeed) {
  log::set_quiet(true);
  struct Variant {
    int elform, ihq;
    Real jitter;
  };
  for (const Variant v : {Variant{1, 0, 0.0}, Variant{1, 1, 0.0}, Variant{1, 2, 0.15}, Variant{1, 4, 0.15},
                          Variant{2, 0, 0.0}, Variant{2, 0, 0.15}}) {
    const auto b = fem_bar(v.elform, v.ihq, v.jitter);
    const Real quarter = test_support::bar_quarter_period(b);
    const auto run = test_support::run_spg_bar(b, 1.5 * quarter);
    const Real error = (first_minimum(run.time, run.kinetic) - quarter) / quarter;
    std::printf("ELFORM %d IHQ %d jitter %.2f: quarter period error %+.3f %%, %lld steps\n", v.elform, v.ihq,
                v.jitter, 100 * error, run.summary.steps);
    EXPECT_LT(std::abs(error), 0.02);
    EXPECT_LT(*std::min_element(run.kinetic.begin(), run.kinetic.end()), 0.02 * run.kinetic.front());
  }
}

TEST(FemElasticBar, EnergyBalanceOverOnePeriodAtTssfac09) {
  log::set_quiet(true);
  for (int elform : {1, 2}) {
    const auto b = fem_bar(elform, 0, 0.15);
    const Real period = 4 * test_support::bar_quarter_period(b);
    const auto run = test_support::run_spg_bar(b, period, 0.9);
    const auto& e = run.summary.energies;
    std::printf("ELFORM %d after one period: kinetic %.6e, internal %.6e, hourglass %.3e, ratio %.6f\n", elform,
                e.kinetic(), e.internal(), e.value(discretization::EnergyLedger::hourglass_energy), e.ratio());
    EXPECT_NEAR(e.ratio(), 1.0, 0.01);
    EXPECT_GT(e.kinetic(), 0.95 * e.initial_total());
  }
}

TEST(FemElasticBar, ResultsDoNotDependOnTheThreadCount) {
  log::set_quiet(true);
  // 120 x 8 x 8 elements in 8 colours of 960: above the loops' serial threshold.
  for (int elform : {1, 2}) {
    auto b = fem_bar(elform, elform == 1 ? 4 : 0, 0.15);
    b.elements = {120, 8, 8};
    const Real end = 0.3 * test_support::bar_quarter_period(b);
    const auto one = test_support::bar_nodes_after(b, end, 1);
    const auto two = test_support::bar_nodes_after(b, end, 2);
    ASSERT_EQ(one.x.size(), two.x.size());
    for (std::size_t i = 0; i < one.x.size(); ++i) {
      ASSERT_EQ(one.x[i], two.x[i]) << "ELFORM " << elform << " node " << one.id[i];
      ASSERT_EQ(one.v[i], two.v[i]) << "ELFORM " << elform << " node " << one.id[i];
    }
  }
}
