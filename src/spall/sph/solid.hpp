#pragma once
// Updated-Lagrangian SPH for solids (Libersky & Petschek 1990; Gray, Monaghan & Swift 2001), the
// base of seed 000 §3-4:
//   continuity       d rho_a/dt = sum_b m_b (v_a - v_b) . grad_a W_ab
//   velocity grad.   L_a = sum_b (m_b / rho_b) (v_b - v_a) (x) grad_a W_ab
//   stress           S rotated by the Jaumann rate (W S - S W) dt, then the material's update
//                    (Hooke, radial return, hardening, heating, damage; src/spall/materials) and
//                    its EOS pressure p(rho, e)
//   momentum         m_a dv_a/dt = sum_b V_a V_b (sigma_a B_a^T + sigma_b B_b^T) grad_a W_ab
//                                  - sum_b m_a m_b (Pi_ab I - R_ab f_ab^n) grad_a W_ab
//                    (seed 000 eqs. 7-8 in a symmetric form that conserves linear momentum)
//   energy           de_a/dt = sigma_a : L_a / rho_a + 1/2 sum_b m_b Pi_ab v_ab . grad_a W_ab
//   correction       B_a = (sum_b V_b (x_b - x_a) (x) grad_a W_ab)^-1 (Randles & Libersky 1996),
//                    applied to L and, by duality, to the force; B = I when switched off
//   viscosity        Pi_ab = (-alpha c_ab mu_ab + beta mu_ab^2) / rho_ab when v_ab . x_ab < 0 (Monaghan),
//                    with rho and c of the step start (evaluated in the rates pass, which holds v_ab
//                    and the pair geometry already)
//   artif. stress    R_ab = R_a + R_b, R_a = -eps sigma_tension / rho_a^2 in the principal frame,
//                    f_ab = W(r_ab) / W(dp) (Monaghan 2000; Gray, Monaghan & Swift 2001)
//   colour field     c_a = sum_b V_b W_ab (self included), n_a = sum_b V_b grad_a W_ab (seed 000
//                    eqs. 9-10); surface: fewer neighbours than a fraction of a full support and
//                    |n| h above a threshold; inner layers: the particles right behind them;
//                    treated parts pass only -p I of those particles to the pair force (seed 000 §4)
//   smoothing length h_a = h0_a (rho_0 / rho_a)^(1/d) within [HMIN h0, HMAX h0] (LS-DYNA's
//                    dh/dt = h div(v) / d, integrated), updated after both pair passes of a step,
//                    which thus share one kernel
// One SPH formulation owns every SPH part; particles of different parts interact through the
// kernel, with each particle's own material.
#include <cstdint>
#include <limits>
#include <optional>
#include <span>
#include <vector>

#include "spall/core/range_array.hpp"
#include "spall/kernels/kernel.hpp"
#include "spall/materials/material.hpp"
#include "spall/neighbors/verlet_list.hpp"
#include "spall/discretization/formulation.hpp"
#include "spall/discretization/particle_share.hpp"
#include "spall/discretization/reach_share.hpp"
#include "spall/sph/artificial_viscosity.hpp"
#include "spall/sph/force_blocks.hpp"

