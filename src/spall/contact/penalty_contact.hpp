#pragma once
// Penalty contact of nodes with segments, with Coulomb friction (*CONTACT_NODES_TO_SURFACE,
// _AUTOMATIC_NODES_TO_SURFACE, _AUTOMATIC_SURFACE_TO_SURFACE, _AUTOMATIC_SINGLE_SURFACE;
// fem-contact.md §2.6-2.8, docs/THEORY.md §12). In the contact phase of each step, every slave
// node finds the closest point of the master segments near it; behind that segment (and not
// deeper than the release depth) it is pushed out by f_n = k g - c v_n along the segment's normal,
// and friction follows an elastic predictor and Coulomb return: F* = F_t - k dt v_t, |F_t| <=
// mu f_n (and <= VC A). The reaction goes to the segment's corners with the weights of the contact
// point. The slave node may be of any formulation (SPH, SPG, FEM, rigid), the segments faces of
// any solid mesh (FEM, SPG, rigid). Each node takes its forces in slave order and the resultants
// are exact sums: the same for any thread count, and for any MPI rank count (each rank finds,
// answers and keeps the touches of its own slave nodes and sends the terms on other ranks' nodes
// to them: docs/SCALING.md §3, "Contact touches by rank").
#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include "spall/contact/segment.hpp"
#include "spall/contact/segment_grid.hpp"
#include "spall/core/archive.hpp"
#include "spall/core/exact_sum.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/energy_ledger.hpp"
#include "spall/discretization/node_store.hpp"

namespace spall::contact {

class PenaltyContact {
 public:
  // Coulomb friction with exponential decay (card 2, scaled by FSF and VSF on card 3).
  struct Friction {
    Real static_coefficient = 0;   // FSF FS
    Real dynamic_coefficient = 0;  // FSF FD (with DC > 0 only)
    Real decay = 0;                // DC, per unit sliding speed
    Real viscous_limit = 0;        // VSF VC: |F_t| <= VSF VC A, A the segment's area (0: no limit)

    // mu = FD + (FS - FD) exp(-DC |v_t|); FS alone when DC = 0.
    Real coefficient(Real sliding_speed) const;
  };

  struct Definition {
    Id id = 0;                 // CID, or the contact's place in the deck
    Friction friction;
    Real damping = 0;          // VDC / 100: the fraction of critical damping of the normal spring
    int soft = 0;              // 0 standard penalty, 1 soft constraint
    Real soft_scale = 0.1;     // SOFSCL
    int penopt = 1;            // 1 the smaller of node and segment stiffness, 2 segment, 3 node
    Real release_depth = 0.4;  // a node deeper than this many segment thicknesses is let go
    Real edge_tolerance = 0.025;  // MAXPAR - 1: how far beyond an edge, in segment sizes, a node touches
    Real stiffness_step = 0;   // DTSTIF: the step of the SOFT 1 stiffness (0: the first step)
    Real birth = 0, death = 1e20;
    // The rigid body (index in the node store's `body`) that all of side A's, and of side B's,
    // nodes belong to, or NodeStore::no_body: rcforc.csv takes a body's moments about its centre.
    std::array<std::int32_t, 2> side_body{discretization::NodeStore::no_body, discretization::NodeStore::no_body};
    // *DATABASE_RCFORC_MOMENT: the node (store index) about which rcforc.csv takes each side's
    // moment instead, or -1.
    std::array<Index, 2> moment_node{-1, -1};
  };

  // The solid elements (deck IDs) a segment follows as elements erode: the one whose face it is,
  // which takes it out of the contact as it erodes, and for a face inside the body (an eroding
  // contact's EROSOP 1) the element beyond it, which brings it in. 0: none (a shell; a face with
  // nothing beyond).
  struct FaceElements {
    Id own = 0;
    Id beyond = 0;
  };

  // One search of slave nodes against master segments; a surface-to-surface contact makes two.
  struct Pass {
    std::vector<Index> slave;           // node-store indices, ascending
    std::vector<Real> slave_stiffness;  // SOFT 0 stiffness of each slave node, SLSFAC SFS K V^(1/3)
    std::vector<Segment> segment;
    std::vector<FaceElements> elements;  // of each segment
    bool slaves_are_side_a = true;      // SURFA's nodes against SURFB's segments; false: the reverse
  };

  // The resultant of the contact forces on one side's nodes, and its moment about the origin.
  struct Resultant {
    Vec3 force = Vec3::Zero();
    Vec3 moment = Vec3::Zero();
  };

  PenaltyContact(const Definition& definition, std::vector<Pass> passes);

