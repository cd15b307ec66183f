#pragma once
// *CONTROL_TIMESTEP DT2MS < 0 (docs/THEORY.md §1, mass scaling): the step a formulation raises its
// elements' (particles') steps to, and the mass it has added so far, for the ledger's added_mass.
#include "spall/core/types.hpp"

namespace spall::discretization {

struct MassScaling {
  Real step = 0;                 // the target stable step, |DT2MS| (0: off)
  bool active = false;           // mass is added on this step
  bool first_step_only = false;  // MS1ST
  Real added = 0;                // in all
  Real added_this_step = 0;

  void start(Real target, bool only_first) { *this = {target, true, only_first}; }
  // After a step that added mass: `total` is what has been added in all.
  void record(Real total) {
    added_this_step = total - added;
    added = total;
    active = !first_step_only;
  }
  // After a step that added none.
  void idle() { added_this_step = 0; }
};

}  // namespace spall::discretization