namespace spall::sph {

struct ArtificialStress {
  bool enabled = false;
  Real epsilon = 0.3;
  Real exponent = 4;
};

// Colour-field categorization of one part (*SPALL_SPH_COLOUR_FIELD).
struct ColourField {
  bool enabled = false;
  bool treat = false;             // surface and inner layers export only their pressure
  Real neighbour_fraction = 0.8;  // surface: count < fraction x full-support count ...
  Real normal_threshold = 0.3;    // ... and |n| h > threshold
  int layers = 1;
  int interval = 1;               // steps between categorizations
  // TFORM 2: seed 000 read literally, treated particles export -pI at once and keep integrating
  // their deviator. TFORM 1 (default): the exported deviator relaxes to zero in `relaxation`
  // wave-transit times h / c and the energy follows the exported stress (docs/THEORY.md §3).
  bool literal = false;
  Real relaxation = 100;
};

// Particle categories as output in the `category` field.
enum class Category : std::uint8_t { interior = 0, inner_layer = 1, surface = 2 };

// Residual-stress detection (seed 000; *SPALL_RESIDUAL_STRESS): a particle carries residual
// stress when its von Mises stress exceeds a fraction of its quasi-static yield stress while its
// effective strain rate is near zero.
struct ResidualStressCriterion {
  Real yield_fraction = 0.5;
  Real strain_rate = 0;  // "near zero" below this; 0: below 1 % of the largest rate in the body
};

// Von Mises statistics of one part and category (category -1: all of the part's particles).
struct ResidualStressRow {
  Id part = 0;
  int category = -1;
  Index particles = 0;
  Real von_mises_max = 0, von_mises_mean = 0, von_mises_p95 = 0;
  Index residual = 0;  // particles meeting the criterion
};

// How the stable step is found (*SPALL_SPH_TIMESTEP RULE).
enum class TimeStepRule : std::uint8_t {
  corrected,  // h / (c s + |v|), s >= 1 from the row sums of the (corrected) gradient operator
  plain,      // h / (c + |v|), LS-DYNA's (and seed 000's setting)
};

// How the SPH equations are discretized (*CONTROL_SPH, *SECTION_SPH, Spall's keywords).
struct SolidOptions {
  kernels::KernelKind kernel = kernels::KernelKind::cubic_spline;
  int dimension = 3;               // 2: plane strain in x-y (all particles at one z)
  bool gradient_correction = true;  // *CONTROL_SPH FORM 1 (0: plain SPH)
  ArtificialViscosity viscosity;
  ArtificialStress artificial_stress;
  TimeStepRule time_step_rule = TimeStepRule::corrected;
  Real start_time = 0;             // *CONTROL_SPH START: no SPH forces before
  Real death_time = 1e20;          // *CONTROL_SPH DT: no SPH forces after
  std::vector<ColourField> colour_field;  // per material-table entry (one per part); empty: off
  std::vector<Id> part_ids;               // the deck's part ID of each material-table entry
};

// One SPH particle as the solver sets it up.
struct ParticleSetup {
  Index node = 0;
  Index material = 0;         // index into the material table
  Real smoothing_length = 0;  // initial h0 (LS-DYNA's); the kernel support is 2h
  Real spacing = 0;           // initial particle spacing (m / rho)^(1/d)
  // h stays within [HMIN h0, HMAX h0] (*SECTION_SPH), one pair of factors per material-table entry.
  Real h_min_factor = 0, h_max_factor = 0;
};

// One particle as the pair loops read it (SolidFormulation::record_): one 256-bit row.
struct alignas(32) PairRecord {
  float x, y, z, h, vx, vy, vz, volume;
};
// What the viscosity reads of each neighbour besides its PairRecord (SolidFormulation::
// viscosity_record_): sound speed and density of the step start, one 64-bit row.
struct alignas(8) ViscosityRecord {
  float sound_speed, density;
};
// One particle as the force pass reads it (SolidFormulation::stress_): P = sigma B^T
// column-major, P(i, j) = P[i + 3 j], and the volume after the state update.
struct alignas(16) StressRecord {
  float P[9];
  float volume;
  float unused[2];
};
// The same for plain SPH (no correction, B = I): P = sigma is symmetric, and its six components
// xx, yy, zz, xy, yz, zx and the volume fit one 256-bit row (SolidFormulation::plain_stress_).
struct alignas(32) PlainStressRecord {
  float sigma[6];
  float volume;
  float unused;
};

class SolidFormulation final : public discretization::Formulation {
 public:
  // `particles` are every particle, or with `across` (the set-up in blocks under MPI) this rank's
  // block of them: those on its block of the nodes, each named by its node's place in the node order.
  SolidFormulation(std::vector<materials::Material> materials,
                   const std::vector<ParticleSetup>& particles, SolidOptions options,
                   const discretization::NodeStore& nodes, const parallel::Communicator* across = nullptr);

