#pragma once
// Solid finite elements (seed 001 §2.3: the hexahedral FEM region around the SPG core): one
// formulation owns every part meshed with *SECTION_SOLID elements, and couples to SPG or SPH
// parts through the nodes they share (each adds its forces to the node store).
//   ELFORM 1   one-point hexahedron (Flanagan & Belytschko's uniform gradient) with hourglass
//              control (*HOURGLASS IHQ 1-5);
//   ELFORM 2   fully integrated selective-reduced hexahedron: the deviator at 2 x 2 x 2 Gauss
//              points, the volumetric strain rate and the pressure constant over the element;
//   ELFORM 10  one-point (constant strain) tetrahedron.
// Every integration point takes the one material-point step of materials::advance_point, as SPG
// particles do. Bulk viscosity (*CONTROL_BULK_VISCOSITY, *HOURGLASS Q1 Q2) on every element.
// Theory, sources and what differs from LS-DYNA: docs/THEORY.md §10.
//
// Elements are processed colour by colour (no two elements of a colour share a node), so each
// adds its forces to its nodes directly, and a node's sum is taken in colour order whatever the
// thread count: results do not depend on it.
#include <array>
#include <cstdint>
#include <optional>
#include <span>
#include <vector>

#include "spall/core/range_array.hpp"
#include "spall/discretization/formulation.hpp"
#include "spall/discretization/mass_scaling.hpp"
#include "spall/discretization/particle_share.hpp"
#include "spall/discretization/reach_share.hpp"
#include "spall/fem/hexahedron.hpp"
#include "spall/materials/material.hpp"

namespace spall::fem {

// *HOURGLASS / *CONTROL_HOURGLASS IHQ for solids, grouped by what Spall computes.
enum class HourglassForm {
  none,          // fully integrated elements and tetrahedra have no hourglass modes
  viscous_base,  // IHQ 1: viscous, on the base vectors Gamma (not orthogonal to rigid rotation)
  viscous,       // IHQ 2, 3: Flanagan-Belytschko viscous, on the orthogonalised gamma
  stiffness      // IHQ 4, 5: Flanagan-Belytschko stiffness, on gamma
};

struct HourglassControl {
  HourglassForm form = HourglassForm::viscous;
  Real coefficient = 0.1;  // QM
};

// When an element is deleted (docs/THEORY.md §10.4): *MAT_ADD_EROSION's criteria (each off when
// unset), evaluated at each integration point with the point's stress and the element's strain;
// a point fails when `criteria` of them hold at once, or when its material failed in a way that
// erodes (materials::erodes_element); the element goes when `points` of its points have failed.
struct Erosion {
  std::optional<Real> max_pressure, min_pressure;                  // MXPRES, MNPRES
  std::optional<Real> max_principal_stress, von_mises;             // SIGP1, SIGVM
  std::optional<Real> max_principal_strain, min_principal_strain;  // MXEPS, MNEPS
  std::optional<Real> effective_strain, volumetric_strain;         // EFFEPS, VOLEPS
  std::optional<Real> failure_time;                                // FAILTM
  int criteria = 1;  // NCS
  int points = 1;    // NUMFIP
  bool material_failure = true;
  // Whether the element must keep its strain tensor and accumulated effective strain.
  bool needs_strain() const {
    return max_principal_strain || min_principal_strain || effective_strain;
  }
};

// What every element of a part shares.
struct PartSettings {
  Id part_id = 0;
  int elform = 1;  // 1, 2 or 10
  materials::Material material;
  HourglassControl hourglass;  // ELFORM 1 only
  Real bulk_quadratic = 1.5;   // Q1
  Real bulk_linear = 0.06;     // Q2
  Erosion erosion;
};

// One element as the deck gives it: its part (index into the settings) and its nodes (node-store
// indices, four for a tetrahedron).
struct ElementSetup {
  Id id = 0;
  int part = 0;
  std::array<Index, 8> node{};
};

// The volume of an element at the nodes' reference positions x0: a tetrahedron of its first four
// nodes, or the trilinear hexahedron of all eight (degenerate ones repeat nodes).
Real element_volume(const std::array<Index, 8>& node, bool tetrahedron, const discretization::NodeStore& nodes);

class SolidElements final : public discretization::Formulation {
 public:
  // Throws std::invalid_argument for an element inverted or flat at the start (fem/setup.cpp
  // checks the deck first and names the card).
  SolidElements(std::vector<PartSettings> parts, const std::vector<ElementSetup>& elements,
                const discretization::NodeStore& nodes);

