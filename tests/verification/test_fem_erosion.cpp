// Element erosion (issue 32; fem-contact.md §1.10-1.12, §2.11): a steel bar pulled apart from its
// middle (the halves set moving apart at 40 m/s) loses exactly the mass of the elements it
// deletes, reports it (the ledger's eroded_mass, glstat's column), keeps its energy balance with
// the eroded kinetic and internal energy booked, and leaves no NaN and no inverted element:
// - *MAT_PLASTIC_KINEMATIC with *MAT_ADD_EROSION EFFEPS 0.1 (effective strain);
// - *MAT_PLASTIC_KINEMATIC with FS 0.1 (its own failure strain, no *MAT_ADD_EROSION);
// - *MAT_JOHNSON_COOK with damage (D1 0.1, EROD 0): deleted when the damage reaches 1.
// And *CONTROL_TIMESTEP ERODE: a soft cube smashed into a rigid wall at 2 km/s stops the run when the
// step falls below DTMIN x dt0, and with ERODE 1 loses the elements instead and runs to the end.
#include <gtest/gtest.h>

#include <cmath>

#include "spall/core/error.hpp"
#include "spall/core/log.hpp"
#include "spall/fem/solid_elements.hpp"
#include "spall/solver/field_output.hpp"
#include "spall/solver/simulation.hpp"
#include "support/spg_block.hpp"

using namespace spall;
using Ledger = discretization::EnergyLedger;

namespace {

enum class Failure { add_erosion, failure_strain, johnson_cook_damage };

model::Model pulled_bar(Failure failure) {
  test_support::SpgBlock b;
  b.size = Vec3(0.1, 0.01, 0.01);
  b.elements = {40, 2, 2};
  b.end_time = 1.5e-4;
  b.fem = test_support::FiniteElements{1, {}};
  model::Model m = test_support::spg_block_model(b);
  if (failure == Failure::johnson_cook_damage) {
    model::MatJohnsonCook jc;  // a steel-like Johnson-Cook material
    jc.ro = 7850, jc.e = 200e9, jc.pr = 0.3, jc.g = jc.e / 2.6;
    jc.a = 350e6, jc.b = 275e6, jc.n = 0.36, jc.m = 1, jc.tm = 1800, jc.tr = 293, jc.cp = 477;
    jc.pc = -1e10, jc.spall = 1;
    jc.d1 = 0.1;
    m.materials[1].keyword = "*MAT_JOHNSON_COOK";
    m.materials[1].params = jc;
  } else {
    model::MatPlasticKinematic pk{7850, 200e9, 0.3, 350e6, 1e9, 1.0};
    if (failure == Failure::failure_strain) pk.fs = 0.1;
    m.materials[1].keyword = "*MAT_PLASTIC_KINEMATIC";
    m.materials[1].params = pk;
  }
  if (failure == Failure::add_erosion) {
    model::MatAddErosion erosion;
    erosion.mid = 1;
    erosion.effeps = 0.1;
    m.add_erosions[1] = erosion;
  }
  for (const auto& node : m.nodes)
    m.initial_velocity_nodes.push_back({node.id, Vec3(node.x.x() < 0.05 ? -40 : 40, 0, 0), Vec3::Zero(), 0, {}});
  return m;
}

}  // namespace

