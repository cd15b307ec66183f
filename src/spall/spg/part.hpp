#pragma once
// One SPG part: its particles (the nodes of its solid mesh), their bonds, RK shape functions and
// smoothing operator, and the material state at each particle. Particles of different parts do not
// see each other through the kernel; parts couple through shared nodes only.
//
// Per step (docs/THEORY.md §9, seed 001 eqs. 6-13):
//   smoothing      xs_I = sum_K Psi_K(X_I) x_K,  vs_I = sum_K Psi_K(X_I) v_K      (eq. 9-11 at the particles)
//   deformation    F_J = sum_I xs_I (x) grad Psi_I(X_J),  dF_J = sum_I vs_I (x) grad Psi_I(X_J)   (eq. 12)
//                  (ITB 2: x and v in place of xs and vs)
//                  plus the integration-constraint correction C on x and v (THEORY §9.4)
//   stress         L = dF F^-1; the material library's point update (materials/material.hpp) with
//                  the Jaumann rotation of the deviator, D = sym L, rho = m / V and the energy equation;
//                  bulk viscosity q = rho l (Q1 l tr(D)^2 - Q2 c tr(D)) in compression
//   force          f_K = -sum_I Psi_K(X_I) h_I - t_K + sum_I Psi_K(X_I) t_I - sum_J V_J P_J C_JK,
//                  h_I = sum_J V_J P_J grad Psi_I(X_J), P = J sigma F^-T          (eq. 6 with eq. 13)
//                  (ITB 2: -h_K in place of the first sum)
//   stabilization  t_J = s_J + c_J (v_J - vs_J), ds_J/dt = kappa_J (v_J - vs_J) + W_J s_J: a spring
//                  and a dashpot on the motion that the smoothing removes (reconstructed; THEORY §9.5)
// with X the reference configuration of the last kernel update (every SMSTEP steps). KERNEL chooses
// what an update rebuilds (THEORY §9.7): 0 updated Lagrangian, the bonds of the first
// configuration with windows that deform with the material; 1 Eulerian, bonds searched anew in the
// current configuration; 2 pseudo-Lagrangian, the bonds of the first configuration. With 1 and 2 the
// windows, in the current configuration, widen with the material's stretch (at most 4 times).
#include <algorithm>
#include <cstdint>
#include <functional>
#include <limits>
#include <vector>

#include "spall/core/communicator.hpp"
#include "spall/core/error.hpp"
#include "spall/core/range_array.hpp"
#include "spall/discretization/energy_ledger.hpp"
#include "spall/discretization/field_set.hpp"
#include "spall/discretization/mass_scaling.hpp"
#include "spall/discretization/particle_share.hpp"
#include "spall/discretization/reach_share.hpp"
#include "spall/materials/material.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/spg/bond_failure.hpp"
#include "spall/spg/bonds.hpp"
#include "spall/spg/integration_constraint.hpp"
#include "spall/spg/kernel_function.hpp"

namespace spall::spg {

// *SECTION_SOLID_SPG KERNEL
enum class KernelUpdate { updated_lagrangian = 0, eulerian = 1, pseudo_lagrangian = 2 };
// *SECTION_SOLID_SPG ITB (1 and 2; 3 is MC-SPG, not implemented)
enum class Stabilization { fluid_particle = 1, simplified_fluid_particle = 2 };

struct PartSettings {
  Id part_id = 0;
  KernelShape shape = KernelShape::cubic_cubical;  // ISPLINE
  Vec3 dilation = Vec3::Constant(1.6);             // DX DY DZ
  KernelUpdate kernel_update = KernelUpdate::updated_lagrangian;
  int update_interval = 15;  // SMSTEP
  Stabilization stabilization = Stabilization::fluid_particle;
  BondFailure failure_quantity = BondFailure::plastic_strain;  // IDAM
  // FS: the critical value of the IDAM quantity (IDAM 1: the material's FS / FAIL when it has one)
  Real failure_value = 1.0e10;
  Real failure_stretch = 1.0;    // STRETCH
  materials::Material material;
  // eta in the stabilization stiffness kappa = eta (K + 4G/3) V / h^2; not a deck field (SPG has no
  // stabilization control parameter, seed 001 §1), 0 only in tests that show what it removes.
  Real stabilization_factor = 1.0;
  // xi: the dashpot beside the spring, c = 2 xi sqrt(kappa m) (THEORY §9.5); not a deck field.
  Real stabilization_damping = 0.3;
  // *CONTROL_BULK_VISCOSITY Q1 (quadratic) and Q2 (linear), LS-DYNA's bulk viscosity of solids.
  Real bulk_viscosity_quadratic = 1.5;
  Real bulk_viscosity_linear = 0.06;
  SourceLocation where;  // *SECTION_SOLID_SPG card 2 (DX ...), for messages about the supports
};

// One particle as the problem builder hands it over.
struct ParticleSetup {
  Index node = 0;
  Real volume = 0;              // nodal volume from the mesh
  Vec3 spacing = Vec3::Zero();  // nodal spacing per direction (largest extent of the elements around)
  bool on_surface = false;      // a node of a face that only one element of the part has
};

class Part {
 public:
  // The particles' nodes are named by their places in the node order (the rows of every node's
  // store at the set-up; NodeStore::node_row finds their rows in a window), ascending. With
  // `across` (the set-up in blocks), `particles` are those on this rank's block of the nodes, the
  // part's others on the other ranks' blocks (collective).
  Part(PartSettings settings, const std::vector<ParticleSetup>& particles, const discretization::NodeStore& nodes,
       const parallel::Communicator* across = nullptr);

