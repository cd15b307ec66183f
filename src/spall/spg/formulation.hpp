#pragma once
// The Smoothed Particle Galerkin formulation (seed 001 §2): one formulation owns every SPG part
// (DESIGN.md); each part keeps its own bonds, shape functions and kernel-update schedule
// (spg/part.hpp), and parts couple through shared nodes.
#include <vector>

#include "spall/solver/formulation.hpp"
#include "spall/spg/part.hpp"

namespace spall::spg {

class SpgFormulation final : public solver::Formulation {
 public:
  explicit SpgFormulation(std::vector<Part> parts) : parts_(std::move(parts)) {}

  const char* name() const override { return "SPG"; }
  void compute_forces(solver::NodeStore& nodes, Real dt) override;
  Real stable_time_step(const solver::NodeStore& nodes) const override;
  Power internal_power(std::span<const Vec3> v) const override;
  void add_fields(std::vector<io::output::PointField>& fields,
                  const solver::NodeStore& nodes) const override;
  Real max_wave_speed() const override;

  const std::vector<Part>& parts() const { return parts_; }
  Index particle_count() const;
  std::size_t memory_bytes() const;

 private:
  std::vector<Part> parts_;
};

}  // namespace spall::spg
