#pragma once
// Weakly compressible SPH for liquids (Monaghan 1994, J. Comput. Phys. 110:399), seed 000 eqs. 4-6
// (m dv/dt = pressure force + viscous force + external force):
//   continuity      d rho_a/dt = sum_b m_b (v_a - v_b) . grad_a W_ab
//   Tait/Murnaghan  p = K0 [(rho / rho0)^gamma - 1],  K0 = rho0 c0^2 / gamma (or another EOS)
//   pressure        f_a = - sum_b m_a m_b (p_a / rho_a^2 + p_b / rho_b^2) grad_a W_ab
//   art. viscosity  f_a = - sum_b m_a m_b Pi_ab grad_a W_ab  (Monaghan 1992, with c_ab = c0)
//   laminar visc.   f_a = sum_b m_a m_b (mu_a + mu_b) / (rho_a rho_b)
//                             (x_ab . grad_a W_ab) / (r_ab^2 + 0.01 h^2) v_ab
//                   (Morris, Fox & Zhu 1997, J. Comput. Phys. 136:214)
//   external        gravity and other base accelerations come from the time loop (*LOAD_BODY)
// Every pair term is antisymmetric in a and b, so linear momentum is conserved to round-off.
//
// Walls: a particle whose three translations are held by SPCs is a dynamic boundary particle
// (Crespo, Gomez-Gesteira & Dalrymple 2007, CMC 5:173; DualSPHysics): it takes part in continuity
// and pressure like the fluid but does not move, and its density is kept >= rho0 so that it never
// pulls fluid in. Its continuity sums over the moving particles only (the walls around it rest,
// so their terms are zero).
//
// One pair pass per step, no stored neighbour list (memory: docs/THEORY.md):
// - The forces at step n need every neighbour's density at step n, which the same pass's
//   continuity sum only gives afterwards. So the pass uses densities predicted from the two last
//   rates, rho~^n = rho^{n-1} + dt (2 rho'^{n-1} - rho'^{n-2}); the rate it computes then corrects
//   rho^n = rho^{n-1} + dt rho'^n. For an acoustic mode of frequency w this predictor-corrector is
//   stable for w dt < 0.72 (and damps the highest modes slightly); the lagged update
//   rho^n = rho^{n-1} + dt rho'^{n-1} alone is unstable for every dt.
// - Particles are kept in cell order; the moving particles of a cell screen together the
//   particles of the cells that can reach their supports (cells of edge (support + skin) / 2, the
//   runs of the 5 x 5 x 5 block around their cell trimmed to their bounding box:
//   neighbors/trimmed_stencil.hpp), each pack of candidates tested against all of them, and each
//   interacts with those inside its support. Cells are rebuilt, and the particles re-sorted, when
//   the particles may have moved more than skin / 2 since the last rebuild: the bound is the sum
//   over steps of dt max |v|, so no reference positions are stored.
// - Positions and velocities are copied each step into single-precision records in cell order;
//   the pair terms are evaluated in single precision by one sequence of operations for every pair,
//   so the term of (a, b) is bitwise minus that of (b, a), and summed in double (the viscous
//   part alone, kept only to split the energy balance, in single precision).
#include <array>
#include <limits>
#include <optional>
#include <vector>

#include "spall/kernels/kernel.hpp"
#include "spall/materials/eos.hpp"
#include "spall/neighbors/cell_list.hpp"
#include "spall/core/parallel.hpp"
#include "spall/discretization/formulation.hpp"
#include "spall/discretization/particle_share.hpp"
#include "spall/discretization/reach_share.hpp"
#include "spall/sph/artificial_viscosity.hpp"

namespace spall::sph {

// A liquid: its rest density, a barotropic equation of state from the material library (Tait /
// Murnaghan for weakly compressible water; Grueneisen and the linear polynomial are evaluated at
// the fixed specific energy e0), a dynamic viscosity and a pressure cutoff.
struct FluidMaterial {
  Real density = 0;  // rho0
  materials::EquationOfState eos = materials::Murnaghan{};
  Real specific_energy = 0;    // e0 (per unit mass) at which the EOS is evaluated
  Real dynamic_viscosity = 0;  // mu (Morris laminar viscosity); 0 for none
  Real pressure_cutoff = -std::numeric_limits<Real>::infinity();  // p >= cutoff (MAT_NULL PC)