  // What holds the nodes a part reads under MPI with NodeStore::window_by_reads (collective): the
  // formulation's window of every part's places_read() and the places given
  // (SpgFormulation::hold_nodes).
  using HoldNodes = std::function<void(parallel::Range places)>;
  // Advances the state over dt with x^n and v^{n-1/2}, updates the kernel when it is due, and
  // adds the internal forces at x^n to nodes.f. Where it plans what it reads anew (the first deal,
  // a new deal, a kernel update), it calls hold_nodes.
  void compute_forces(discretization::NodeStore& nodes, Real dt, const HoldNodes& hold_nodes = {});
  Real stable_time_step(const discretization::NodeStore& nodes) const;
  // DT2MS (discretization::Formulation::scale_mass_below).
  void scale_mass_below(Real step, bool first_step_only);
  // The mass DT2MS added on the last step, and in all (over every rank's particles).
  Real added_mass_step() const { return mass_scaling_.added_this_step; }
  Real added_mass() const { return mass_scaling_.added; }
  // The power of the internal forces at the velocities v: stored (strain energy, stabilization
  // springs) and dissipated by the bulk viscosity.
  discretization::InternalPower internal_power(const discretization::NodeStore& nodes,
                                              std::span<const Vec3> v) const;
  Real max_wave_speed() const;

  // Writes this part's output fields for the nodes of its own particles (all on one process).
  void write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const;

  const PartSettings& settings() const { return settings_; }
  Index particle_count() const { return static_cast<Index>(node_.size()); }
  const BondList& bonds() const { return bonds_; }
  // Every bond broken so far, also those an Eulerian update has dropped from the rows since.
  const std::vector<BondPair>& broken_pairs() const { return broken_pairs_; }
  // The bond entries whose shape functions this rank holds (hold_shape_rows).
  parallel::Range held_shape_rows() const { return {grad_.held_begin(), grad_.held_end()}; }
  // The particles whose state (F, the material point, the spring, ...) this rank holds (hold_state).
  parallel::Range held_state() const { return {state_.held_begin(), state_.held_end()}; }
  long long kernel_updates() const { return kernel_updates_; }
  // Particles whose bonds no longer hold a linear field (Shepard smoothing, no strain of their own),
  // over the ranks (collective).
  Index degraded_count() const;
  // Under MPI with the velocities by reach: every rank's positions and velocities of its own
  // particles' nodes in (with a window, those of the rows held), before a checkpoint (which writes
  // the state held by stretch in pieces).
  void complete_state(discretization::NodeStore& nodes) { complete_kinematics(nodes); }
  // Under MPI with the velocities by reach (NodeStore::velocities_by_reach): v^{n+1/2} of the other
  // ranks' particles that this rank's smoothing reads, the bond partners of the particles it reads
  // (plan_smoothed), in from their ranks; the rest go stale until a kernel update, a new deal or a
  // checkpoint completes them (complete_kinematics). The time loop advances the positions of the
  // rows those particles' nodes span (nodes_read).
  void share_velocities(discretization::NodeStore& nodes);
  // The rows from the lowest node of those particles and this rank's own to past the highest;
  // every row until planned.
  parallel::Range nodes_read(const discretization::NodeStore& nodes) const;
  // The places in the node order of those nodes (of the particles the smoothing reads).
  parallel::Range places_read() const {
    if (smoothed_.size() == 0) return {};
    return {node_[smoothed_.begin], node_[smoothed_.end - 1] + 1};
  }
  // Everything but the settings (the deck's) and the particles' nodes, which must match.
  void checkpoint(Archive& archive);
  std::size_t memory_bytes() const;

