#pragma once
// The problem as the solver runs it, built from a Model: the node store, the formulations, the
// boundary conditions and loads resolved to dense node indices, and the run controls. Building it
// checks everything the solver needs; what it cannot run is an InputError at the card's line.
#include <memory>
#include <vector>

#include "spall/contact/penalty_contact.hpp"
#include "spall/contact/rigid_wall.hpp"
#include "spall/model/model.hpp"
#include "spall/discretization/formulation.hpp"
#include "spall/discretization/node_store.hpp"
#include "spall/rigid/rigid_bodies.hpp"

namespace spall::sph {
class SolidFormulation;
}

namespace spall::solver {

// A prescribed translation of one node in one direction (*BOUNDARY_PRESCRIBED_MOTION_NODE/_SET).
struct NodalMotion {
  Index node = 0;  // its place in the deck (NodeStore::row_of finds its row)
  int direction = 0;  // 0 x, 1 y, 2 z
  int vad = 0;        // 0 velocity, 1 acceleration, 2 displacement
  const model::Curve* curve = nullptr;
  Real sf = 1;
  Real birth = 0, death = 1e28;
};

// A base acceleration a(t) = sf * curve(t) along `direction`; nodes feel -m a (*LOAD_BODY_X/Y/Z).
struct BaseAcceleration {
  int direction = 0;
  const model::Curve* curve = nullptr;
  Real sf = 1;
};

struct RunControls {
  Real end_time = 0;
  long long end_cycle = 0;     // 0: no limit
  Real dt_min_factor = 0;      // stop when dt < DTMIN * dt_initial
  bool erode = false;          // ERODE: delete solids below DTMIN * dt_initial (and inverted ones) instead
  Real end_energy = 0;         // stop when the energy ratio changes by ENDENG percent (0: off)
  Real tssfac = 0.9;
  Real mass_scaling_step = 0;  // |DT2MS| of a negative DT2MS: the step mass scaling brings elements to (0: off)
  Real end_mass_percent = 1e8;  // ENDMAS: stop when the added mass reaches this percentage of the initial mass
  Real dt_initial = 0;         // DTINIT (0: from the stable step)
  const model::Curve* max_dt_curve = nullptr;  // LCTM
  Real d3plot_dt = 0;
  const model::Curve* d3plot_dt_curve = nullptr;  // LCDT
  Real glstat_dt = 0;
  Real rwforc_dt = 0;                             // rigid-wall forces (GLSTAT's interval by default)
  const model::Curve* rwforc_dt_curve = nullptr;  // LCUR
  Real rcforc_dt = 0;                             // contact forces (GLSTAT's interval by default)
  const model::Curve* rcforc_dt_curve = nullptr;  // LCUR
  Real rbdout_dt = 0;                             // rigid bodies (GLSTAT's interval by default)
  const model::Curve* rbdout_dt_curve = nullptr;  // LCUR
  Real nodout_dt = 0;                             // history nodes (GLSTAT's interval by default)
  const model::Curve* nodout_dt_curve = nullptr;  // LCUR
  Real elout_dt = 0;                              // history elements (GLSTAT's interval by default)
  const model::Curve* elout_dt_curve = nullptr;   // LCUR
  // *DATABASE_SPCFORC: the constraints' reactions (spcforc.csv) at its interval; only with the card.
  bool spcforc = false;
  Real spcforc_dt = 0;
  const model::Curve* spcforc_dt_curve = nullptr;  // LCUR
  // *DATABASE_BNDOUT: the prescribed motions' reactions and work (bndout.csv); only with the card.
  bool bndout = false;
  Real bndout_dt = 0;
  const model::Curve* bndout_dt_curve = nullptr;  // LCUR
  // *DATABASE_MATSUM: the energies and momenta of each of `matsum_parts` (every *PART of the deck)
  // in matsum.csv; only with the card.
  bool matsum = false;
  Real matsum_dt = 0;
  const model::Curve* matsum_dt_curve = nullptr;  // LCUR
  std::vector<Id> matsum_parts;
  // *DAMPING_GLOBAL: f = -D(t) m (scale . v), D = damping or damping_curve(t).
  Real damping = 0;
  const model::Curve* damping_curve = nullptr;
  Vec3 damping_scale = Vec3::Zero();
};

struct Problem {
  discretization::NodeStore nodes;
  std::vector<std::unique_ptr<discretization::Formulation>> formulations;
  // The SPH solid among them, if the deck has one: its residual-stress report (seed 000) reads it.
  const sph::SolidFormulation* sph_solid = nullptr;
  std::vector<NodalMotion> motions;
  // *DATABASE_HISTORY_NODE (_SET): the nodes nodout.csv follows, by place in the deck (as the
  // motions' nodes), in the deck's order, each once.
  std::vector<Index> history_nodes;
  // *DATABASE_HISTORY_SOLID: the solid elements elout.csv follows, by ID, in the deck's order, each
  // once (the formulations that compute them follow them: Formulation::follow_elements).
  std::vector<Id> history_solids;
  std::vector<BaseAcceleration> base_accelerations;
  std::vector<contact::RigidWall> rigid_walls;
  std::vector<contact::PenaltyContact> contacts;
  rigid::RigidBodies rigid_bodies;
  RunControls controls;
  const model::Model* model = nullptr;  // curves are owned by the model, which must outlive this
};

// How the set-up holds the nodes under MPI: every node on every rank, or a rank's block of the
// node order where the deck allows (one of SPH fluid alone, whose nodes the time loop deals by
// region: the fluid's first rebuild, or its first step after a restart file is read into the
// block, moves each particle to its region's rank; or one of SPH solid alone, whose blocks the time
// loop keeps as the windows of the nodes; docs/SCALING.md §3). Collective under MPI.
enum class SetUp { whole, in_blocks_where_possible };

// Whether the deck is one that the set-up builds in blocks under MPI (SPH fluid alone, SPH solid
// alone or SPG alone: no other element, rigid part, contact or coordinate system on nodes): such a
// deck can be read in shares (model::CardShare), every other needs every card on every rank
// (Model::gather_cards).
// Collective where the model holds a share of the cards.
bool sets_up_in_blocks(const model::Model& model);

// Builds the problem; throws InputError for anything the solver cannot run.
Problem build_problem(const model::Model& model, SetUp set_up = SetUp::whole);

}  // namespace spall::solver