  const char* name() const override { return "FEM"; }
  void compute_forces(discretization::NodeStore& nodes, Real dt) override;
  Real stable_time_step(const discretization::NodeStore& nodes) const override;
  void book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                     std::span<const Vec3> v, Real dt) const override;
  // The hourglass energy of the elements it books that have not eroded and the mass DT2MS added to
  // them (their internal and eroded energies are the ledger's by part: book_energies).
  void sum_parts(discretization::PartSummary& parts, const discretization::NodeStore& nodes) const override;
  void write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const override;
  Real max_wave_speed() const override { return max_sound_speed_; }
  std::span<const Id> eroded_elements() const override { return eroded_now_; }

  // rho0 V0 / (nodes per element) to each node of each element (LS-DYNA's lumped mass).
  // Records the mass other formulations gave each node first (what an eroded node keeps).
  void add_nodal_masses(discretization::NodeStore& nodes);

  // *CONTROL_TIMESTEP ERODE: elements whose own stable step falls below `step` are deleted, and
  // so are inverted ones (instead of stopping the run).
  void erode_below(Real step) override {
    erode_enabled_ = true;
    erosion_step_ = step;
  }
  bool scale_mass_below(Real step, bool first_step_only) override;
  void complete_state(discretization::NodeStore& nodes) override;
  // Under MPI with the velocities by reach (NodeStore::velocities_by_reach): v^{n+1/2} of the other
  // ranks' nodes of the elements this rank computes, from their ranks; the rest go stale until a
  // new deal or a checkpoint completes them (refresh_nodes).
  void share_state(discretization::NodeStore& nodes) override;
  bool halo_by_reach() const override { return true; }
  // The rows of the nodes of the elements this rank computes, and its own; every row until dealt.
  parallel::Range rows_read(const discretization::NodeStore& nodes) const override;
  // Alone in a deck, a rank holds the window of the node order from the first of its own nodes and
  // its elements' to the last (hold_nodes).
  bool holds_window() const override { return true; }
  // A rank writes the cells whose first node it owns (solver/field_output.cpp), elements it
  // computes: nothing to bring in.
  void complete_for_output(discretization::NodeStore& /*nodes*/) override {}
  void follow_elements(std::span<const Id> ids, std::vector<std::uint8_t>& taken) override;
  // The elements whose first node this rank owns (those it writes in the field output).
  void element_histories(std::span<double> values) const override;
  void checkpoint(Archive& archive, const discretization::NodeStore& nodes) override;

  Index element_count() const;
  Index eroded_count() const;  // under MPI: of the elements this rank books (the owner of their first node)
  std::size_t memory_bytes() const;
  const std::vector<PartSettings>& parts() const { return parts_; }

  // The elements of one kind, structure of arrays, each kind's in the order of their first nodes
  // in the node store, colour by colour within stretches of 512 of that order (so that under MPI
  // the elements a rank computes, those with a node of its block of the node order, are one stretch
  // short of the block's edges; solid_elements.cpp, store_in_colours).
  enum class Kind : std::uint8_t { hexahedron, hexahedron_selective_reduced, tetrahedron };
  struct Block {
    Kind kind = Kind::hexahedron;
    int nodes_per_element = 8;
    int points_per_element = 1;
    // The mesh, every element's.
    std::vector<Index> node;  // local node indices (into node_), nodes_per_element per element
    std::vector<std::int32_t> part;
    std::vector<Id> id;
    std::vector<Real> mass;
    std::vector<Index> colour_offset, colour_element;  // the elements of colour c, in order
    // The state, of the stretch of elements a rank computes under MPI (every element's on one
    // process): indexed by element, or by point (points_per_element an element).
    RangeArray<Real> mass_scale;  // DT2MS: the factor f >= 1 on the element's mass (off without)
    RangeArray<materials::PointState> state;   // per point
    RangeArray<materials::PointThermo> thermo;  // per point
    RangeArray<Mat3> back_stress;  // per point where a part keeps one (MAT_003 BETA < 1), else off
    RangeArray<Real> volume;
    RangeArray<Real> hourglass_energy;  // per element, for output
    RangeArray<Vec3> hourglass_force;   // stiffness forms: Q_alpha, hourglass_modes per element
    // Per element: the power its hourglass control dissipates at this step's rates (book_energies).
    RangeArray<Real> hourglass_power;
    // Erosion: 0 alive, 1 deleted during this step (booked at its end), 2 deleted.
    RangeArray<std::uint8_t> eroded;
    RangeArray<Mat3> strain;             // the element's strain, Jaumann-rotated (strain criteria)
    RangeArray<Real> effective_strain;   // sum of dt sqrt(2/3 dev D : dev D) (EFFEPS)
    Index size() const { return static_cast<Index>(id.size()); }
    // visit(array, values an element) for each state array a step carries over (all but
    // hourglass_power, which each step makes anew).
    template <typename Visit>
    void carried_state(Visit&& visit) {
      visit_carried(*this, visit);
    }
    template <typename Visit>
    void carried_state(Visit&& visit) const {
      visit_carried(*this, visit);
    }
    template <typename Self, typename Visit>
    static void visit_carried(Self& b, Visit& visit) {
      const int points = b.points_per_element;
      visit(b.mass_scale, 1), visit(b.state, points), visit(b.thermo, points), visit(b.back_stress, points);
      visit(b.volume, 1), visit(b.hourglass_energy, 1), visit(b.hourglass_force, hourglass_modes);
      visit(b.eroded, 1), visit(b.strain, 1), visit(b.effective_strain, 1);
    }
    // Holds the state of elements [begin, end) from now on (RangeArray::hold).
    void hold(parallel::Range elements);
  };