 private:
  // The rows of this rank's own particles (every particle's on one process), in the current
  // positions; `previous`: the rows before (a KERNEL 1 update), whose bonds keep their rest lengths;
  // `near`: the particles whose positions and windows are current here, ascending (every one where
  // null), among them every particle within the search radius of this rank's own.
  void search_bonds(const BondList* previous, const std::vector<Index>* near = nullptr);
  // The largest support radius of every rank's own particles: no bond is longer (collective).
  Real search_radius() const;
  // Under MPI at the first deal: the bonds of this rank's own particles, searched among those near
  // them (bring_neighbourhood), their positions and velocities from the nodes.
  void search_from_own(discretization::NodeStore& nodes);
  // Under MPI at the first deal, once the particles read are held: the constants of this rank's
  // own particles from the builder's (particles_at_set_up_), the state the others carry
  // (visit_carried_state: their constants among it) in from their ranks (reach_). Collective.
  void set_up_read_constants();
  // Under MPI at the first deal and at a KERNEL 1 update: the positions, velocities and windows of
  // the particles within twice the search radius of the box around this rank's own (those its new
  // rows and their partners read) in from their ranks, into x_, v_, support_ and the nodes; returns those and its
  // own, ascending. Collective.
  std::vector<Index> bring_neighbourhood(discretization::NodeStore& nodes);
  // The bonds of the rows this rank reads (read_) in from the ranks that hold them (`from`, planned
  // for those rows), the rows held now kept while they travel (this rank's own after a search, a
  // new deal's senders'), and the mirrors of its own rows linked.
  void take_read_rows(const discretization::ReachShare& from);
  // The bonds of the rows of `particles` in (`from`, planned for them), those held now kept.
  void bring_bond_rows(const discretization::ReachShare& from, parallel::Range particles);
  // The set-up's shape functions and integration-constraint correction (on one process in the
  // constructor, under MPI at the first deal: set_up_pending_).
  void set_up_shape_functions(const discretization::NodeStore& nodes);
  // The per-particle state (F, the material point, the thermodynamic scalars, the spring, the
  // step's scratch, the shape functions' self terms and the correction's, the windows, the
  // constants) of particles [begin, end) held from now on (every particle on one process, those a
  // rank reads under MPI: read_): the particles held before keep their values, the others start at
  // the set-up's (the windows and constants at none), and come in from their ranks where a pass
  // reads them (at the first deal, the constants too: set_up_read_constants).
  void hold_state(parallel::Range particles);
  // The constants (volumes, first windows, spacings, spring stiffnesses and dashpots, surface flags)
  // of `particles`, held, from the builder's `setup`, whose first is particle `first`.
  void set_up_constants(const std::vector<ParticleSetup>& setup, Index first, parallel::Range particles);
  // visit(array, fresh) for each array of that state, in one order (the checkpoint's), with the
  // value a particle newly held starts at: the state a particle carries to the ranks that read it
  // anew (a new deal), then the step's scratch, which the passes fill before they read it.
  template <typename Self, typename Visit>
  static void visit_carried_state(Self& part, Visit&& visit);
  template <typename Self, typename Visit>
  static void visit_held_state(Self& part, Visit&& visit);
  // Returns at the set-up the lowest particle over the ranks whose support holds too few particles
  // for a linear field (-1: none), which stops the run; later such a particle is degraded.
  Index build_shape_functions(bool at_setup);
  // The deck's ID of particle's node, from the rank that computes it (collective: for messages).
  Id node_id(const discretization::NodeStore& nodes, Index particle) const;
  // rho_0 V_0: this part's share of the node's mass (DT2MS adds to it), of a particle held.
  Real mass(Index i) const { return settings_.material.density * volume0_[i]; }
  void update_kernel(discretization::NodeStore& nodes);
  void detach_degraded_particles();
  void smooth(StretchView<Vec3> field, RangeArray<Vec3>& smoothed) const;
  // Returns the first particle whose F inverted (-1: none); the caller stops the run.
  Index deformation(StretchView<Vec3> x, StretchView<Vec3> v, Real dt);
  void update_stabilization(Real dt);
  // IDAM's quantity, held for the particles given alone.
  void failure_quantity(RangeArray<Real>& out, parallel::Range particles) const;
  void internal_forces();
  // `whole`: every rank adds every particle's raise (else each its own particles').
  void scale_masses(discretization::NodeStore& nodes, bool whole);
  Real current_spacing(Index i) const;
  // Whether this rank computes particle i's strain and force (NodeStore::owns; every particle when
  // the run is one process). Under MPI (replicated storage, docs/SCALING.md) each step's state of a
  // rank's particles goes to the ranks whose particles are bonded to them (plan_reads, reach_); a
  // rank smooths, integrates the springs of and weighs the stress of the particles it reads alone
  // (reads_), and holds the bonds of their rows alone. At a kernel update a rank folds the F of the
  // particles it reads and judges its own particles' bonds, and the bonds broken travel to every
  // rank (every rank keeps every broken pair); the bond search (KERNEL 1: the positions and windows
  // of the particles near its own in), the shape functions and the integration-constraint solve
  // are each rank's for its own particles, and of them only what the other ranks' rows read
  // travels (reach_, planned anew for the new bonds).
  bool owns(Index i) const { return share_.owns(node_[i]); }
  // own_ in the nodes' deal.
  void find_own(const discretization::NodeStore& nodes);
  // The other ranks' particles bonded to this rank's (from its own rows): at each kernel update and
  // each new deal. Sets reads_ (this rank's own particles and those) and read_, and returns the
  // flags of every particle, as reads_ holds them (collective).
  std::vector<std::uint8_t> plan_reads(const discretization::NodeStore& nodes);
  // Then, from the rows read: smoothed_ (x_ and v_ held for it), and with the velocities by reach
  // velocity_reach_ (collective).
  void plan_smoothed(const discretization::NodeStore& nodes);
  // The pairs given by every rank (under MPI; each rank's own alone before the deal), sorted, each once.
  std::vector<BondPair> every_ranks(std::vector<BondPair> pairs) const;
  // Whether this rank computes particle i's smoothed fields, spring and weighted stress: every
  // particle on one process, else those it reads.
  bool computes(Index i) const { return reads_.empty() || reads_[i]; }
  // The rows a rank holds current, as break_bonds takes them: those of the particles it reads (an
  // empty view, every row, on one process).
  StretchView<std::uint8_t> rows_read() const {
    return reads_.empty() ? StretchView<std::uint8_t>{} : reads_.view(particle_count());
  }
  // Under MPI, the nodes dealt anew (load balance): the particles this rank now reads come in with
  // their shape functions and correction and their state held by stretch from the ranks that
  // computed them before (collective).
  void deal_anew(const discretization::NodeStore& nodes);
  // From now on the bonds' shape functions and correction hold the entries `rows` (those of the
  // particles read_, every row on one process, but while a new deal's rows travel), the entries
  // held before keeping their values.
  void hold_shape_rows(parallel::Range rows);
  // With the velocities by reach, every rank's positions and velocities of its own particles' nodes
  // in (share_, in the deal they were computed in), and with DT2MS their masses: what a new deal's
  // rows and a checkpoint read. With a window of the nodes, those of the rows it holds alone (from
  // the ranks that computed them). DT2MS's factors travel with the state (visit_carried_state).
  void complete_kinematics(discretization::NodeStore& nodes);
  void correct_integration_constraint(bool at_setup);