  const char* name() const override { return "SPH"; }
  void compute_forces(discretization::NodeStore& nodes, Real dt) override;
  Real stable_time_step(const discretization::NodeStore& nodes) const override;
  void book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                     std::span<const Vec3> v, Real dt) const override;
  void write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const override;
  // The power of the last internal forces at the node velocities v (one a row of `nodes`).
  discretization::InternalPower internal_power(const discretization::NodeStore& nodes, std::span<const Vec3> v) const;
  // The largest sound speed of the set-up's state.
  Real max_wave_speed() const override;
  void complete_state(discretization::NodeStore& nodes) override;
  // The fields and the residual-stress report read a rank's own particles alone.
  void complete_for_output(discretization::NodeStore& /*nodes*/) override {}
  // Under MPI with velocities by reach (NodeStore::velocities_by_reach): v^{n+1/2} of the other
  // ranks' particles this rank's rows read (reach_), from their ranks.
  void share_state(discretization::NodeStore& nodes) override;
  bool halo_by_reach() const override { return true; }
  // With NodeStore::window_by_reads it holds the window of its own block and the nodes of the
  // particles it reads (hold_nodes): at each list build, each new deal and where every row is read.
  bool holds_window() const override { return true; }
  // The nodes of the particles whose read state this rank holds (read_state_held), which hold those
  // its rows read; every node until the first list says which.
  parallel::Range rows_read(const discretization::NodeStore& nodes) const override;
  void checkpoint(Archive& archive, const discretization::NodeStore& nodes) override;

  Index particle_count() const { return static_cast<Index>(node_.size()); }
  // Bytes held by the formulation's arrays and its neighbour list.
  std::size_t memory_bytes() const;
  const neighbors::NeighborList& neighbor_list() const { return verlet_.list(); }
  long long neighbor_list_builds() const { return verlet_.builds(); }
  // Whether the last force pass took each pair once (blocks of particles, compute_pair_forces)
  // rather than every row whole.
  bool pairs_taken_once() const { return force_blocks_ > 0; }
  // Categories of the last categorization (particle order), empty when no part asks for them.
  // Of this rank's own particles (all on one process).
  const RangeArray<Category>& categories() const { return category_; }
  Index node_of(Index particle) const { return node_[particle]; }
  // The particles whose read state (what the rows read of their neighbours: records, h, density,
  // volume, sound speed, stress records, forces) this rank holds: every particle on one process;
  // under MPI from the first particle its rows read to the last (read_stretch).
  neighbors::ParticleRange read_state_held() const { return {record_.held_begin(), record_.held_end()}; }
  // Per part and category, in part-table order (residual_stress.cpp).
  std::vector<ResidualStressRow> residual_stress(const ResidualStressCriterion& criterion) const;

