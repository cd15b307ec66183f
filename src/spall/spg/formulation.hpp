#pragma once
// The Smoothed Particle Galerkin formulation (seed 001 §2): one formulation owns every SPG part
// (DESIGN.md); each part keeps its own bonds, shape functions and kernel-update schedule
// (spg/part.hpp), and parts couple through shared nodes.
#include <vector>

#include "spall/discretization/formulation.hpp"
#include "spall/spg/part.hpp"

namespace spall::spg {

class SpgFormulation final : public discretization::Formulation {
 public:
  explicit SpgFormulation(std::vector<Part> parts) : parts_(std::move(parts)) {}

  const char* name() const override { return "SPG"; }
  void compute_forces(discretization::NodeStore& nodes, Real dt) override;
  Real stable_time_step(const discretization::NodeStore& nodes) const override;
  void book_energies(discretization::EnergyLedger& ledger, const discretization::NodeStore& nodes,
                     std::span<const Vec3> v, Real dt) const override;
  // The mass DT2MS added to each part (the parts' internal energies are the ledger's work by part:
  // book_energies).
  void sum_parts(discretization::PartSummary& parts, const discretization::NodeStore& nodes) const override;
  void write_fields(discretization::FieldSet& fields, const discretization::NodeStore& nodes) const override;
  Real max_wave_speed() const override;
  bool scale_mass_below(Real step, bool first_step_only) override;
  void complete_state(discretization::NodeStore& nodes) override;
  // Each part brings in the velocities its smoothing reads (Part::share_velocities).
  void share_state(discretization::NodeStore& nodes) override;
  bool halo_by_reach() const override { return true; }
  parallel::Range rows_read(const discretization::NodeStore& nodes) const override;
  // Alone in a deck, each rank holds the window of the node order from the first of its own nodes
  // and of every part's nodes it reads to the last (hold_nodes), each part calling for it where it
  // plans what it reads anew (the first deal, a new deal, a kernel update).
  bool holds_window() const override { return true; }
  // The fields read a rank's own particles alone, and the bonds, which every rank keeps current.
  void complete_for_output(discretization::NodeStore& /*nodes*/) override {}
  void checkpoint(Archive& archive, const discretization::NodeStore& nodes) override;

  const std::vector<Part>& parts() const { return parts_; }
  Index particle_count() const;
  std::size_t memory_bytes() const;

 private:
  // With NodeStore::window_by_reads, the window of this rank's own nodes, the nodes each part
  // reads (Part::places_read) and `places` (collective).
  void hold_nodes(discretization::NodeStore& nodes, parallel::Range places) const;

  std::vector<Part> parts_;
  bool mass_scaled_ = false;  // DT2MS
};

}  // namespace spall::spg