  PartSettings settings_;
  // Per particle.
  std::vector<Index> node_;          // the node's place in the node order (its row: NodeStore::node_row)
  // Of the particles a rank reads (read_; every particle on one process; hold_state).
  // The window's half-widths in the reference configuration of the kernel: a_I, or with KERNEL 1
  // and 2 the box around a_I carried by the deformation since the start (window_extent, part.cpp);
  // a KERNEL 1 search holds those near a rank's own too while it runs (bring_neighbourhood).
  RangeArray<Vec3> support_;
  RangeArray<Real> volume0_;            // V_0
  RangeArray<Real> volume_ref_;         // volume in the reference configuration of the kernel
  RangeArray<Vec3> initial_support_;    // a_I = (DX, DY, DZ) x nodal spacing
  RangeArray<Real> spacing_;            // smallest nodal spacing, for the stable step
  RangeArray<Real> mean_spacing_;       // (h_x h_y h_z)^(1/3)
  RangeArray<Real> stiffness_;          // kappa_I of the stabilization spring
  RangeArray<Real> dashpot_;            // c_J
  RangeArray<Index> initial_bond_count_;
  RangeArray<std::uint8_t> on_surface_;  // on the mesh's boundary faces
  RangeArray<Mat3> F_;        // deformation gradient since the last kernel update
  RangeArray<Mat3> F_total_;  // from the initial configuration to the last kernel update
  RangeArray<materials::PointState> state_;
  RangeArray<Mat3> back_stress_;  // where the material keeps one (materials::keeps_back_stress), else off
  RangeArray<Real> pressure_, density_, specific_energy_;
  RangeArray<Real> viscous_pressure_;  // bulk viscosity q, added to the pressure
  RangeArray<Real> viscous_power_;     // V q (-tr D): the rate of energy it dissipates
  RangeArray<Real> sound_speed_;  // (read_) read at a rank's own: the stable step, the bulk viscosity, DT2MS
  RangeArray<Vec3> stabilization_force_;  // s_J, the spring (read_)
  RangeArray<Vec3> stabilization_total_;  // s_J + c_J (v_J - vs_J), what the force gathers (read_)
  RangeArray<Real> stabilization_power_;  // c_J |v_J - vs_J|^2, dissipated (read_)
  // 1 where the bonds left no longer hold a linear field: Shepard smoothing, no strain of its own
  // (read_: a rank's own set by the shape functions, the others' in from their ranks).
  RangeArray<std::uint8_t> degraded_;
  // Shape functions in the reference configuration: self term per particle (read_), the rest per bond.
  RangeArray<Real> psi_self_;
  RangeArray<Vec3> grad_self_;
  // Per bond, of the rows of the particles a rank reads alone (read_; every row on one process):
  // the other rows are read by no pass of the rank's (hold_shape_rows; the bonds alike).
  RangeArray<Real> psi_;   // psi_[k], k in row J: Psi_{neighbour}(X_J)
  RangeArray<Vec3> grad_;  // grad Psi_{neighbour}(X_J)
  BondList bonds_;
  std::vector<BondPair> broken_pairs_;
  IntegrationCorrection correction_;
  // Scratch of the current step: x and v of the particles the smoothing reads (smoothed_; every
  // particle's until the first deal, whose search reads them), copied from the nodes at each step,
  // and while a KERNEL 1 search runs those near a rank's own (bring_neighbourhood).
  RangeArray<Vec3> x_, v_;
  // Of the particles read (read_).
  RangeArray<Vec3> xs_, vs_, h_, force_;
  RangeArray<Mat3> weighted_stress_;  // V_J P_J
  RangeArray<Mat3> spin_;             // W_J