  // Tait / Murnaghan water, p = K0 [(rho / rho0)^gamma - 1] with K0 = rho0 c0^2 / gamma.
  static FluidMaterial tait(Real rho0, Real c0, Real gamma, Real mu);
  Real pressure(Real rho) const;
  // c = sqrt(K_s / rho), K_s the isentropic bulk modulus of the EOS (c^2 = dp/drho when the EOS
  // does not depend on e).
  Real sound_speed_at(Real rho) const;
  Real reference_sound_speed() const { return sound_speed_at(density); }  // c0
};

// What the pair pass reads of a particle, in one 32-byte record: its position relative to the
// cells' corner, its velocity, 1 / rho~ and p / rho~^2, single precision. A neighbour's eight
// numbers are one aligned load; the seam's float packs transpose sixteen records (eight with AVX2)
// into lanes, where gathering the eight numbers from eight arrays took eight gather instructions of
// about 28 cycles each on the hosts measured (docs/PERFORMANCE.md, session 12).
struct alignas(32) FluidRecord {
  float x, y, z;
  float vx, vy, vz;
  float inverse_density;
  float pressure_term;
};

struct FluidParameters {
  FluidMaterial material;
  Real smoothing_length = 0;  // LS-DYNA's h, one for every particle; the kernel support is 2h
  kernels::KernelKind kernel = kernels::KernelKind::cubic_spline;  // *SECTION_SPH SPHKERN
  ArtificialViscosity viscosity;
  Real skin = 0.1;  // cell edge = (1 + skin) * support
  // 3, or 2 for plane strain in x-y: every particle at one z, masses per unit thickness, the
  // two-dimensional kernel (LS-DYNA *CONTROL_SPH IDIM = 2).
  int dimension = 3;
};

class FluidFormulation final : public discretization::Formulation {
 public:
  // `particle_nodes`: the node of each particle; masses come from the node store. Under MPI every
  // rank constructs its own (collective), of every particle or of those on its block of the rows.
  FluidFormulation(const FluidParameters& parameters, const std::vector<Index>& particle_nodes,
                   const discretization::NodeStore& nodes);

  const char* name() const override { return "SPH fluid"; }
  void compute_forces(discretization::NodeStore& nodes, Real dt) override;
  Real stable_time_step(const discretization::NodeStore& nodes) const override;
  void book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                     std::span<const Vec3> v, Real dt) const override;
  // The compression energy of its own moving particles, m e(rho), e(rho) = integral_rho0^rho p(r) / r^2 dr
  // (a barotropic liquid: de = p drho / rho^2). The walls' densities change too, but they do no
  // work: their share is not the liquid's (nor any part's).
  void sum_parts(discretization::PartSummary& parts, const discretization::NodeStore& nodes) const override;
  void write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const override;
  // The power of the last internal forces at the node velocities v.
  discretization::InternalPower internal_power(std::span<const Vec3> v) const;
  Real max_wave_speed() const override;
  void share_state(discretization::NodeStore& nodes) override;
  bool halo_by_reach() const override { return true; }
  bool migrates() const override { return true; }
  // The wall particles (an SPC holds them in every direction) only lend their density to the pairs.
  bool forces_on_held_nodes() const override { return false; }
  void complete_state(discretization::NodeStore& nodes) override;
  void checkpoint(Archive& archive, const discretization::NodeStore& nodes) override;

  Index particle_count() const { return static_cast<Index>(node_.size()); }
  const FluidParameters& parameters() const { return parameters_; }
  // Bytes held by the formulation: its per-particle arrays and the cell list.
  std::size_t memory_bytes() const;
  // Number of particles inside the support of each particle (self excluded), in particle
  // order (node_of(a) is particle a's node), on the positions of the last pass.
  std::vector<Index> neighbour_counts() const;
  Index node_of(Index particle) const { return node_[particle]; }

 private:
  void rebuild_cells(const discretization::NodeStore& nodes);
  // Under MPI, dealt by region: the cells of this rank's particles and of those within reach of its
  // region, brought in from the ranks that hold them current, as the run that bins every particle
  // would make them; the particles migrate to their regions' ranks on the way, and the rank keeps
  // no other particle (rows of its own, NodeStore). After a restart file read into a block of the
  // rows (binned_), the particles bring their keys and the cells are those of the last rebuild.
  void rebuild_near_region(discretization::NodeStore& nodes);
  // Before the arrivals of a rebuild: only the particles within `near` (this rank's region grown by
  // the reach) stay, with their rows and those of the nodes it computes that carry none; `current`
  // follows the particles.
  void drop_beyond(discretization::NodeStore& nodes, const BoundingBox& near, std::vector<std::uint8_t>& current);
  // The rows of the particles `near` this rank's region (their ranks set by the regions) and of the
  // nodes it computes that carry none.
  void keep_rows_near(discretization::NodeStore& nodes, std::span<const Index> near);
  // The node store keeps the rows of `particles` and of the nodes this rank computes that carry
  // none, in row order; node_ follows (-1 for a particle not kept).
  void keep_rows_of(discretization::NodeStore& nodes, std::span<const Index> particles);
  // Every particle in the cells of the grid (lower, cell_size, along) again, from the keys their
  // ranks binned them at (a checkpoint read back).
  void make_cells_whole(const discretization::NodeStore& nodes, std::span<const neighbors::CellKey> key,
                        const Vec3& lower, Real cell_size, const std::array<std::int64_t, 3>& along);
  // The per-particle arrays put in `order` (order[k] the particle that goes to slot k), and the
  // moving bits and active cells that follow them.
  void take_cell_order(const discretization::NodeStore& nodes, std::span<const Index> order);
  // The grid's corner and rounding margin of the cells just built, and no travel since.
  void finish_build();
  template <class Chosen>
  std::vector<std::uint8_t> cells_near(Chosen&& chosen) const;
  // Under MPI: which of the other ranks' particles come in with the halo.
  void plan_halo(const discretization::NodeStore& nodes);
  // Under MPI, dealt in blocks: every rank's particles' positions, velocities and continuity state
  // in.
  void complete(discretization::NodeStore& nodes);
  void gather(const discretization::NodeStore& nodes, Real dt);
  // The pair pass with the kernel of the parameters.
  void pair_pass(discretization::NodeStore& nodes, Real dt);
  template <typename Kernel>
  void pair_pass(discretization::NodeStore& nodes, Real dt);
  // Calls visit(a, ranges, range count) for every particle a, in an `omp for` over the cells: the
  // ranges hold every particle within the support of a. For the pair pass (pair_pass), the
  // moving particles of a cell come together instead, to visit(cluster, count, ranges, range
  // count) with the runs of the bounding box of the cell's particles, which hold every particle
  // within the support of any of them, and the walls of the cell in groups of up to wall_group
  // (fluid.cpp) to visit_walls(walls, count, spans, span count), the same runs cut to their
  // moving spans (none in a cell without moving particles around).
  template <bool pair_pass, typename Visit, typename VisitWalls>
  void for_each_particle_candidates(const parallel::Team& team, Visit&& visit, VisitWalls&& visit_walls) const;