  const std::vector<Block>& blocks() const { return blocks_; }
  // Local node -> its place in the node order (NodeStore::node_row finds its row).
  std::span<const Index> local_nodes() const { return node_; }
  // The elements of block k whose state this rank holds: the stretch from the first it computes to
  // the last under MPI, every element on one process; none before the state is set up.
  parallel::Range held(std::size_t k) const {
    if (!state_set_up_) return {0, 0};
    return share_ ? share_->blocks[k].held : parallel::Range{0, blocks_[k].size()};
  }
  // The local nodes whose forces this rank sums: those of the elements it computes, from the first
  // to the last (its own among them), every local node on one process; none before the set-up.
  parallel::Range forces_held() const {
    if (!state_set_up_) return {0, 0};
    return share_ ? share_->forces : parallel::Range{0, static_cast<Index>(node_.size())};
  }

 private:
  // One element's step (solid_elements.cpp): its stable step, -1 once it inverted, -2 when it fails.
  // ELFORM 2 and tetrahedra.
  template <Kind kind>
  Real element_step(Block& block, Index e, discretization::NodeStore& nodes, Real dt);
  // The same for up to a pack's lanes of one-point hexahedra of one part, side by side (an element
  // a lane of simd::Pack): each element's result in steps[0 .. count).
  void hexahedra(Block& block, const Index* elements, int count, discretization::NodeStore& nodes, Real dt,
                 Real* steps);
  // Whether element e fails *MAT_ADD_EROSION or its material's failure after the step with mean
  // velocity gradient L, and (ERODE) whether its stable step is below erosion_step_.
  bool fails(Block& block, Index e, const Mat3& L, Real dt, Real stable_step);
  // The element's stable step with its length and sound speed, after DT2MS raised its mass.
  Real scaled_step(Block& block, Index e, Real length, Real c, Real volume_rate, discretization::NodeStore& nodes);
  // Takes the elements deleted during this step out: their mass from their nodes, their energies
  // into the eroded terms.
  void remove_eroded(discretization::NodeStore& nodes);