 private:
  void gather_kinematics(const discretization::NodeStore& nodes);
  // Particle a's node's row in `nodes` (the nodes are named by their places: NodeStore::node_row).
  Index row(const discretization::NodeStore& nodes, Index a) const { return nodes.node_row(node_[a]); }
  // With NodeStore::window_by_reads: the window of this rank's own block of the nodes and those of
  // the particles it reads (read_stretch) from now on, with `keep` those it holds too, and x_ and v_
  // from them (collective).
  void hold_nodes(discretization::NodeStore& nodes, bool keep);
  void update_records();
  void update_neighbour_list(discretization::NodeStore& nodes);
  neighbors::ParticleRange own_particles() const;
  neighbors::ParticleRange computed_rows() const;  // for the present force blocks
  // Under MPI, after the first build: the list's rows this rank searches (rows_searched, for its
  // own particles `own`), built from its own particles and the others' within reach of those rows,
  // which come in from their ranks; returns every particle's box (the grid's).
  BoundingBox search_near_rows(discretization::NodeStore& nodes);
  neighbors::ParticleRange rows_searched(neighbors::ParticleRange own) const;
  // Under MPI, dealt in blocks (by share_, or by `share`).
  neighbors::ParticleRange particles_of(int rank) const { return particles_of(rank, share_); }
  neighbors::ParticleRange particles_of(int rank, const discretization::ParticleShare& share) const;
  // Under MPI: each rank's rows' box at the positions x, grown by the list radius (collective).
  std::vector<BoundingBox> near_rows(StretchView<Vec3> x, Real radius, const BoundingBox& grid) const;
  // Under MPI after a new deal: the rows this rank computes from the list's positions at its build
  // of its particles and those near them, in from their ranks (collective).
  void search_dealt_rows(const discretization::ParticleShare& dealt_before);
  // The list's skin for the largest h of every particle.
  static Real list_skin(Real h_largest);
  // Every particle's position and reach at the last list build (each rank's own come in), where
  // rows no rank searched are searched from them (VerletList::search_every_row): force blocks
  // longer than the margin of the rows searched (rows_searched). Collective.
  void complete_list();
  // Under MPI, once the rows are searched: the positions and reaches at the build of a rank's own
  // particles alone, which its rebuild test reads and complete_list brings to the others.
  void keep_own_list_state();
  StretchView<Real> list_reach() const { return list_reach_.view(particle_count()); }
  // corrected: *CONTROL_SPH FORM 1 (the moment and its inverse B), else plain SPH.
  // Returns the first particle whose state update left it unsound (sound()), else
  // particle_count(); none is updated while categorizing.
  template <typename Kernel, bool corrected>
  Index compute_rates(Real dt);
  void categorize();
  // The state update of every particle, after the categorization (colour field on); without it
  // compute_rates updates each particle as soon as its rates are known (update_particle).
  // Returns as compute_rates does.
  Index update_state(Real dt);
  // Particle a's material state, density and exported stress sigma_a B_a^T over dt, from its
  // velocity gradient L (corrected), correction B and density rate.
  void update_particle(Index a, const Mat3& L, const Mat3& correction, Real density_rate, Real dt);
  // Whether the categorization, which needs every particle's rates, separates the rates pass
  // from the state update.
  bool categorizing() const { return !category_.empty(); }
  // Whether particle a's density and smoothing length are still positive numbers.
  bool sound(Index a) const;
  // Stops the run (InstabilityError) at the first particle that is not sound (first_unsound <
  // particle_count()), before the force pass, the neighbour search or the materials see it.
  void check_state(const discretization::NodeStore& nodes, Index first_unsound) const;
  // Particle a's limit on the step at node velocity v (stable_time_step).
  Real stable_step_of(Index a, const Vec3& v) const;
  void relax_exported_deviator(Index a, const Mat3& L, const Mat3& D_dev, bool treated,
                               Real relaxation, Real dt);
  // corrected: the records of FORM 1 (stress_), else those of plain SPH (plain_stress_).
  template <typename Kernel, bool corrected>
  void compute_pair_forces();
  // Calls f(kernel, corrected) with the kernel (kernels::with_kernel) and whether the gradient
  // is corrected (std::true_type or std::false_type), both known at compile time.
  template <typename F>
  void with_discretization(F&& f);
  bool active(Real time) const;
  // Under MPI (replicated storage, the halo by reach; docs/SCALING.md §3): after the state update,
  // what the force pass and the next step's rates pass read of the other ranks' particles (their
  // volume, sound speed, density and the stress records) comes in from their ranks (reach_); the
  // rest of their state goes stale.
  void share_updated_state();
  // Which of the other ranks' particles this rank's rows read (plan_reach): the neighbours of its
  // own particles and of the force blocks it runs. At each list build and each new deal.
  void plan_reach(const discretization::NodeStore& nodes);
  // Every rank's positions and velocities of its own particles in (share_), where the halo brought
  // in only those its rows read: before a checkpoint, and before every row is searched when the
  // force blocks outgrow the rows a rank searched (update_neighbour_list).
  void complete_kinematics(discretization::NodeStore& nodes);
  // Which force blocks this rank runs (ForceBlocks: each block by one rank): at each list build
  // and each new deal. All when the run is one process.
  void choose_force_blocks(const discretization::NodeStore& nodes);
  // Under MPI, the nodes dealt anew (load balance): this rank's new rows, and the state they read
  // from the ranks that computed it before (collective).
  void deal_anew(discretization::NodeStore& nodes);
  void search_computed_rows(const discretization::NodeStore& nodes, const discretization::ParticleShare& dealt_before);
  // The Own arrays hold particles [begin, end) from now on (this rank's own once the particles are
  // dealt; more while a new deal brings their state in), and so do the Own constants once held.
  void hold_own_state(neighbors::ParticleRange range);
  // The set-up's state of particles [begin, end), which the Own and Read arrays then hold: at rest,
  // each material's density, initial energy and state.
  void set_up_state(neighbors::ParticleRange range);
  // The Read arrays hold particles [begin, end) from now on: under MPI the stretch from the first
  // particle this rank's rows read to the last (read_stretch), more while a list build or a new
  // deal brings in their state; every particle on one process. The Read constants too, once held.
  void hold_read_state(neighbors::ParticleRange range);
  // From the first particle this rank's rows read (current_) or its force blocks add to, to the last.
  neighbors::ParticleRange read_stretch() const;