  // The first step of the run: the step of the SOFT 1 stiffness 0.5 SOFSCL m* / dt^2 unless
  // DTSTIF gave one.
  void set_first_step(Real dt) {
    if (!(definition_.stiffness_step > 0)) stiffness_step_ = dt;
  }

  // The solid elements that eroded this step (deck IDs, ascending, the same on every rank): their
  // faces leave the contact, and a face inside the body whose element beyond them eroded enters it.
  void erode(std::span<const Id> elements);

  // Adds the contact forces at x^n to nodes.f. t is t^n (for birth and death), dt the last step,
  // over which the velocities v^{n-1/2} slid.
  void apply(discretization::NodeStore& nodes, Real t, Real dt);

  // Books dt times the power of this step's forces at the velocities v (v^n): the normal part as
  // contact_energy (the penalty springs and their damping), the tangential part as friction_energy.
  // Each rank sums the touches of its own slave nodes, whose v^n it holds, exactly, and the sums are
  // taken over the ranks (collective): the same for any partition.
  void book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                     std::span<const Vec3> v, Real dt) const;

  // Whether every segment's corners, and the nodes rcforc.csv takes moments about, move with a
  // rigid body (a tool's surface): then a rank reads only its own slave nodes and the bodies' nodes,
  // which every rank moves, and the time loop may share only the velocities the formulations read
  // (the halo by reach).
  bool segments_rigid(const discretization::NodeStore& nodes) const;

  const Definition& definition() const { return definition_; }
  void set_moment_nodes(const std::array<Index, 2>& nodes) { definition_.moment_node = nodes; }
  const Resultant& side_a() const { return side_[0]; }
  const Resultant& side_b() const { return side_[1]; }
  // How many slave nodes touch a segment now (under MPI, of this rank's own).
  Index touching() const;
  // Under MPI every rank's touches (their friction) to every rank, where a checkpoint needs them.
  void complete_state();

  // The friction state, the first step's stiffness and the last resultants.
  void checkpoint(Archive& a) {
    a.expect_size("contact passes", passes_.size());
    a(passes_, stiffness_step_, side_[0].force, side_[0].moment, side_[1].force, side_[1].moment);
  }

  static constexpr std::string_view contact_energy = "contact_energy";
  static constexpr std::string_view friction_energy = "friction_energy";

 private:
  // A slave node on a segment this step.
  struct Touch {
    Index slave = 0;    // position in the pass's slave list
    Index segment = 0;
    std::array<Real, 4> weight{};
    Vec3 normal = Vec3::UnitZ();
    Real normal_force = 0;            // >= 0, along the normal, on the slave
    Vec3 friction = Vec3::Zero();     // tangential force on the slave
    // x^n of the slave node, from the rank that answered it (for the moment of its side's
    // resultant; with the halo by reach the other ranks' may be stale). Not kept between steps.
    Vec3 slave_position = Vec3::Zero();
    // The depth at which a node was found deeper than one step's approach brings it (a node the
    // contact had let go of, caught again), shrinking as it comes out: only the depth beyond it
    // pushes (THEORY §12.3). Negative until the first response.
    Real tracked_depth = -1;
    void checkpoint(Archive& a) { a(slave, segment, weight, normal, normal_force, friction, tracked_depth); }
  };

  // A segment's part in the search: a face inside the body waits until the element beyond it
  // erodes; a face whose own element eroded is gone for good.
  enum Status : std::uint8_t { waiting, live, gone };

  struct PassState {
    Pass pass;
    std::vector<std::uint8_t> status;  // Status of each segment
    SegmentGrid grid;
    std::vector<Real> reach;          // release depth of each segment
    std::vector<Real> grow;           // how far the grid grows each segment's box: reach + offset
    std::vector<std::int32_t> found;  // per slave: the segment it touches, or -1
    std::vector<Touch> touches, previous;
    bool started = false;  // a step of this contact has been taken: the first step's touches are not tracked
    // The touches of the last step (their friction carries over); the grid is rebuilt every step.
    void checkpoint(Archive& a) { a(status, reach, found, touches, previous, started); }
  };

  void search(PassState& state, const discretization::NodeStore& nodes) const;
  void respond(PassState& state, const discretization::NodeStore& nodes, Real dt) const;
  void complete_touches(PassState& state) const;
  void gather(const PassState& state, discretization::NodeStore& nodes, std::array<ExactSum, 12>& sums);

  Definition definition_;
  std::vector<PassState> passes_;
  Real stiffness_step_ = 0;
  Resultant side_[2];
  long long partition_ = -1;  // NodeStore::partition of the last step: its touches are its own slaves'
};

}  // namespace spall::contact
