// A block of SPH particles strikes a free SPG plate through penalty contact
// (*CONTACT_AUTOMATIC_NODES_TO_SURFACE: the particles are the slave nodes, the exterior faces of
// the plate's hexahedra the master segments; issue 33, fem-contact.md §2.6-2.8). Nothing holds
// either body and no load acts, so:
//  - the total momentum of block and plate keeps its initial value (Newton's third law: the
//    contact pushes a slave node and its segment's corners with equal and opposite forces, and
//    neither body's internal forces have a resultant); issue 33's tolerance, 0.5 % of it;
//  - no particle goes into the plate further than the penalty spring lets it: g = f / k, which for
//    the block landing on its N contact springs is at most about v0 sqrt(M / (N k)) (a rigid mass
//    M on N springs stores its kinetic energy in them: 1/2 M v0^2 = N 1/2 k g^2), and no particle
//    stays inside once the block has bounced off;
//  - the energy balance closes: the springs' work and the damping VDC's dissipation are booked as
//    contact_energy, friction's as friction_energy (see the test for the tolerances).
#include <gtest/gtest.h>
#include <omp.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <optional>
#include <unordered_map>

#include "spall/core/log.hpp"
#include "spall/io/keyword/reader.hpp"
#include "spall/solver/simulation.hpp"
#include "support/contact_decks.hpp"

using namespace spall;
using namespace spall::test_support;

namespace {

constexpr Real density = 1000, young = 1e7, poisson = 0.3;  // soft bodies: a long stable step
constexpr Real speed = 2.0;             // m/s, down onto the plate
constexpr Real sideways = 0.5;          // m/s along x: friction carries momentum across too
constexpr Real mu = 0.2, vdc = 20;      // Coulomb coefficient; normal damping, % of critical
constexpr Real element = 0.01;          // the plate's element size (m)
constexpr int plate_cells[3] = {12, 12, 3};
constexpr Real spacing = 0.0025;        // the block's particle spacing, a quarter of the element
constexpr int edge = 16;                // particles along each edge of the block: 4096 of them, so
                                        // that the contact's search and response loops run threaded
constexpr Real gap = 0.001;             // between the lowest particles and the plate at the start
constexpr Real end_time = 4e-3;         // impact at 0.5 ms; the block has left the plate by 2.4 ms
constexpr Id plate_first_node = 100001;

// The plate (part 2): 0.12 x 0.12 x 0.03 m of SPG hexahedra, its top at z = 0, centred on the z
// axis. The block (part 1), 0.04 m across, above its middle, off the axis by a fraction of an
// element so that its particles land on faces, edges and corners of the segments alike.
std::string impact_deck() {
  std::string deck = "*KEYWORD\n*CONTROL_TERMINATION\n" + row({number(end_time)}) + "*DATABASE_GLSTAT\n" +
                     row({number(end_time / 200)});
  deck += deformable_part(Body::sph, 1, density, young, poisson);
  const Real half = 0.5 * spacing * (edge - 1);
  deck += sph_lattice(1, Vec3(0.0031 - half, 0.0017 - half, gap), spacing, {edge, edge, edge}, density, 1);
  deck += deformable_part(Body::spg, 2, density, young, poisson);
  const Vec3 size = element * Vec3(plate_cells[0], plate_cells[1], plate_cells[2]);
  deck += hex_box(2, Vec3(-0.5 * size.x(), -0.5 * size.y(), -size.z()), size,
                  {plate_cells[0], plate_cells[1], plate_cells[2]}, plate_first_node, 100001);
  deck += "*CONTACT_AUTOMATIC_NODES_TO_SURFACE_ID\n" + row({"1"}) + row({"1", "2", "3", "3"}) +
          row({number(mu), number(mu), "0.0", "0.0", number(vdc)}) + row({});
  deck += "*INITIAL_VELOCITY_GENERATION\n" + row({"1", "2", "0.0", number(sideways), "0.0", number(-speed)}) + row({});
  return deck + "*END\n";
}

// The plate's top surface as the contact defines it: each top face of the top layer of hexahedra
// cut into the four triangles its edges make with its centre (segment.hpp).
struct TopSurface {
  std::vector<std::array<Index, 4>> faces;  // node-store indices, counter-clockwise seen from +z

