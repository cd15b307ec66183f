#include "run_outputs.hpp"

namespace spall::cli {

namespace fs = std::filesystem;
using io::output::Column;

RunOutputs::RunOutputs(const fs::path& out, const solver::Problem& problem, const model::Model& model, bool resume)
    : out_(out), problem_(problem), fields_(out) {
  // glstat.csv: time, dt, the energy ledger's terms (whoever produces a term registers it in the
  // first step, before the first row), the total and the energy ratio.
  glstat_.path = out / "glstat.csv";
  // Forces on the rigid walls, one row per wall and output time; only when the deck has walls.
  if (!problem.rigid_walls.empty()) {
    rwforc_.path = out / "rwforc.csv";
    rwforc_.columns = {{"time", "time"}, {"wall", ""}, {"normal_force", "force"},
                       {"fx", "force"},  {"fy", "force"}, {"fz", "force"}};
  }
  // Forces of the penalty contacts on each side (1: SURFA, 2: SURFB), with their moments about the
  // *DATABASE_RCFORC_MOMENT node, or the side's rigid-body centre, or the origin; only with contacts.
  if (!problem.contacts.empty()) {
    rcforc_.path = out / "rcforc.csv";
    rcforc_.columns = {{"time", "time"}, {"contact", ""}, {"side", ""}};
    for (const char* name : {"fx", "fy", "fz"}) rcforc_.columns.push_back({name, "force"});
    for (const char* name : {"mx", "my", "mz"}) rcforc_.columns.push_back({name, "force*length"});
    for (const char* name : {"px", "py", "pz"}) rcforc_.columns.push_back({name, "length"});
  }
  // The rigid bodies' motion and the forces on them, at the RBDOUT interval (GLSTAT's without the
  // card); only with bodies.
  if (!problem.rigid_bodies.empty()) {
    rbdout_.path = out / "rbdout.csv";
    rbdout_.columns = {{"time", "time"}, {"part", ""}};
    for (const char* name : {"x", "y", "z"}) rbdout_.columns.push_back({name, "length"});
    for (const char* name : {"vx", "vy", "vz"}) rbdout_.columns.push_back({name, "velocity"});
    for (const char* name : {"wx", "wy", "wz"}) rbdout_.columns.push_back({name, "1/time"});
    for (const char* name : {"fx", "fy", "fz"}) rbdout_.columns.push_back({name, "force"});
    for (const char* name : {"mx", "my", "mz"}) rbdout_.columns.push_back({name, "force*length"});
  }
  // The history nodes' motion (*DATABASE_HISTORY_NODE), a row per node and output time at the NODOUT
  // interval (GLSTAT's without the card): LS-DYNA's nodout displacements, velocities, accelerations
  // and coordinates; only with history nodes.
  if (!problem.history_nodes.empty()) {
    nodout_.path = out / "nodout.csv";
    nodout_.columns = {{"time", "time"}, {"node", ""}};
    for (const char* name : {"ux", "uy", "uz"}) nodout_.columns.push_back({name, "length"});
    for (const char* name : {"vx", "vy", "vz"}) nodout_.columns.push_back({name, "velocity"});
    for (const char* name : {"ax", "ay", "az"}) nodout_.columns.push_back({name, "length/time^2"});
    for (const char* name : {"x", "y", "z"}) nodout_.columns.push_back({name, "length"});
  }
  // The history elements' stress (*DATABASE_HISTORY_SOLID), a row per element and output time at
  // the ELOUT interval (GLSTAT's without the card): LS-DYNA's elout stresses of solids, the mean
  // over the element's points; only with history elements.
  if (!problem.history_solids.empty()) {
    elout_.path = out / "elout.csv";
    elout_.columns = {{"time", "time"}, {"element", ""}};
    for (const char* name : {"sxx", "syy", "szz", "sxy", "syz", "szx", "pressure", "von_mises"})
      elout_.columns.push_back({name, "stress"});
    elout_.columns.push_back({"effective_plastic_strain", ""});
    elout_.columns.push_back({"eroded", ""});
  }
  // The prescribed motions' reactions (*DATABASE_BNDOUT, only with the card) at its interval: the
  // resultant and the work done since the start, LS-DYNA's bndout totals of nodal motions.
  if (problem.controls.bndout) {
    bndout_.path = out / "bndout.csv";
    bndout_.columns = {{"time", "time"}};
    for (const char* name : {"fx", "fy", "fz"}) bndout_.columns.push_back({name, "force"});
    bndout_.columns.push_back({"work", "energy"});
  }
  // The parts' energies and momenta (*DATABASE_MATSUM, only with the card), a row per part and
  // output time at its interval: LS-DYNA's matsum.
  if (problem.controls.matsum) {
    matsum_.path = out / "matsum.csv";
    matsum_.columns = {{"time", "time"}, {"part", ""}};
    for (const std::string_view name : discretization::PartSummary::names)
      matsum_.columns.push_back({std::string(name), name.ends_with("momentum") ? "mass*length/time"
                                                    : name == "added_mass"       ? "mass"
                                                                                 : "energy"});
  }
  // The resultant of the SPCs' reactions (*DATABASE_SPCFORC, only with the card) at its interval:
  // LS-DYNA's spcforc resultant.
  if (problem.controls.spcforc) {
    spcforc_.path = out / "spcforc.csv";
    spcforc_.columns = {{"time", "time"}};
    for (const char* name : {"fx", "fy", "fz"}) spcforc_.columns.push_back({name, "force"});
  }
  // Residual stress of the SPH solids per part and category (seed 000), at the end of the run and,
  // on request, at every field output.
  solid_ = problem.sph_solid;
  residual_options_ = model.sph_residual_stress.value_or(model::SphResidualStress{});
  if (resume) return;
  for (History* h : {&rwforc_, &rcforc_, &rbdout_, &nodout_, &spcforc_, &elout_, &bndout_, &matsum_})
    if (!h->columns.empty()) open(*h);
  if (solid_) residual_.emplace(out / "residual.csv", *solid_, residual_options_);
}

void RunOutputs::write_fields(const solver::StepInfo& step, const solver::Problem& p) {
  fields_.write(step, p);
  if (residual_) residual_->at_field_output(step.time);
}

fs::path RunOutputs::last_field_file() const { return fields_.last_file(); }

std::optional<std::string> RunOutputs::finish(double end_time) {
  if (!residual_) return std::nullopt;
  return residual_->finish(end_time);
}

solver::Observer RunOutputs::observer() {
  solver::Observer observer;
  observer.on_field_output = [this](const solver::StepInfo& step, const solver::Problem& p) { write_fields(step, p); };
  observer.on_history = [this](const solver::StepInfo& step, const discretization::EnergyLedger& e) {
    using Role = discretization::EnergyLedger::Role;
    if (!glstat_.file) {
      glstat_.columns = {{"time", "time"}, {"dt", "time"}};
      for (const auto& term : e.terms()) glstat_.columns.push_back({term.name, term.role == Role::reported ? "mass" : "energy"});
      glstat_.columns.push_back({"total_energy", "energy"});
      glstat_.columns.push_back({"energy_ratio", ""});
      open(glstat_);
    }
    std::vector<double> row{step.time, step.dt};
    for (const auto& term : e.terms()) row.push_back(term.value);
    masses_.clear();
    for (const auto& term : e.terms())
      if (term.role == Role::reported) masses_.emplace_back(term.name, term.value);
    row.push_back(e.total());
    row.push_back(e.ratio());
    glstat_.file->append(row);
  };
  observer.on_rigid_bodies = [this](const solver::StepInfo& step, const rigid::RigidBodies& bodies) {
    for (const auto& body : bodies.bodies()) {
      std::vector<double> r{step.time, static_cast<double>(body.part_id)};
      for (const Vec3* v : {&body.step_centre, &body.velocity, &body.angular_velocity, &body.force, &body.moment})
        r.insert(r.end(), v->data(), v->data() + 3);
      rbdout_.file->append(r);
    }
  };
  observer.on_node_histories = [this](const solver::StepInfo& step, const std::vector<solver::NodeHistory>& nodes) {
    for (const auto& node : nodes) {
      std::vector<double> r{step.time, static_cast<double>(node.id)};
      for (const Vec3* v : {&node.displacement, &node.velocity, &node.acceleration, &node.position})
        r.insert(r.end(), v->data(), v->data() + 3);
      nodout_.file->append(r);
    }
  };
  observer.on_element_histories = [this](const solver::StepInfo& step,
                                         const std::vector<solver::ElementHistory>& elements) {
    for (const auto& e : elements) {
      std::vector<double> r{step.time, static_cast<double>(e.id)};
      r.insert(r.end(), e.stress.begin(), e.stress.end());
      r.insert(r.end(), {e.pressure, e.von_mises, e.plastic_strain, e.eroded ? 1.0 : 0.0});
      elout_.file->append(r);
    }
  };
  observer.on_motion_reaction = [this](const solver::StepInfo& step, const Vec3& reaction, Real work) {
    const double row[] = {step.time, reaction.x(), reaction.y(), reaction.z(), work};
    bndout_.file->append(row);
  };
  observer.on_part_summary = [this](const solver::StepInfo& step, const discretization::PartSummary& parts) {
    using Summary = discretization::PartSummary;
    for (std::size_t k = 0; k < parts.parts().size(); ++k) {
      std::vector<double> row{step.time, static_cast<double>(parts.parts()[k])};
      for (int q = 0; q < Summary::quantity_count; ++q) row.push_back(parts.value(k, Summary::Quantity(q)));
      matsum_.file->append(row);
    }
  };
  observer.on_spc_reaction = [this](const solver::StepInfo& step, const Vec3& reaction) {
    const double row[] = {step.time, reaction.x(), reaction.y(), reaction.z()};
    spcforc_.file->append(row);
  };
  observer.on_rigid_wall_forces = [this](const solver::StepInfo& step, const std::vector<contact::RigidWall>& walls) {
    for (const auto& wall : walls) {
      const Vec3& f = wall.force();
      const double row[] = {step.time, static_cast<double>(wall.definition().id), wall.normal_force(), f.x(), f.y(), f.z()};
      rwforc_.file->append(row);
    }
  };
  observer.on_contact_forces = [this](const solver::StepInfo& step, const std::vector<contact::PenaltyContact>& contacts) {
    for (const auto& c : contacts)
      for (int side = 0; side < 2; ++side) {
        const auto& r = side == 0 ? c.side_a() : c.side_b();
        const std::int32_t body = c.definition().side_body[side];
        const Index node = c.definition().moment_node[side];
        const Vec3 p = node >= 0   ? problem_.nodes.x[node]
                       : body >= 0 ? problem_.rigid_bodies.bodies()[body].step_centre
                                   : Vec3::Zero();
        const Vec3 m = r.moment - p.cross(r.force);
        std::vector<double> row{step.time, static_cast<double>(c.definition().id), double(side + 1)};
        for (const Vec3* v : {&r.force, &m, &p}) row.insert(row.end(), v->data(), v->data() + 3);
        rcforc_.file->append(row);
      }
  };
  return observer;
}

void RunOutputs::checkpoint(Archive& a) {
  a.section("output files 6");
  a(masses_, glstat_.columns);
  for (History* h : {&glstat_, &rwforc_, &rcforc_, &rbdout_, &nodout_, &spcforc_, &elout_, &bndout_, &matsum_}) {
    std::optional<std::uint64_t> bytes;
    if (h->file) bytes = h->file->bytes();
    a(bytes);
    if (a.reading() && bytes) h->file.emplace(h->path, h->columns, *bytes);
  }
  std::optional<std::uint64_t> residual_bytes;
  if (residual_) residual_bytes = residual_->bytes();
  a(residual_bytes);
  if (a.reading() && residual_bytes) residual_.emplace(out_ / "residual.csv", *solid_, residual_options_, *residual_bytes);
}

}  // namespace spall::cli