TEST(FemErosion, APulledBarLosesExactlyTheMassOfItsDeletedElements) {
  log::set_quiet(true);
  Index massless = 0;
  for (Failure failure : {Failure::add_erosion, Failure::failure_strain, Failure::johnson_cook_damage}) {
    solver::Problem p = solver::build_problem(pulled_bar(failure));
    Real mass0 = 0;
    for (Real m : p.nodes.mass) mass0 += m;
    const auto summary = solver::run(p, {});
    const auto& fem = dynamic_cast<const fem::SolidElements&>(*p.formulations.at(0));
    Real mass = 0;
    for (Real m : p.nodes.mass) mass += m;
    const Real element_mass = 7850 * 0.1 * 0.01 * 0.01 / 160;
    const Index eroded = fem.eroded_count();
    const auto& e = summary.energies;
    std::printf("failure %d: %d of %d elements deleted, mass %.6e + eroded %.6e = %.6e (start %.6e), eroded kinetic "
                "%.4g J, internal %.4g J, energy ratio %.5f\n", static_cast<int>(failure), eroded, fem.element_count(),
                mass, e.value(Ledger::eroded_mass), mass + e.value(Ledger::eroded_mass), mass0,
                e.value(Ledger::eroded_kinetic_energy), e.value(Ledger::eroded_internal_energy), e.ratio());
    EXPECT_GT(eroded, 0);
    EXPECT_LT(eroded, fem.element_count() / 4);  // a neck, not the whole bar
    EXPECT_NEAR(e.value(Ledger::eroded_mass), eroded * element_mass, 1e-12 * mass0);
    EXPECT_NEAR(mass + e.value(Ledger::eroded_mass), mass0, 1e-12 * mass0);
    EXPECT_GT(e.value(Ledger::eroded_kinetic_energy), 0);
    EXPECT_NEAR(e.ratio(), 1.0, 0.02);
    // The two halves separate: no NaN, every element left has its volume, and the ends move apart.
    for (Index i = 0; i < p.nodes.size(); ++i) {
      ASSERT_TRUE(p.nodes.x[i].allFinite());
      ASSERT_TRUE(p.nodes.v[i].allFinite());
    }
    discretization::FieldSet fields(p.nodes.size());
    fem.write_fields(fields, p.nodes);
    const auto& block = fields.cell_blocks().at(0);
    const discretization::Field* density = nullptr;
    const discretization::Field* flags = nullptr;
    for (const auto& f : block.fields) {
      if (f.name == "density") density = &f;
      if (f.name == "eroded") flags = &f;
    }
    ASSERT_TRUE(density && flags);
    const auto& rho = std::get<std::vector<double>>(density->values);
    const auto& deleted = std::get<std::vector<std::int64_t>>(flags->values);
    for (std::size_t k = 0; k < rho.size(); ++k)
      if (!deleted[k]) {
        ASSERT_TRUE(rho[k] > 0 && std::isfinite(rho[k])) << "element " << k;
      }
    // The field output keeps the nodes of deleted elements that lost all their mass (the cells,
    // flagged, still name them).
    const solver::FieldSnapshot snapshot = solver::snapshot_fields(p);
    for (Real m : p.nodes.mass) massless += !(m > 0);
    for (const auto& cells : snapshot.cell_blocks)
      for (Index node : cells.connectivity)
        ASSERT_TRUE(node >= 0 && node < static_cast<Index>(snapshot.points.size())) << "failure " << int(failure);
  }
  EXPECT_GT(massless, 0);  // some run left nodes without elements
}

namespace {

// A 1 cm cube of 4 x 4 x 4 elements of a weak steel (yield 100 MPa, no hardening) hitting a rigid
// wall at 2 km/s: it spreads into a pancake and its first layer is crushed. DTMIN 0.3.
model::Model smashed_cube(int erode) {
  test_support::SpgBlock b;
  b.size = Vec3(0.01, 0.01, 0.01);
  b.elements = {4, 4, 4};
  b.end_time = 6e-6;
  b.fem = test_support::FiniteElements{1, {}};
  model::Model m = test_support::spg_block_model(b);
  m.materials[1].keyword = "*MAT_PLASTIC_KINEMATIC";
  m.materials[1].params = model::MatPlasticKinematic{7850, 200e9, 0.3, 100e6, 0, 1.0};
  m.termination->dtmin = 0.3;
  m.timestep.erode = erode;
  for (const auto& node : m.nodes) m.initial_velocity_nodes.push_back({node.id, Vec3(0, 0, -2000), Vec3::Zero(), 0, {}});
  model::RigidWallPlanar wall;
  wall.head = Vec3(0, 0, 1);
  wall.keyword = "*RIGIDWALL_PLANAR";
  m.rigid_walls.push_back(wall);
  return m;
}

}  // namespace

TEST(FemErosion, ErodeDeletesElementsWhoseStepCollapses) {
  log::set_quiet(true);
  solver::Problem stopping = solver::build_problem(smashed_cube(0));
  try {
    const auto summary = solver::run(stopping, {});
    FAIL() << "the step should have fallen below DTMIN x dt0 (" << summary.steps << " steps)";
  } catch (const InstabilityError& e) {
    EXPECT_NE(std::string(e.what()).find("fell below DTMIN"), std::string::npos) << e.what();
  }
  solver::Problem eroding = solver::build_problem(smashed_cube(1));
  const auto summary = solver::run(eroding, {});
  const auto& fem = dynamic_cast<const fem::SolidElements&>(*eroding.formulations.at(0));
  std::printf("ERODE 1: %d of %d elements deleted, %lld steps to %.3g s, eroded mass %.4g kg\n", fem.eroded_count(),
              fem.element_count(), summary.steps, summary.end_time, summary.energies.value(Ledger::eroded_mass));
  EXPECT_GT(fem.eroded_count(), 0);
  EXPECT_NEAR(summary.end_time, 6e-6, 1e-12);
  EXPECT_GT(summary.energies.value(Ledger::eroded_mass), 0);
}