  Real highest(const discretization::NodeStore& nodes) const {
    Real z = -1e30;
    for (const auto& f : faces)
      for (Index i : f) z = std::max(z, nodes.x[i].z());
    return z;
  }

  // How far below the surface p lies, along the vertical through it (> 0: inside the plate);
  // nullopt when no face lies above or below it. A vertical ray rather than the contact's own
  // closest point: it shares no code with the contact, and a particle that went through the plate
  // would count by how far it went.
  std::optional<Real> depth(const Vec3& p, const discretization::NodeStore& nodes) const {
    const auto cross = [](const Vec3& u, const Vec3& v, const Vec3& w) {  // twice the xy area of uvw
      return (v.x() - u.x()) * (w.y() - u.y()) - (v.y() - u.y()) * (w.x() - u.x());
    };
    for (const auto& f : faces) {
      const Vec3 centre = 0.25 * (nodes.x[f[0]] + nodes.x[f[1]] + nodes.x[f[2]] + nodes.x[f[3]]);
      for (int k = 0; k < 4; ++k) {
        const Vec3& a = nodes.x[f[k]];
        const Vec3& b = nodes.x[f[(k + 1) % 4]];
        const Real area = cross(a, b, centre);
        const Real wa = cross(p, b, centre) / area, wb = cross(a, p, centre) / area, wc = 1 - wa - wb;
        if (wa >= 0 && wb >= 0 && wc >= 0) return wa * a.z() + wb * b.z() + wc * centre.z() - p.z();
      }
    }
    return std::nullopt;
  }
};

TopSurface top_surface(const discretization::NodeStore& nodes) {
  std::unordered_map<Id, Index> index;
  for (Index i = 0; i < nodes.size(); ++i) index[nodes.id[i]] = i;
  const auto node = [&](int i, int j) {  // hex_box's numbering, top layer k = plate_cells[2]
    return index.at(plate_first_node + i + (plate_cells[0] + 1) * (j + (plate_cells[1] + 1) * plate_cells[2]));
  };
  TopSurface s;
  for (int j = 0; j < plate_cells[1]; ++j)
    for (int i = 0; i < plate_cells[0]; ++i)
      s.faces.push_back({node(i, j), node(i + 1, j), node(i + 1, j + 1), node(i, j + 1)});
  return s;
}

struct Impact {
  Vec3 p0 = Vec3::Zero();           // initial total momentum
  Real worst_momentum = 0;          // largest |P - P0| at any step
  Vec3 block_p = Vec3::Zero(), plate_p = Vec3::Zero();  // at the end
  Real deepest = -1e30;             // largest depth of a particle below the top surface, any step
  Real mean_at_deepest = 0;         // the mean depth of the particles inside at that step
  Real deepest_end = -1e30;         // the largest depth at the end (< 0: the smallest clearance)
  Real worst_ratio = 0;             // largest |ledger ratio - 1| at any GLSTAT output
  Real worst_half_step = 0;         // the same for the balance with v^{n+1/2} (see the test)
  Real largest_lag = 0;             // largest |KE(v^{n+1/2}) - KE(v^n)| / E0
  Real contact_energy = 0, friction_energy = 0, kinetic0 = 0;
  Index most_touching = 0;
  long long steps = 0;
  double seconds = 0;
  std::vector<Vec3> x, v;           // at the end
};

Impact impact(int threads) {
  log::set_quiet(true);
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  test::DeckFolder folder;
  const model::Model model = io::keyword::read_deck(folder.write("impact.k", impact_deck()));
  io::keyword::validate(model);
  solver::Problem problem = solver::build_problem(model);
  const auto& nodes = problem.nodes;
  const TopSurface top = top_surface(nodes);
  std::vector<Index> particles;
  for (Index i = 0; i < nodes.size(); ++i)
    if (problem.nodes.part[i] == 1) particles.push_back(i);

  const auto momentum = [&](int part) {  // part 0: every node
    Vec3 p = Vec3::Zero();
    for (Index i = 0; i < nodes.size(); ++i)
      if (part == 0 || problem.nodes.part[i] == part) p += nodes.mass[i] * nodes.v[i];
    return p;
  };
  // The largest depth of a particle below the surface, and the mean depth of those inside; only
  // particles below the highest top node can be inside, unless `all`.
  const auto depths = [&](bool all) {
    Real deepest = -1e30, sum = 0;
    int inside = 0;
    const Real highest = top.highest(nodes);
    for (Index i : particles) {
      if (!all && nodes.x[i].z() > highest) continue;
      if (const auto d = top.depth(nodes.x[i], nodes)) {
        deepest = std::max(deepest, *d);
        if (*d > 0) sum += *d, ++inside;
      }
    }
    return std::pair{deepest, inside > 0 ? sum / inside : Real(0)};
  };

  Impact r;
  r.p0 = momentum(0);
  solver::Observer observer;
  // Every step, after the velocity update: x^n, v^{n+1/2}.
  observer.on_step = [&](const solver::StepInfo& step) {
    r.steps = step.step;
    r.worst_momentum = std::max(r.worst_momentum, (momentum(0) - r.p0).norm());
    const auto [deepest, mean] = depths(false);
    if (deepest > r.deepest) r.deepest = deepest, r.mean_at_deepest = mean;
    for (const auto& c : problem.contacts) r.most_touching = std::max(r.most_touching, c.touching());
  };
  observer.on_history = [&](const solver::StepInfo& step, const discretization::EnergyLedger& e) {
    if (step.step == 0) r.kinetic0 = e.kinetic();
    Real kinetic_half = 0;  // nodes.v is v^{n+1/2} here
    for (Index i = 0; i < nodes.size(); ++i) kinetic_half += 0.5 * nodes.mass[i] * nodes.v[i].squaredNorm();
    r.worst_ratio = std::max(r.worst_ratio, std::abs(e.ratio() - 1));
    r.worst_half_step =
        std::max(r.worst_half_step, std::abs((e.total() - e.kinetic() + kinetic_half) / e.initial_total() - 1));
    r.largest_lag = std::max(r.largest_lag, std::abs(kinetic_half - e.kinetic()) / e.initial_total());
    r.contact_energy = e.value(contact::PenaltyContact::contact_energy);
    r.friction_energy = e.value(contact::PenaltyContact::friction_energy);
  };
  const auto start = std::chrono::steady_clock::now();
  solver::run(problem, observer);
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  omp_set_num_threads(before);
  r.deepest_end = depths(true).first;
  r.block_p = momentum(1);
  r.plate_p = momentum(2);
  r.x = nodes.x;
  r.v = nodes.v;
  return r;
}

const Impact& on_two_threads() {
  static const Impact r = impact(2);
  return r;
}

TEST(ContactImpact, SphBlockOnFreeSpgPlate) {
  const Impact& r = on_two_threads();
  const Real n = edge;
  const Real block_mass = density * std::pow(spacing, 3) * n * n * n;
  // The penalty stiffness of a particle, k = SLSFAC K V^(1/3) (SLSFAC 0.1, V = spacing^3); the
  // segments' SLSFAC K A^2 / V is four times stiffer here, and PENOPT 1 takes the smaller
  // (fem-contact.md §2.6, docs/THEORY.md §12).
  const Real bulk = young / (3 * (1 - 2 * poisson));
  const Real k = 0.1 * bulk * spacing;
  // The block as a rigid mass on its n^2 lowest particles' springs, on a plate that stays put and
  // without damping: 1/2 M v0^2 = n^2 1/2 k g^2. 0.69 mm: 0.28 of the particle spacing, 0.07 of the
  // element, 0.17 of the release depth (0.4 x the element's thickness V / A = 4 mm). It is the
  // depth of a face pressed evenly; the block's own give and the plate's recoil take some of the
  // energy (the mean depth of the particles inside stays near half of it), while its edges go
  // deeper than its middle, the leading edge most (friction at its foot tips it forward). So the
  // deepest particle, not the mean, is held to it: no particle sinks further than the whole block
  // would on its springs.
  const Real penalty_depth = speed * std::sqrt(block_mass / (n * n * k));
  std::printf("%lld steps in %.2f s; at most %ld particles touching\n", r.steps, r.seconds,
              static_cast<long>(r.most_touching));
  std::printf("momentum: P0 (%.6g %.6g %.6g), worst |P - P0| %.3e (%.3e of |P0|); at the end block (%.5g %.5g %.5g), "
              "plate (%.5g %.5g %.5g)\n",
              r.p0.x(), r.p0.y(), r.p0.z(), r.worst_momentum, r.worst_momentum / r.p0.norm(), r.block_p.x(),
              r.block_p.y(), r.block_p.z(), r.plate_p.x(), r.plate_p.y(), r.plate_p.z());
  std::printf("deepest particle %.4g mm (%.3f spacing; mean of those inside then %.4g mm; penalty estimate %.4g mm); "
              "at the end %.4g mm\n",
              1e3 * r.deepest, r.deepest / spacing, 1e3 * r.mean_at_deepest, 1e3 * penalty_depth, 1e3 * r.deepest_end);
  std::printf("energy: worst |ratio - 1| %.3e (half-step lag up to %.3e), with v^{n+1/2} %.3e; contact %.4g J, "
              "friction %.4g J of kinetic %.4g J\n",
              r.worst_ratio, r.largest_lag, r.worst_half_step, r.contact_energy, r.friction_energy, r.kinetic0);

  // The block struck the plate: all of its lowest layer touched, and it bounced back up.
  EXPECT_EQ(r.most_touching, edge * edge);
  EXPECT_GT(r.block_p.z(), 0.0);
  // Momentum: issue 33's 0.5 % of the initial momentum, at every step.
  EXPECT_LT(r.worst_momentum, 0.005 * r.p0.norm());
  // Penetration: never deeper than the penalty springs allow, and nothing inside at the end (a
  // hundredth of the spacing: the block has left the plate).
  EXPECT_GT(r.deepest, 0.0);
  EXPECT_LT(r.deepest, penalty_depth);
  EXPECT_LT(r.deepest_end, 0.01 * spacing);
  // Energy, two ways. The ledger's ratio compares the energies at t^n with the work booked through
  // t^{n+1/2} (each step's work dt F.v^n covers the step from t^{n-1/2} to t^{n+1/2}), so while
  // forces work fast it is off by dt/2 x their power, |KE(v^{n+1/2}) - KE(v^n)|: 1 % as the block
  // lands (printed as the half-step lag), so 2 % allows for that lag and no more. With
  // the kinetic energy at v^{n+1/2} instead the balance is the central difference's own identity,
  // 1/2 m (v^{n+1/2})^2 - 1/2 m (v^{n-1/2})^2 = dt F.v^n for equal steps; the step changes by under
  // 1 % here, and the last step is cut short to land on the end time: what those leave is
  // second order, 1e-4 of the energy (m dv^2 of one step), so 0.1 %.
  EXPECT_LT(r.worst_ratio, 0.02);
  EXPECT_LT(r.worst_half_step, 1e-3);
  EXPECT_GT(r.contact_energy, 0.0);   // the damping took some
  EXPECT_GT(r.friction_energy, 0.0);  // and so did friction, sliding the block along x
}

TEST(ContactImpact, OneAndTwoThreadsGiveTheSameBits) {
  const Impact& two = on_two_threads();
  const Impact one = impact(1);
  ASSERT_EQ(one.x.size(), two.x.size());
  for (std::size_t i = 0; i < one.x.size(); ++i) {
    ASSERT_EQ(one.x[i], two.x[i]) << "node " << i;
    ASSERT_EQ(one.v[i], two.v[i]) << "node " << i;
  }
  EXPECT_EQ(one.contact_energy, two.contact_energy);
  EXPECT_EQ(one.friction_energy, two.friction_energy);
}

}  // namespace