  std::vector<materials::Material> materials_;
  SolidOptions options_;

  // Per particle (structure of arrays). Under MPI the state that only a particle's own rank reads
  // is held for its own particles alone (Own, hold_own_state); the state that the rows read of
  // their neighbours, for the stretch of particles from the first a rank's rows read to the last
  // (Read, hold_read_state); the rest (each particle's node, the list's reach) for every particle.
  template <typename T>
  using Own = RangeArray<T>;
  template <typename T>
  using Read = RangeArray<T>;
  std::vector<Index> node_;
  // The set-up's constants (material, mass, and below the initial h, spacing and full-support
  // count) are held as the state is, by rank and by stretch, once constants_held_: under MPI from
  // the first list build on (a new deal before it, while a part waits for START, sets up the new
  // own particles' state from every particle's constants, which no rank has brought in yet), and
  // from the start where the set-up built each rank's block of them (never a part that waits).
  Read<Index> material_;
  Read<Real> mass_;
  Real uniform_mass_ = 0;  // the mass of every particle when all are equal, else 0
  bool constants_held_ = false;
  // Set up in blocks (no rank held every particle's position): the first list is built as the later
  // ones are, from a rank's own particles and those near its rows (search_near_rows).
  bool set_up_in_blocks_ = false;
  Real max_wave_speed_ = 0;  // the set-up's largest sound speed (max_wave_speed)
  Read<Real> smoothing_length_;  // h (LS-DYNA's); the kernel support is 2h
  Real smoothing_length(Index a) const { return smoothing_length_[a]; }
  Real& smoothing_length(Index a) { return smoothing_length_[a]; }
  // What the pair loops read of each particle, in single precision, written at the start of each
  // evaluation (update_records): positions relative to record_origin_ (the middle of the body at
  // the last list build, so that a float keeps its digits for the differences), h, velocity,
  // volume, sound speed and density of the step start, and the mass when the masses differ.
  Read<PairRecord> record_;
  Read<ViscosityRecord> viscosity_record_;
  Read<float> record_mass_;  // off when every mass is uniform_mass_
  Vec3 record_origin_ = Vec3::Zero();
  // What the force pass reads: sigma_a B_a^T and the volume after the state update, with the
  // gradient correction (stress_), else sigma_a and the volume (plain_stress_); the other is empty.
  Read<StressRecord> stress_;
  Read<PlainStressRecord> plain_stress_;
  // The stress as the force pass reads it, P = sigma B^T, and the volume after the update.
  void record_stress(Index a, const Mat3& exported, const Mat3& correction);
  // cutoff_margin h at the last list build; under MPI a rank's own particles' between builds, as the
  // list's positions at the build (keep_own_list_state).
  Own<Real> list_reach_;
  Read<Real> initial_smoothing_length_;
  struct HBounds {
    Real lower = 0, upper = 0;  // HMIN, HMAX
  };
  std::vector<HBounds> h_bounds_;  // per material-table entry
  Read<Real> spacing_;
  Read<Real> density_;
  Read<Real> volume_;  // m / rho, kept with the density: the pair loops read it per pair
  // The volume after the state update: the rates pass of the step still reads the step start's
  // volume_ of the neighbours while particles are being updated; swapped in after the update.
  Read<Real> updated_volume_;
  Own<Real> pressure_;
  Read<Real> sound_speed_;
  // c after the state update, swapped in with updated_volume_: the rates pass's viscosity reads the
  // neighbours' c of the step start.
  Read<Real> updated_sound_speed_;
  Own<Real> internal_energy_;  // specific (per unit mass)
  Own<materials::PointState> state_;  // deviatoric stress, plastic strain, temperature, ...
  Own<Mat3> back_stress_;  // where a material keeps one (materials::keeps_back_stress), else empty
  Own<Real> gradient_amplification_;              // s_a of the stable step (stable_time_step)
  Real full_support_gradient_ = 0;                // H sum_b V_b |grad W| of a full support
  // B_a (identity without correction) between compute_rates and update_state, when categorizing.
  Own<Mat3> correction_;
  Read<Mat3> artificial_stress_;                  // R_a (empty when switched off)
  // The deviator the pair force uses under the relaxed treatment (empty when no part has it):
  // follows the material's increments and relaxes toward 0 (treated) or S (not treated).
  Own<Mat3> exported_deviator_;
  // Colour field (empty when no part asks for it).
  Own<Real> colour_;
  Own<Vec3> colour_normal_;
  Own<std::int32_t> support_count_;        // neighbours inside the support
  Own<Real> full_support_count_;           // the count of a full support at this h/spacing
  Own<Category> category_;
  // Scratch of the current step.
  // x and v of the particles' nodes, by particle: the node store's own arrays when the particles own
  // a contiguous run of nodes (first_node_ >= 0) and it holds every node, else copies gathered into
  // x_copy_, v_copy_, of the stretch of particles whose nodes a window holds under MPI.
  StretchView<Vec3> x_, v_;
  RangeArray<Vec3> x_copy_, v_copy_;
  Index first_node_ = -1;
  // The rates that wait for the categorization (empty when not categorizing).
  Own<Real> density_rate_;
  Own<Mat3> velocity_gradient_;
  Own<Real> strain_rate_squared_;  // 2/3 D':D' of the last step, the effective strain rate squared
  // Which entries of each Verlet row the rates pass found inside the support (one byte per pack;
  // solid.cpp, mask_start): the force pass, at the same h, takes the same pairs.
  std::vector<std::uint8_t> support_mask_;
  // The artificial viscosity of the step, from the rates pass (compute_rates).
  Own<Real> viscous_heating_;  // 1/2 sum_b m_b Pi_ab v_ab . grad_a W_ab
  Own<Vec3> viscous_force_;    // -sum_b m_a m_b Pi_ab grad_a W_ab
  // Total internal force as (x, y, z, 0): the pair sums of the force pass, to which the viscous
  // force is added last; one 256-bit row a particle, which the pair-once subtraction updates whole.
  Read<Eigen::Vector4d> force_;
  // The force pass's blocks of particles (compute_pair_forces), as the last list build laid them
  // out; none when the list spans too much of the particle order for pair-once blocks, and the pass
  // then gathers every row whole. blocks_: which this rank runs (choose_force_blocks).
  Index force_blocks_ = 0, force_block_length_ = 0;
  ForceBlocks blocks_;
  long long blocks_partition_ = -1;  // NodeStore::partition that blocks_ was assigned for