  discretization::ParticleShare share_;  // under MPI: the particles this rank computes, theirs to all
  discretization::ReachShare reach_;     // under MPI: the other ranks' particles bonded to this rank's
  RangeArray<std::uint8_t> reads_;       // under MPI: 1 for this rank's particles and those (read_; plan_reads)
  long long reach_partition_ = -1;       // NodeStore::partition that reach_ was planned for
  // With the velocities by reach: the other ranks' particles whose velocities this rank's smoothing
  // reads (two bonds from its own), and whether every particle's position and velocity is current
  // here (complete_kinematics).
  discretization::ReachShare velocity_reach_;
  bool kinematics_complete_ = true;
  // The stretches of the particles (in node order) that hold this rank's own, those it reads, and
  // those whose positions and velocities the smoothing of the particles it reads reads: the step's
  // passes run over them (every particle on one process and until the nodes are dealt; find_own,
  // plan_reads, plan_smoothed).
  parallel::Range own_, read_, smoothed_;
  bool set_up_pending_ = false;  // under MPI until the first deal: no bond, shape function or correction yet
  // Under MPI the builder's particles (every one, or set up in blocks those of this rank's block,
  // the first of them particle set_up_first_), until the first deal sets up the constants of its
  // own (set_up_read_constants).
  std::vector<ParticleSetup> particles_at_set_up_;
  Index set_up_first_ = 0;
  const HoldNodes* hold_nodes_ = nullptr;  // compute_forces's, while it runs

  int steps_since_update_ = 0;
  long long kernel_updates_ = 0;
  discretization::MassScaling mass_scaling_;  // DT2MS
  RangeArray<Real> mass_scale_;  // DT2MS: the factor f >= 1 on each particle's mass (read_; off without)
};

}  // namespace spall::spg