  FluidParameters parameters_;
  Real support_ = 0;  // H = 2h
  Real courant_factor_ = 0;  // of the kernel (fluid.cpp)

  // Per particle, in cell order (structure of arrays).
  std::vector<Index> node_;
  std::vector<float> mass_;
  // Every particle's mass when they are all equal (the usual lattice of one spacing), else 0: the
  // vector pair paths then broadcast it instead of gathering the same number.
  float uniform_mass_ = 0;
  std::vector<Real> density_;        // rho^n (corrected)
  std::vector<float> rate_;           // rho'^n
  std::vector<float> previous_rate_;  // rho'^{n-1}
  // Per step: what the pair pass reads (padded: see simd_width in fluid.cpp).
  std::vector<FluidRecord> record_;
  // The last internal forces, for internal_power: pressure part and viscous part.
  std::vector<float> pressure_force_;  // 3 per particle
  std::vector<float> viscous_force_;   // 3 per particle
  // One bit a particle, in cell order: 1 moving, 0 a wall. The walls' screen keeps only moving
  // neighbours.
  std::vector<std::uint8_t> moving_;

  neighbors::CellList cells_;
  // Per cell: 1 when a moving (non-wall) particle is in the 5 x 5 x 5 cells around it. Wall
  // particles of other cells have no moving particle in their support until the next rebuild,
  // so their continuity rate is exactly zero and they are skipped.
  std::vector<std::uint8_t> active_cell_;
  // Under MPI, per cell: 1 when a particle this rank computes is in the 5 x 5 x 5 cells around it,
  // so that its pair pass reads the cell; marked for the cells and the node partition of
  // near_owned_partition_ (-1: not yet). Empty in one process (every cell).
  std::vector<std::uint8_t> near_owned_cell_;
  long long near_owned_partition_ = -1;
  // The halo by reach (share_state): the other ranks' particles in the cells near this rank's.
  discretization::ReachShare halo_;
  // Whether every particle's position, velocity and continuity state is current here (dealt in
  // blocks): from the set-up, a checkpoint or complete() until the next halo by reach.
  bool complete_ = true;
  Vec3 origin_ = Vec3::Zero();  // the cells' grid corner
  Real rounding_margin_ = 0;    // widens the search for the single-precision positions
  bool cells_built_ = false;
  // Read from a restart file into a block of the rows (the set-up in blocks): each particle's key
  // in the grid of the last rebuild (per particle, following them), from which the cells of the
  // particles near this rank's region are built at the first step (rebuild_near_region).
  struct BinnedAt {
    std::vector<neighbors::CellKey> key;
    Vec3 lower;
    Real cell_size = 0;
    std::array<std::int64_t, 3> along{};
  };
  std::optional<BinnedAt> binned_;
  bool first_pass_ = true;
  Real travelled_ = 0;  // bound on any particle's displacement since the cells were built
  // From the last pass, for the stable step and the runaway check.
  Real max_speed_ = 0;
  Real max_sound_speed_ = 0;
  Real max_acceleration_ = 0;
  discretization::ParticleShare share_;  // under MPI: the particles this rank computes, theirs to all
  bool owns(Index particle) const { return share_.owns(node_[particle]); }
  Real max_mu_ = 0;  // largest |mu_ab| of an approaching pair (Monaghan's viscosity)
};

}  // namespace spall::sph