  // Under MPI (docs/SCALING.md §3, "Solid elements by rank"): a rank computes every element with a
  // node it owns, so that each of its nodes sums the forces of all its elements in the serial order
  // (the elements on a rank boundary are computed by both ranks, alike); the other nodes' sums are
  // read by nobody there (the energies sum over each rank's own nodes). A rank holds the state of
  // the stretch of elements from the first it computes to the last alone; at a new deal the state
  // of those it computes anew comes from the ranks that computed them, each element's from the
  // owner of its first node, and a checkpoint gets each element from that rank too.
  struct Share {
    // Per block: the elements this rank computes, by colour as in the block (colour c's are
    // element[offset[c]] to element[offset[c + 1]]), and the stretch from the first to the last.
    struct Computed {
      std::vector<Index> offset, element;
      parallel::Range held;
    };
    std::vector<Computed> blocks;
    // The local nodes from the first of those elements' to the last (force_ and bulk_force_).
    parallel::Range forces;
    discretization::ParticleShare nodes;                    // the local nodes
    // With the velocities by reach: the other ranks' local nodes of the elements this rank
    // computes, and the places from the first of those and its own to the last.
    discretization::ReachShare velocities;
    parallel::Range places_read;  // in the node order, from the first of those and its own to the last
    long long partition = 0;                                // NodeStore::partition planned for
  };
  // Whether this rank owns local node k (its forces are whole here); every node on one process.
  bool owns(Index k) const { return !share_ || share_->nodes.owns(node_[k]); }
  // Whether this rank accounts for element e (its eroded mass and energies, DT2MS's added mass, its
  // hourglass dissipation, its cell in the output and its state in a checkpoint): the owner of its
  // first node, so that each element counts once.
  // book_energies's internal_energy part by part (EnergyLedger::keep_part_work).
  void book_part_work(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                      std::span<const Vec3> v, Real dt) const;
  bool books(const Block& block, Index e) const {
    return !share_ || share_->nodes.owns(node_[block.node[static_cast<std::size_t>(block.nodes_per_element) * e]]);
  }
  // Each held element's state and the held forces as the set-up gives them: on one process at
  // construction, under MPI at the first deal (every rank its own elements' alone).
  void set_up_state(const discretization::NodeStore& nodes);
  // The elements this rank computes in the nodes' present deal. Collective (with the velocities by
  // reach, their plan).
  Share plan_share(const discretization::NodeStore& nodes) const;
  // Makes share_ when the run has several ranks, again when the nodes were dealt anew (after, with
  // the velocities by reach, refresh_nodes, and with a window, hold_nodes): the elements' state then
  // comes to the ranks that compute them now.
  void distribute(discretization::NodeStore& nodes);
  // With the velocities by reach: the position, velocity, mass, activity and live element count of
  // every local node this rank holds a row of, from the rank that computes it in the deal share_
  // was made for (which keeps them current), where a new deal or a checkpoint needs them. Collective.
  void refresh_nodes(discretization::NodeStore& nodes);
  // With NodeStore::window_by_reads: the window of the nodes share_ reads (Share::places_read), the
  // rows this rank lacked brought whole from their ranks. Collective.
  void hold_nodes(discretization::NodeStore& nodes) const;
  // After elements eroded or DT2MS raised masses, unless the velocities go by reach: every rank's
  // nodes' masses, activity and live element counts to every rank.
  void share_masses(discretization::NodeStore& nodes);

  std::vector<PartSettings> parts_;
  std::vector<Block> blocks_;
  std::vector<Index> node_;   // local node -> its place in the node order
  // The elements' internal forces on each local node, and the bulk viscosity's share of them (its
  // work at the nodes' mid-step velocities is what the bulk viscosity dissipates): under MPI of
  // the stretch of local nodes of the elements the rank computes (forces_held).
  RangeArray<Vec3> force_, bulk_force_;
  Real stable_step_ = 0;
  Real max_sound_speed_ = 0;
  Real time_ = 0;           // the sum of the steps taken (FAILTM)
  Real erosion_step_ = 0;   // ERODE: elements below this step are deleted (0: off)
  std::vector<std::int32_t> live_elements_;  // per local node: elements not deleted
  std::vector<Real> other_mass_;             // per local node: the mass other formulations gave it
  // Per local node, the part (index into parts_) its work goes to in matsum.csv: of its elements',
  // the one of the lowest ID.
  std::vector<std::int32_t> node_part_;
  // This step's deletions (booked by book_energies) and the totals; the energies also by part
  // (parts_'s order), for matsum.csv.
  Real eroded_kinetic_step_ = 0, eroded_internal_step_ = 0;
  std::vector<Real> eroded_internal_by_part_, eroded_kinetic_by_part_;
  Real eroded_mass_ = 0;
  std::vector<Id> eroded_now_;  // the IDs of the elements that eroded this step, ascending, of every rank
  discretization::MassScaling mass_scaling_;  // DT2MS
  bool may_erode_ = false;       // some part has an erosion criterion or a material that fails
  bool hourglass_ = false;       // some part's one-point hexahedra have hourglass control
  bool erode_enabled_ = false;   // ERODE
  bool state_set_up_ = false;    // set_up_state, or a checkpoint read
  std::optional<Share> share_;   // under MPI
  // *DATABASE_HISTORY_SOLID: each followed element's block and index, and its place in the IDs.
  struct Followed {
    std::size_t block = 0;
    Index element = 0;
    std::size_t place = 0;
  };
  std::vector<Followed> followed_;
};

}  // namespace spall::fem