  // The nodes this rank computes (NodeStore::owns); every node when the run is one process.
  discretization::ParticleShare share_;  // under MPI: the particles this rank computes, theirs to all
  bool owns(Index a) const { return share_.owns(node_[a]); }
  discretization::ReachShare reach_;  // under MPI: the other ranks' particles this rank's rows read
  // Under MPI: 1 for the particles this rank's rows read (its own among them), whose state and h
  // it keeps current each step; empty for one process (every particle).
  std::vector<std::uint8_t> current_;
  bool current(Index a) const { return current_.empty() || current_[a]; }
  long long reach_partition_ = -1;    // NodeStore::partition that reach_ was planned for
  // NodeStore::partition whose own particles the Own arrays hold. Under MPI each rank sets up its own
  // particles' state at the first deal (a checkpoint is read by rank, or read whole before the first
  // list and cut to them); it keeps its own and those its rows read, and no rank gathers another's:
  // the fields, the residual-stress report and a failure report are each rank's own particles', a
  // new deal brings in what the new rows read (deal_anew), and each rank writes its own into a
  // checkpoint.
  long long held_partition_ = -1;
  bool set_up_ = false;  // whether the state was set up (set_up_state) or read from a checkpoint
  bool kinematics_complete_ = true;   // every particle's x and v current (complete_kinematics())

  neighbors::VerletList verlet_;
  Real time_ = 0;
  long long step_ = 0;
  bool list_built_ = false;
  bool h_outgrown_ = false;  // some h_a exceeded its list reach at the last h update
  // The stable step at the state of the last compute_forces, found in its last pass (none while
  // inactive or before the first call).
  std::optional<Real> stable_step_;
  bool has_temperature_ = false;  // some material heats (Johnson-Cook): output the temperature
};

}  // namespace spall::sph
