#pragma once
// A discretization plugged into the step (SPH fluid, SPH solid, SPG, FEM). It owns its own
// state (densities, stresses, bonds ...) and adds its internal forces to the shared node store.
#include <cstdint>
#include <span>
#include <utility>
#include <vector>

#include "spall/core/archive.hpp"
#include "spall/core/parallel.hpp"
#include "spall/core/types.hpp"
#include "spall/discretization/energy_ledger.hpp"
#include "spall/discretization/field_set.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/discretization/part_summary.hpp"

namespace spall::discretization {

// An element's values in elout.csv: the stress xx yy zz xy yz zx, the pressure, the von Mises
// stress, the effective plastic strain (each the mean over its integration points) and 1 once it
// has eroded (else 0).
inline constexpr int element_history_values = 10;

class Formulation {
 public:
  virtual ~Formulation() = default;

  virtual const char* name() const = 0;

  // Advances the formulation's state over `dt` (the step just taken, 0 at the first call) with the
  // current positions x^n and velocities v^{n-1/2}, then adds the internal forces at x^n to
  // nodes.f.
  virtual void compute_forces(NodeStore& nodes, Real dt) = 0;

  // The largest stable step, before TSSFAC, for the state of the last compute_forces (a
  // formulation may find it there; the step asks right after, with the same nodes).
  virtual Real stable_time_step(const NodeStore& nodes) const = 0;

  // Books dt times the power of the last internal forces at the node velocities v (mid-step
  // velocities, one a row of `nodes`) into the ledger: the stored (strain) energy and whatever the
  // formulation dissipates (artificial viscosity, hourglass control ...). Called every step, from
  // the first, so that the formulation's terms are registered before the first output. A
  // formulation whose material points hold no energy that follows this work (sum_parts) books its
  // stored share part by part too when the ledger keeps part work (EnergyLedger::keep_part_work).
  virtual void book_energies(EnergyLedger& ledger, const NodeStore& nodes, std::span<const Vec3> v, Real dt) const = 0;

  // *DATABASE_MATSUM: adds to `parts`, under each particle's or element's part, the internal energy
  // its material points hold, m (e - e0), the hourglass energy of its elements and the mass DT2MS
  // added to them: of those this rank accounts for (its own particles, the elements it books), at
  // an output.
  virtual void sum_parts(PartSummary& /*parts*/, const NodeStore& /*nodes*/) const {}

  // Writes the formulation's output fields (pressure, von Mises stress, density, ...) for its own
  // nodes, and its cells if it has any: those whose first node this rank owns (NodeStore::owns),
  // which its piece of the output holds (every cell on one process).
  virtual void write_fields(FieldSet& fields, const NodeStore& nodes) const = 0;

  // Largest signal speed, for the runaway-velocity check.
  virtual Real max_wave_speed() const = 0;

  // *CONTROL_TIMESTEP ERODE: from now on, delete the elements (or particles) whose own stable step
  // falls below `step` rather than let the run stop. A formulation that cannot delete ignores it.
  virtual void erode_below(Real /*step*/) {}
  // The deck IDs of the elements that eroded in this step's compute_forces, ascending, the same on
  // every rank (the contacts' surfaces follow them).
  virtual std::span<const Id> eroded_elements() const { return {}; }

  // *CONTROL_TIMESTEP DT2MS < 0, LS-DYNA's conventional mass scaling: from now on, an element (a
  // particle) whose own stable step is below `step` gets the mass that raises its step to `step`;
  // the mass goes to its nodes and stays there, and book_energies reports it as added_mass. With
  // `first_step_only` (MS1ST) only the first step adds mass. False from a formulation that cannot
  // scale its mass.
  virtual bool scale_mass_below(Real /*step*/, bool /*first_step_only*/) { return false; }

  // Under MPI the nodes are dealt out to the ranks (NodeStore::owns; replicated state,
  // docs/SCALING.md): a formulation computes the forces and the state of its owned nodes only, takes
  // global decisions over the ranks, and here brings in every rank's new state of its own nodes,
  // once a step (the time loop's halo phase).
  virtual void share_state(NodeStore& /*nodes*/) {}
  // True when share_state also brings in the velocities of the other ranks' nodes that the
  // formulation reads, and those are all it reads of them until it completes them itself: the
  // time loop then need not share every node's velocity (the halo by reach).
  virtual bool halo_by_reach() const { return false; }
  // With the halo by reach, in blocks of the nodes: a range of rows that holds every other rank's
  // node whose position the formulation reads before it completes them (others in the range may be
  // stale): the time loop advances those and a rank's own, no more. Every row unless told.
  virtual parallel::Range rows_read(const NodeStore& nodes) const { return {0, nodes.size()}; }
  // True when, the one formulation of a deck in blocks with the halo by reach, it can hold a
  // window of the nodes (NodeStore::hold_window) of its own and those it reads, which it brings in,
  // and read no other: the time loop then sets NodeStore::window_by_reads.
  virtual bool holds_window() const { return false; }
  // True when the formulation's results do not depend on which rank computes which node, nor on
  // the order it holds them in, and it calls NodeStore::migrate for its nodes whenever every rank
  // holds their positions current: a deck of such formulations alone has its nodes dealt by region
  // (docs/SCALING.md §3, "Ownership by region").
  virtual bool migrates() const { return false; }
  // Whether the forces it adds include those on the nodes an SPC holds in every direction, whose
  // reactions spcforc.csv sums (-f there); the SPH fluid's wall particles take none.
  virtual bool forces_on_held_nodes() const { return true; }
  // *DATABASE_HISTORY_SOLID: follows those of the elements `ids` that it computes, marking each in
  // `taken` (at the set-up, on every rank alike). element_histories then writes the values of
  // elout.csv (element_history_values each, at the element's place in `ids`) of those this rank
  // accounts for, leaving the others as they are.
  virtual void follow_elements(std::span<const Id> /*ids*/, std::vector<std::uint8_t>& /*taken*/) {}
  virtual void element_histories(std::span<double> /*values*/) const {}
  // Under MPI, on every rank before one of them writes a checkpoint: brings in what the
  // formulation keeps current only where a rank computes it (the state of solid elements with no
  // node of the rank's, the positions and velocities of particles far from a rank's), so that the
  // state is whole on rank 0, which writes (dealt by region, where a rank holds rows of its own,
  // each rank's own state goes to it in pieces instead: core/pieces.hpp).
  virtual void complete_state(NodeStore& /*nodes*/) {}
  // Under MPI with nodes dealt in blocks, on every rank before the fields and reports are written:
  // brings in what they read beyond a rank's own nodes; all that a checkpoint needs unless the
  // formulation's fields and reports of its own nodes are current where they are computed (a
  // piece's nodes that another rank computes take that rank's fields: solver/field_output.cpp).
  virtual void complete_for_output(NodeStore& nodes) { complete_state(nodes); }
  // Writes (or reads back) everything the formulation carries from one step to the next, so that a
  // run continued from a checkpoint is bitwise the uninterrupted one (core/archive.hpp). Under MPI
  // every rank calls it, rank 0 with the archive it writes (collective); `nodes` were checkpointed
  // just before.
  virtual void checkpoint(Archive& archive, const NodeStore& nodes) = 0;
};

}  // namespace spall::discretization
