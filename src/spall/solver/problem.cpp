#include "spall/solver/problem.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fmt/format.h>
#include <optional>
#include <set>
#include <span>
#include <stdexcept>
#include <type_traits>
#include <unordered_map>
#include <utility>

#include "spall/contact/setup.hpp"
#include "spall/core/bounding_box.hpp"
#include "spall/core/communicator.hpp"
#include "spall/core/first_failure.hpp"
#include "spall/core/log.hpp"
#include "spall/materials/make_material.hpp"
#include "spall/neighbors/verlet_list.hpp"
#include "spall/sph/fluid_setup.hpp"
#include "spall/fem/setup.hpp"
#include "spall/rigid/setup.hpp"
#include "spall/spg/setup.hpp"
#include "spall/solver/nodes_in_blocks.hpp"
#include "spall/solver/set_up_messages.hpp"
#include "spall/sph/solid.hpp"

namespace spall::solver {

namespace {

// Drops each entry whose key an earlier entry has: the first of each stays, in its place.
template <class T, class Key>
void keep_first_of_each(std::vector<T>& entries, Key key) {
  std::set<std::invoke_result_t<Key&, const T&>> seen;
  std::erase_if(entries, [&](const T& entry) { return !seen.insert(key(entry)).second; });
}

class Builder {
 public:
  Builder(const model::Model& model, SetUp set_up)
      : model_(model), in_blocks_(set_up == SetUp::in_blocks_where_possible && sets_up_in_blocks(model)) {
    if (!in_blocks_ && !model.cards.whole())
      throw std::logic_error("set-up: the model holds a share of the cards but is not set up in blocks");
  }

  Problem build() {
    problem_.model = &model_;
    build_nodes();
    build_sph();
    std::vector<Index>().swap(model_node_);  // read by build_sph alone
    if (auto spg = build_spg()) problem_.formulations.push_back(std::move(spg));
    if (auto fem = fem::build_fem(model_, index_of_node_, problem_.nodes))
      problem_.formulations.push_back(std::move(fem));
    rigid::add_rigid_masses(model_, index_of_node_, problem_.nodes);
    apply_spcs();
    build_motions();
    build_history_nodes();
    build_history_solids();
    apply_initial_velocities();
    problem_.rigid_bodies = rigid::build_rigid_bodies(model_, index_of_node_, problem_.nodes);
    problem_.contacts = contact::build_contacts(model_, index_of_node_, problem_.nodes);
    build_loads();
    build_rigid_walls();
    build_controls();
    if (problem_.controls.mass_scaling_step > 0) scale_masses();
    if (in_blocks_ && (problem_.formulations.size() != 1 || !problem_.rigid_bodies.empty() ||
                       !problem_.contacts.empty() ||
                       !(problem_.formulations.front()->migrates() || problem_.formulations.front()->holds_window())))
      throw std::logic_error("set-up in blocks: the deck is not one of SPH fluid, SPH solid or SPG alone");
    return std::move(problem_);
  }

 private:
  // The row of the node at `deck` in the node order, -1 when this rank's block does not hold it
  // (every node is a row of its own index when the set-up is whole).
  Index row(Index deck) const {
    const Index r = deck - first_row_;
    return r >= 0 && r < problem_.nodes.size() ? r : -1;
  }
  // The rows of the nodes at `decks` that this rank holds.
  std::vector<Index> rows(const std::vector<Index>& decks) const {
    std::vector<Index> held;
    for (const Index deck : decks)
      if (const Index r = row(deck); r >= 0) held.push_back(r);
    return held;
  }

  // The node's place in the node order (its row when the set-up is whole).
  Index node_index(Id id, const SourceLocation& where, const char* keyword) const {
    const Index* place = nullptr;
    if (!in_blocks_) {
      place = index_of_node_.find(id);
    } else if (const auto named = std::lower_bound(named_.begin(), named_.end(), std::pair(id, Index(-1)));
               named != named_.end() && named->first == id) {
      place = &named->second;
    }
    if (!place) fail_at(where, keyword, set_up_message::no_such_node(id));
    return *place;
  }

  const model::Curve* curve(Id id, const SourceLocation& where, const char* keyword,
                            const char* field) const {
    if (id == 0) return nullptr;
    auto it = model_.curves.find(id);
    if (it == model_.curves.end())
      fail_at(where, keyword, fmt::format("{}: curve {} does not exist", field, id));
    return &it->second;
  }

  std::vector<Index> node_set(Id id, const SourceLocation& where, const char* keyword) const {
    auto it = model_.node_sets.find(id);
    if (it == model_.node_sets.end())
      fail_at(where, keyword, fmt::format("node set {} does not exist", id));
    std::vector<Index> nodes;
    for (Id n : it->second.nodes) nodes.push_back(node_index(n, it->second.where, "*SET_NODE"));
    return nodes;
  }

  // The rows of the part's nodes.
  std::vector<Index> part_nodes(Id part_id, const SourceLocation& where, const char* keyword) const {
    if (!model_.find_part(part_id)) fail_at(where, keyword, fmt::format("part {} does not exist", part_id));
    std::vector<Index> nodes;
    for (Index i = 0; i < problem_.nodes.size(); ++i)
      if (problem_.nodes.part[i] == part_id) nodes.push_back(i);
    return nodes;
  }

  // The nodes are stored in cell order, so that neighbouring particles are close in memory. Set up
  // in blocks, each rank builds its block of that order from its share of the cards, and the places
  // of the nodes that other cards name are found over the ranks (NodesInBlocks).
  void build_nodes() {
    if (in_blocks_) {
      blocks_.emplace(model_, problem_.nodes, parallel::world());
      first_row_ = blocks_->first_row();
      deck_nodes_ = blocks_->deck_nodes();
      named_ = blocks_->places_of(model_.named_nodes());
      return;
    }
    const Index n = static_cast<Index>(model_.nodes.size());
    deck_nodes_ = n;
    {
      BoundingBox box;
      for (Index i = 0; i < n; ++i) {
        check_node_position(model_.nodes[i]);
        box.include(model_.nodes[i].x);
      }
      const NodeOrderAxes axes(box);
      std::vector<Vec3> x(n);
      for (Index i = 0; i < n; ++i) x[i] = axes(model_.nodes[i].x);
      if (n > 0) model_node_ = neighbors::spatial_order(x, node_order_cell(box, n));
    }
    std::vector<Id> id(n);
    for (Index k = 0; k < n; ++k) id[k] = model_.nodes[model_node_[k]].id;
    if (const Index twice = index_of_node_.assign(id); twice >= 0) {
      const auto& node = model_.nodes[model_node_[twice]];
      fail_at(node.where, "*NODE", set_up_message::node_defined_twice(node.id));
    }
    auto& nodes = problem_.nodes;
    nodes.resize(n);
    for (Index k = 0; k < n; ++k) {
      const auto& node = model_.nodes[model_node_[k]];
      nodes.id[k] = node.id;
      nodes.x0[k] = node.x;
      nodes.x[k] = node.x;
      nodes.fixed[k] = model::constraint_axes(node.tc);
    }
  }

  // The SPG parts; set up in blocks (a deck of SPG alone), each rank's particles those on its block
  // of the nodes, from its share of the element cards (docs/SCALING.md §3).
  std::unique_ptr<discretization::Formulation> build_spg() {
    if (!in_blocks_) return spg::build_spg(model_, index_of_node_, problem_.nodes);
    const parallel::Communicator& ranks = parallel::world();
    return spg::build_spg_in_blocks(model_, blocks_->solid_elements(problem_.nodes),
                                    parallel::block_offsets(deck_nodes_, ranks.size()), problem_.nodes, ranks);
  }

  // An SPH part as the solver needs it, checked once however many particles it has.
  struct SphPart {
    const model::SectionSph* section = nullptr;
    Index material = 0;  // index into the material table
    Real density = 0;
    Real spacing = 0;  // the largest particle spacing (m / rho)^(1/3) of the part
  };

  SphPart resolve_sph_part(Id pid, const SourceLocation& where,
                           std::vector<materials::Material>& table,
                           std::unordered_map<Id, Index>& material_index) {
    const model::Part* part = model_.find_part(pid);
    if (!part) fail_at(where, "*ELEMENT_SPH", fmt::format("PID: part {} does not exist", pid));
    auto sec = model_.sections.find(part->secid);
    if (sec == model_.sections.end() || !std::holds_alternative<model::SectionSph>(sec->second))
      fail_at(part->where, "*PART",
              fmt::format("part {} has SPH particles but section {} is not a *SECTION_SPH", part->id,
                       part->secid));
    const auto& section = std::get<model::SectionSph>(sec->second);
    if (section.cslh < 1.0)
      fail_at(section.where, "*SECTION_SPH",
              fmt::format("CSLH: {} is inadmissible (less than 1; 1.05 to 1.3 are recommended)", section.cslh));
    if (!kernels::kernel_of_code(section.sphkern))
      fail_at(section.where, "*SECTION_SPH",
              fmt::format("SPHKERN {}: not implemented ({})", section.sphkern, kernels::kernel_codes));
    if (!(section.hmin > 0 && section.hmin <= 1 && section.hmax >= 1))
      fail_at(section.where, "*SECTION_SPH",
              fmt::format("HMIN {} HMAX {}: need 0 < HMIN <= 1 <= HMAX (factors on the initial h)",
                       section.hmin, section.hmax));
    if (section.death < 1e20 || section.start > 0)
      fail_at(section.where, "*SECTION_SPH", "DEATH/START: particle birth and death are not implemented yet");
    if (part->hgid != 0)
      fail_at(part->where, "*PART",
              fmt::format("part {}: HGID {}: *HOURGLASS controls are not supported yet", part->id, part->hgid));
    auto [it, inserted] = material_index.emplace(part->id, static_cast<Index>(table.size()));
    if (inserted) table.push_back(materials::make_material(model_, *part));
    return {&section, it->second, table[it->second].density, 0};
  }

  // *SPALL_SPH_TIMESTEP sets the SPH solid's step: without SPH solid particles it would do nothing.
  void refuse_sph_timestep_without_solid() const {
    if (model_.sph_timestep)
      fail_at(model_.sph_timestep->where, "*SPALL_SPH_TIMESTEP",
              "RULE: the deck has no SPH solid particles, whose stable step the rule sets");
  }

  void build_sph() {
    if (model_.sph_card_count() == 0) return refuse_sph_timestep_without_solid();
    if (in_blocks_) {  // SPH fluid or SPH solid alone: each rank the particles on its block's nodes
      const parallel::Communicator& ranks = parallel::world();
      std::vector<sph::ParticleCard> block = blocks_->particles();
      const auto of_solid = [&](const sph::ParticleCard& p) { return !sph::is_fluid_part(model_, p.element->pid); };
      if (ranks.any(std::any_of(block.begin(), block.end(), of_solid))) return build_sph_solid_in_blocks(block, ranks);
      const sph::SolidOptions options = sph_options();
      problem_.formulations.push_back(
          sph::build_fluid(model_, block, options.viscosity, options.dimension, problem_.nodes, &ranks));
      return refuse_sph_timestep_without_solid();
    }
    std::vector<materials::Material> table;
    std::unordered_map<Id, Index> material_index;
    std::unordered_map<Id, SphPart> parts;
    std::vector<sph::ParticleSetup> particles;
    std::vector<char> carries_particle(deck_nodes_, 0);  // by place in the node order: 1 B a node, not a set's 40
    // The particle's node's place in the node order, its row.
    const auto carry = [&](const model::ElementSph& e) {
      const Index node = node_index(e.nid, e.where, "*ELEMENT_SPH");
      if (std::exchange(carries_particle[node], 1))
        fail_at(e.where, "*ELEMENT_SPH", set_up_message::node_with_two_particles(e.nid));
      return node;
    };
    sph::SolidOptions options = sph_options();
    std::vector<sph::ParticleCard> fluid;
    for (Index k = 0; k < static_cast<Index>(model_.sph_elements.size()); ++k) {
      const model::ElementSph& e = model_.sph_elements[k];
      // *MAT_NULL parts are liquid: the SPH fluid formulation (sph/fluid_setup.cpp) takes them.
      if (sph::is_fluid_part(model_, e.pid)) {
        const Index node = carry(e);
        fluid.push_back({&e, node, k});
        continue;
      }
      auto found = parts.find(e.pid);
      if (found == parts.end())
        found = parts.emplace(e.pid, resolve_sph_part(e.pid, e.where, table, material_index)).first;
      SphPart& part = found->second;
      const Index node = carry(e);
      const Real mass = particle_mass(e, part);
      if (!(mass > 0)) fail_at(e.where, "*ELEMENT_SPH", set_up_message::no_mass(e.nid));
      particles.push_back(place_particle(e, part, mass, node, node, options.dimension));
    }
    std::optional<kernels::KernelKind> kernel;
    for (auto& p : particles) kernel = smoothing_length(p, parts.at(problem_.nodes.part[p.node]), kernel);
    if (!fluid.empty())
      problem_.formulations.push_back(sph::build_fluid(model_, fluid, options.viscosity, options.dimension,
                                                  problem_.nodes));
    if (particles.empty()) return refuse_sph_timestep_without_solid();
    add_solid(std::move(table), parts, std::move(particles), options, *kernel);
  }

  // An SPH solid particle's mass: MASS, or its volume -MASS times the part's density.
  static Real particle_mass(const model::ElementSph& e, const SphPart& part) {
    return e.mass > 0 ? e.mass : -e.mass * part.density;
  }

  // The particle of card `e` on the node at `place` in the node order (its row `row`): its node's
  // mass and part, and its spacing, which the part's largest spacing takes in.
  sph::ParticleSetup place_particle(const model::ElementSph& e, SphPart& part, Real mass, Index place, Index row,
                                    int dimension) {
    problem_.nodes.mass[row] = mass;
    problem_.nodes.part[row] = e.pid;
    // In plane strain (IDIM 2) masses are per unit thickness and particles stay in their plane.
    const Real spacing = dimension == 2 ? std::sqrt(mass / part.density) : std::cbrt(mass / part.density);
    part.spacing = std::max(part.spacing, spacing);
    if (dimension == 2) problem_.nodes.fixed[row] |= 1u << 2;
    return {place, part.material, 0, spacing, 0, 0};
  }

  // LS-DYNA: h = CSLH * initial spacing, unless SPHINI gives h directly; it then varies within
  // [HMIN h0, HMAX h0]. Checks h and that the part's kernel is `kernel` (the earlier parts'), which
  // it returns.
  static kernels::KernelKind smoothing_length(sph::ParticleSetup& p, const SphPart& part,
                                              std::optional<kernels::KernelKind> kernel) {
    const model::SectionSph& section = *part.section;
    p.smoothing_length = section.sphini > 0 ? section.sphini : section.cslh * part.spacing;
    // The solid's pair terms are single precision (docs/THEORY.md §3): kernel gradients go as
    // h^-5 and viscous denominators as h^4, within float's range for these h.
    if (!(p.smoothing_length >= 1e-6 && p.smoothing_length <= 1e6))
      fail_at(section.where, "*SECTION_SPH",
              fmt::format("smoothing length {:.3g} (CSLH x spacing, or SPHINI) is outside 1e-6 to 1e6: the SPH "
                       "solid's pair terms are single precision; use units (mm, um) that bring it within",
                       p.smoothing_length));
    p.h_min_factor = section.hmin;
    p.h_max_factor = section.hmax;
    const auto kind = *kernels::kernel_of_code(section.sphkern);  // checked by resolve_sph_part
    if (kernel && *kernel != kind)
      fail_at(section.where, "*SECTION_SPH",
              fmt::format("SPHKERN {}: every SPH part must use the same kernel (particles of "
                       "different parts interact through it)",
                       section.sphkern));
    return kind;
  }

  // The SPH solid of these particles (every one of the deck's, or with `across` this rank's block
  // of them), in node (cell) order for memory locality.
  void add_solid(std::vector<materials::Material> table, const std::unordered_map<Id, SphPart>& parts,
                 std::vector<sph::ParticleSetup> particles, sph::SolidOptions options, kernels::KernelKind kernel,
                 const parallel::Communicator* across = nullptr) {
    options.kernel = kernel;
    options.colour_field = colour_fields(parts, table.size());
    options.part_ids.resize(table.size());
    for (const auto& [pid, part] : parts) options.part_ids[part.material] = pid;
    std::sort(particles.begin(), particles.end(), [](const auto& a, const auto& b) { return a.node < b.node; });
    auto solid =
        std::make_unique<sph::SolidFormulation>(std::move(table), particles, options, problem_.nodes, across);
    problem_.sph_solid = solid.get();
    problem_.formulations.push_back(std::move(solid));
  }

  // A deck of SPH solid alone set up in blocks: this rank's particles, those on its block's nodes
  // (NodesInBlocks::particles, in the deck's order). Every rank sets up every part, in the order of
  // their first particles over the ranks (the material table's, as the whole set-up's); each part's
  // spacing is the largest over the ranks; the first failure in the deck's order, at a part's first
  // particle or a particle without mass, stops every rank (as the whole set-up, card after card).
  void build_sph_solid_in_blocks(const std::vector<sph::ParticleCard>& block, const parallel::Communicator& ranks) {
    const std::vector<sph::FirstParticle> firsts = sph::parts_by_first_particle(model_, block, &ranks);
    // A failure's place in the deck's order: its card's, then the part's set-up (0) before the mass (1).
    std::int64_t position = -1;
    std::optional<InputError> error;
    const auto fail = [&](Index ordinal, int what, const InputError& e) {
      const std::int64_t at = 2 * std::int64_t(ordinal) + what;
      if (position < 0 || at < position) position = at, error = e;
    };
    std::vector<materials::Material> table;
    std::unordered_map<Id, Index> material_index;
    std::unordered_map<Id, SphPart> parts;
    for (const sph::FirstParticle& f : firsts) {
      if (parts.contains(f.pid)) continue;  // a later rank's first of a part set up already
      try {
        parts.emplace(f.pid, resolve_sph_part(f.pid, model_.location(f.line), table, material_index));
      } catch (const InputError& e) {
        fail(f.ordinal, 0, e);
        break;  // the parts after it are not reached
      }
    }
    sph::SolidOptions options = sph_options();
    std::vector<sph::ParticleSetup> particles;
    for (const auto& p : block) {
      const model::ElementSph& e = *p.element;
      const auto found = parts.find(e.pid);
      if (found == parts.end()) continue;  // its part failed: a failure before this particle's
      const Real mass = particle_mass(e, found->second);
      if (!(mass > 0)) {
        fail(p.ordinal, 1, InputError(e.where, "*ELEMENT_SPH", set_up_message::no_mass(e.nid)));
        continue;
      }
      particles.push_back(place_particle(e, found->second, mass, first_row_ + p.node, p.node, options.dimension));
    }
    parallel::throw_first_failure(position, error, ranks);
    std::vector<double> spacing;  // the largest of each part over the ranks
    for (const sph::FirstParticle& f : firsts) spacing.push_back(parts.at(f.pid).spacing);
    ranks.maximum(spacing);
    for (std::size_t k = 0; k < firsts.size(); ++k) parts.at(firsts[k].pid).spacing = spacing[k];
    // h and the kernel by part, in the order of their first particles: the whole set-up's first
    // failure, alike on every rank.
    std::optional<kernels::KernelKind> kernel;
    for (const sph::FirstParticle& f : firsts) {
      sph::ParticleSetup first;
      kernel = smoothing_length(first, parts.at(f.pid), kernel);
    }
    for (auto& p : particles) smoothing_length(p, parts.at(problem_.nodes.part[p.node - first_row_]), kernel);
    add_solid(std::move(table), parts, std::move(particles), options, *kernel, &ranks);
  }

  // *SPALL_SPH_COLOUR_FIELD per SPH part (indexed like the material table: one entry per part);
  // a card for a part that has no SPH particles is an error at the card.
  std::vector<sph::ColourField> colour_fields(const std::unordered_map<Id, SphPart>& parts,
                                              std::size_t part_count) const {
    std::vector<sph::ColourField> result(part_count);
    for (const auto& card : model_.sph_colour_fields)
      if (card.pid != 0 && !parts.count(card.pid))
        fail_at(card.where, "*SPALL_SPH_COLOUR_FIELD",
                fmt::format("PID: part {} has no SPH particles", card.pid));
    for (const auto& [pid, part] : parts) {
      const model::SphColourField* chosen = nullptr;
      for (const auto& card : model_.sph_colour_fields)
        if (card.pid == pid || (card.pid == 0 && !chosen)) chosen = &card;
      if (!chosen) continue;
      sph::ColourField& c = result[part.material];
      c.enabled = true;
      c.treat = chosen->treat == 1;
      c.neighbour_fraction = chosen->neighbour_fraction;
      c.normal_threshold = chosen->normal_threshold;
      c.layers = chosen->layers;
      c.interval = chosen->interval;
      c.literal = chosen->form == 2;
      c.relaxation = chosen->relaxation;
    }
    return result;
  }

  // *CONTROL_SPH, *CONTROL_BULK_VISCOSITY and *SPALL_SPH_ARTIFICIAL_STRESS as the SPH solver uses
  // them; a field whose option Spall does not implement stops the run at its card.
  sph::SolidOptions sph_options() const {
    sph::SolidOptions options;
    options.viscosity.beta = model_.bulk_viscosity.q1;
    options.viscosity.alpha = model_.bulk_viscosity.q2;
    if (const auto& stress = model_.sph_artificial_stress) {
      options.artificial_stress.enabled = true;
      options.artificial_stress.epsilon = stress->epsilon;
      options.artificial_stress.exponent = stress->exponent;
    }
    if (model_.sph_timestep && model_.sph_timestep->rule == 1) options.time_step_rule = sph::TimeStepRule::plain;
    if (!model_.control_sph) return options;
    const model::ControlSph& c = *model_.control_sph;
    const auto refuse = [&](int card, std::string_view field, auto value, std::string_view why) {
      fail_at(c.card_where[card], "*CONTROL_SPH", fmt::format("{} {}: {}", field, value, why));
    };
    if (c.boxid != 0) refuse(0, "BOXID", c.boxid, "SPH activation boxes are not implemented");
    if (c.idim == -2) refuse(0, "IDIM", c.idim, "axisymmetric SPH is not implemented (3 and 2 are)");
    if (c.form != 0 && c.form != 1)
      refuse(0, "FORM", c.form, "only 0 (plain SPH) and 1 (renormalized, Spall's default) are implemented");
    if (c.maxv > 0 && c.maxv < 1.0e15)
      refuse(0, "MAXV", c.maxv, "deactivating fast particles is not implemented (leave MAXV blank)");
    if (c.cont != 0) refuse(1, "CONT", c.cont, "switching off the interaction between SPH parts is not implemented");
    if (c.deriv != 0) refuse(1, "DERIV", c.deriv, "only 0 (dh/dt = h div(v) / d) is implemented");
    if (c.ini != 0) refuse(1, "INI", c.ini, "only 0 (initial h from the particle spacing) is implemented");
    if (c.ierod != 0) refuse(1, "IEROD", c.ierod, "SPH particle erosion is not implemented");
    if (c.icont != 0) refuse(1, "ICONT", c.icont, "contact of eroded SPH particles is not implemented");
    if (c.iavis != 0) refuse(1, "IAVIS", c.iavis, "only 0 (Monaghan's artificial viscosity) is implemented");
    if (c.ithk != 0) refuse(2, "ITHK", c.ithk, "contact thickness of SPH particles is not implemented");
    if (c.istab != 0) refuse(2, "ISTAB", c.istab, "only 0 (standard stabilization) is implemented");
    if (c.sphsort != 0) refuse(2, "SPHSORT", c.sphsort, "is not implemented (Spall keeps particles in cell order)");
    if (c.ishift != 0) refuse(2, "ISHIFT", c.ishift, "particle shifting is not implemented");
    options.dimension = c.idim == 2 ? 2 : 3;
    options.gradient_correction = c.form == 1;
    options.start_time = c.start;
    options.death_time = c.dt;
    return options;
  }

  void apply_spcs() {
    for (const auto& spc : model_.spcs) {
      const char* keyword = spc.target == model::Target::node ? "*BOUNDARY_SPC_NODE" : "*BOUNDARY_SPC_SET";
      model_.require_global_axes(spc.cid, spc.where, keyword, "CID", false);
      std::uint8_t mask = 0;
      for (int d = 0; d < 3; ++d)
        if (spc.dof[d]) mask |= std::uint8_t(1u << d);
      const auto nodes = spc.target == model::Target::node
                             ? std::vector<Index>{node_index(spc.id, spc.where, keyword)}
                             : node_set(spc.id, spc.where, keyword);
      for (Index i : rows(nodes)) problem_.nodes.fixed[i] |= mask;
    }
  }

  void build_motions() {
    for (const auto& pm : model_.prescribed_motions) {
      const char* keyword = pm.target == model::Target::node ? "*BOUNDARY_PRESCRIBED_MOTION_NODE"
                            : pm.target == model::Target::node_set ? "*BOUNDARY_PRESCRIBED_MOTION_SET"
                                                                   : "*BOUNDARY_PRESCRIBED_MOTION_RIGID";
      if (pm.target == model::Target::part) continue;  // a rigid body's (rigid/setup.cpp)
      if (pm.dof < 1 || pm.dof > 3)
        fail_at(pm.where, keyword,
                fmt::format("DOF {}: only translations along x, y, z (1, 2, 3) are supported", pm.dof));
      if (pm.vad < 0 || pm.vad > 2)
        fail_at(pm.where, keyword,
                fmt::format("VAD {}: only velocity (0), acceleration (1) and displacement (2) are supported", pm.vad));
      const model::Curve* c = curve(pm.lcid, pm.where, keyword, "LCID");
      if (!c) fail_at(pm.where, keyword, "LCID: a load curve is required");
      const auto nodes = pm.target == model::Target::node
                             ? std::vector<Index>{node_index(pm.id, pm.where, keyword)}
                             : node_set(pm.id, pm.where, keyword);
      for (Index i : nodes)  // by place in the node order: the time loop finds their rows
        problem_.motions.push_back({i, pm.dof - 1, pm.vad, c, pm.sf, pm.birth, pm.death});
    }
  }

  void build_history_nodes() {
    std::vector<Index>& places = problem_.history_nodes;
    for (const auto& card : model_.history_nodes) {
      const char* keyword = card.sets ? "*DATABASE_HISTORY_NODE_SET" : "*DATABASE_HISTORY_NODE";
      for (const Id id : card.ids) {
        const std::vector<Index> nodes = card.sets ? node_set(id, card.where, keyword)
                                                   : std::vector<Index>{node_index(id, card.where, keyword)};
        places.insert(places.end(), nodes.begin(), nodes.end());
      }
    }
    // A node named twice (in two sets, say) is followed once, where it was first named.
    keep_first_of_each(places, [](Index place) { return place; });
  }

  // *DATABASE_HISTORY_SOLID, _SET: the elements elout.csv follows, in the deck's order (a set's in
  // its order), each once; each must be a finite element of a formulation that follows it.
  void build_history_solids() {
    struct Named {
      Id id;
      SourceLocation where;  // the history card's
      const char* keyword;
    };
    std::vector<Named> named;
    for (const auto& card : model_.history_solids) {
      const char* keyword = card.sets ? "*DATABASE_HISTORY_SOLID_SET" : "*DATABASE_HISTORY_SOLID";
      for (const Id id : card.ids) {
        if (!card.sets) {
          named.push_back({id, card.where, keyword});
          continue;
        }
        const auto set = model_.solid_sets.find(id);
        if (set == model_.solid_sets.end())
          fail_at(card.where, keyword, fmt::format("solid set {} does not exist", id));
        for (const Id element : set->second.elements) named.push_back({element, card.where, keyword});
      }
    }
    keep_first_of_each(named, [](const Named& entry) { return entry.id; });
    if (named.empty()) return;
    std::vector<Id>& ids = problem_.history_solids;
    for (const Named& entry : named) ids.push_back(entry.id);
    std::vector<std::uint8_t> taken(ids.size(), 0);
    for (auto& f : problem_.formulations) f->follow_elements(ids, taken);
    const auto missing = std::find(taken.begin(), taken.end(), 0);
    if (missing == taken.end()) return;
    const std::size_t k = static_cast<std::size_t>(missing - taken.begin());
    // The set-up in blocks (a deck of particles alone, no finite element) holds a share of the cards.
    const auto card = std::find_if(model_.solid_elements.begin(), model_.solid_elements.end(),
                                   [&](const model::ElementSolid& e) { return e.eid == ids[k]; });
    if (!in_blocks_ && card == model_.solid_elements.end())
      fail_at(named[k].where, named[k].keyword, fmt::format("solid element {} does not exist", ids[k]));
    fail_at(named[k].where, named[k].keyword,
            fmt::format("solid element {} is not a finite element (its part's are SPG particles or a rigid "
                        "body): follow its nodes with *DATABASE_HISTORY_NODE",
                        ids[k]));
  }

  void apply_initial_velocities() {
    auto& v = problem_.nodes.v;
    for (const auto& iv : model_.initial_velocities) {
      if (iv.boxid != 0) fail_at(iv.where, "*INITIAL_VELOCITY", "BOXID: boxes are not supported yet");
      model_.require_global_axes(iv.icid, iv.where, "*INITIAL_VELOCITY", "ICID", true);
      std::vector<char> exempt(problem_.nodes.size(), 0);
      if (iv.nsidex != 0)
        for (Index i : rows(node_set(iv.nsidex, iv.where, "*INITIAL_VELOCITY"))) exempt[i] = 1;
      std::vector<Index> nodes;
      if (iv.nsid == 0) {
        for (Index i = 0; i < problem_.nodes.size(); ++i) nodes.push_back(i);
      } else {
        nodes = rows(node_set(iv.nsid, iv.where, "*INITIAL_VELOCITY"));
      }
      for (Index i : nodes) v[i] = exempt[i] ? iv.v_exempt : iv.v;
    }
    for (const auto& iv : model_.initial_velocity_nodes) {
      model_.require_global_axes(iv.icid, iv.where, "*INITIAL_VELOCITY_NODE", "ICID", true);
      if (const Index i = row(node_index(iv.nid, iv.where, "*INITIAL_VELOCITY_NODE")); i >= 0) v[i] = iv.v;
    }
    for (const auto& g : model_.initial_velocity_generations) {
      const char* keyword = "*INITIAL_VELOCITY_GENERATION";
      model_.require_global_axes(g.icid, g.where, keyword, "ICID", true);
      std::vector<Index> nodes;
      if (g.styp == 2) {
        nodes = part_nodes(g.id, g.where, keyword);
      } else if (g.styp == 1) {
        auto ps = model_.part_sets.find(g.id);
        if (ps == model_.part_sets.end()) fail_at(g.where, keyword, fmt::format("part set {} does not exist", g.id));
        for (Id pid : ps->second.parts) {
          const auto more = part_nodes(pid, ps->second.where, "*SET_PART");
          nodes.insert(nodes.end(), more.begin(), more.end());
        }
      } else if (g.styp == 3) {
        nodes = rows(node_set(g.id, g.where, keyword));
      } else {
        fail_at(g.where, keyword, fmt::format("STYP {}: must be 1 (part set), 2 (part) or 3 (node set)", g.styp));
      }
      Vec3 axis = g.axis;
      if (g.omega != 0) {
        if (axis.norm() == 0) fail_at(g.where, keyword, "NX NY NZ: the rotation axis is zero");
        axis.normalize();
      }
      // v = v0 + omega n x (x - xc): rigid translation plus rotation about the axis.
      for (Index i : nodes)
        v[i] = g.v + g.omega * axis.cross(problem_.nodes.x[i] - g.xc);
    }
  }

  void build_loads() {
    static const char* keywords[3] = {"*LOAD_BODY_X", "*LOAD_BODY_Y", "*LOAD_BODY_Z"};
    for (const auto& load : model_.body_loads) {
      const char* keyword = keywords[load.direction];
      model_.require_global_axes(load.cid, load.where, keyword, "CID", false);
      const model::Curve* c = curve(load.lcid, load.where, keyword, "LCID");
      if (!c) fail_at(load.where, keyword, "LCID: a load curve is required");
      problem_.base_accelerations.push_back({load.direction, c, load.sf});
    }
  }

  // *RIGIDWALL_PLANAR...: the plane, friction, and the tracked nodes (those with mass).
  void build_rigid_walls() {
    const auto& x = problem_.nodes.x;
    for (std::size_t w = 0; w < model_.rigid_walls.size(); ++w) {
      const auto& wall = model_.rigid_walls[w];
      const std::string& keyword = wall.keyword;
      if (wall.boxid != 0)
        fail_at(wall.where, keyword, fmt::format("BOXID {}: *DEFINE_BOX is not supported yet", wall.boxid));
      // LS-DYNA scales with RWKSF the penalty stiffness of a wall against rigid-body nodes; the
      // kinematic wall of deformable nodes has no stiffness, and Spall has no rigid bodies yet.
      if (wall.rwksf != 1.0)
        warn(wall, fmt::format("RWKSF {}: scales a penalty stiffness that the kinematic wall does not "
                               "have; no effect", wall.rwksf));
      if (wall.wvel != 0 && wall.fric < 2)
        warn(wall, fmt::format("WVEL {}: the welding speed applies only with FRIC 2 or 3; no effect "
                               "with FRIC {}", wall.wvel, wall.fric));

      contact::RigidWall::Definition d;
      d.id = wall.id != 0 ? wall.id : static_cast<Id>(w + 1);  // LS-DYNA numbers walls in order
      d.origin = wall.tail;
      d.normal = (wall.head - wall.tail).normalized();
      if (wall.finite) {
        const Vec3 l = wall.edge_head - wall.tail;
        d.edge_l = (l - l.dot(d.normal) * d.normal).normalized();
        d.edge_m = d.normal.cross(d.edge_l);
        d.length_l = wall.lenl;
        d.length_m = wall.lenm;
      }
      auto& friction = d.friction;
      friction.coefficient = wall.fric < 1 ? wall.fric : 0;
      friction.stick = wall.fric == 1 || wall.fric == 3;
      friction.weld = wall.fric == 2 || wall.fric == 3;
      friction.weld_speed = wall.wvel;
      d.birth = wall.birth;
      d.death = wall.death;
      if (wall.moving) {
        d.mass = wall.mass;
        d.initial_velocity = wall.v0;
      }

      std::vector<char> exempt(problem_.nodes.size(), 0);
      if (wall.nsidex != 0)
        for (Index i : rows(node_set(wall.nsidex, wall.where, keyword.c_str()))) exempt[i] = 1;
      std::vector<Index> candidates;
      if (wall.nsid == 0) {
        for (Index i = 0; i < problem_.nodes.size(); ++i) candidates.push_back(i);
      } else {
        candidates = rows(node_set(wall.nsid, wall.where, keyword.c_str()));
        std::sort(candidates.begin(), candidates.end());
        candidates.erase(std::unique(candidates.begin(), candidates.end()), candidates.end());
      }
      // By place in the node order, ascending (the time loop finds their rows); set up in blocks,
      // each rank's of its block, then every rank's in the ranks' order.
      std::vector<Index> tracked;
      std::vector<std::uint8_t> front;
      for (Index i : candidates) {
        if (exempt[i] || problem_.nodes.mass[i] <= 0) continue;  // a node without mass never moves
        if (wall.offset > 0 && std::abs(d.normal.dot(x[i] - d.origin)) > wall.offset) continue;
        tracked.push_back(first_row_ + i);
        front.push_back(contact::RigidWall::starts_in_front(d, x[i]));
      }
      if (in_blocks_) {
        const parallel::Communicator& ranks = parallel::world();
        tracked = ranks.all(std::span<const Index>(tracked));
        front = ranks.all(std::span<const std::uint8_t>(front));
      }
      problem_.rigid_walls.emplace_back(d, std::move(tracked), std::move(front));
    }
  }

  static void warn(const model::RigidWallPlanar& wall, const std::string& message) {
    log::warning(fmt::format("{}: {}: {}", to_string(wall.where), wall.keyword, message));
  }

  void build_controls() {
    if (!model_.termination)
      throw InputError("the deck has no *CONTROL_TERMINATION: ENDTIM is required");
    const auto& term = *model_.termination;
    auto& c = problem_.controls;
    if (!(term.endtim > 0)) fail_at(term.where, "*CONTROL_TERMINATION", fmt::format("ENDTIM: must be > 0 (found {})", term.endtim));
    c.end_time = term.endtim;
    c.end_cycle = term.endcyc;
    c.dt_min_factor = term.dtmin;
    c.end_energy = term.endeng;
    const auto& ts = model_.timestep;
    c.tssfac = ts.tssfac;
    if (!(c.tssfac > 0)) fail_at(ts.where, "*CONTROL_TIMESTEP", "TSSFAC: a curve (negative TSSFAC) is not supported yet");
    c.dt_initial = ts.dtinit;
    c.max_dt_curve = curve(ts.lctm, ts.where, "*CONTROL_TIMESTEP", "LCTM");
    if (ts.dt2ms > 0)
      fail_at(ts.where, "*CONTROL_TIMESTEP",
              "DT2MS > 0 (every element brought to one step, mass taken from the large ones) is not supported; a "
              "negative DT2MS adds mass only where the step is below |DT2MS|");
    if (ts.ms1st != 0 && ts.ms1st != 1)
      fail_at(ts.where, "*CONTROL_TIMESTEP", fmt::format("MS1ST: {} is not 0 or 1", ts.ms1st));
    if (ts.ms1st == 1 && ts.dt2ms == 0)
      log::warning(fmt::format("{}: *CONTROL_TIMESTEP: MS1ST 1 does nothing without a negative DT2MS",
                               to_string(ts.where)));
    c.mass_scaling_step = -ts.dt2ms;
    c.end_mass_percent = term.endmas;
    c.erode = ts.erode % 10 == 1;
    if (model_.d3plot) {
      const auto& d = *model_.d3plot;
      c.d3plot_dt = d.dt > 0 ? d.dt : (d.npltc > 0 ? c.end_time / d.npltc : 0);
      c.d3plot_dt_curve = curve(d.lcdt, d.where, "*DATABASE_BINARY_D3PLOT", "LCDT");
      if (c.d3plot_dt <= 0 && !c.d3plot_dt_curve)
        fail_at(d.where, "*DATABASE_BINARY_D3PLOT", "DT: must be > 0 (or give NPLTC or LCDT)");
    }
    // Without *DATABASE_GLSTAT the energies are still written, 1000 rows over the run.
    c.glstat_dt = (model_.glstat && model_.glstat->dt > 0) ? model_.glstat->dt : c.end_time / 1000;
    force_history(model_.rwforc, "*DATABASE_RWFORC", c.rwforc_dt, c.rwforc_dt_curve);
    force_history(model_.rcforc, "*DATABASE_RCFORC", c.rcforc_dt, c.rcforc_dt_curve);
    force_history(model_.rbdout, "*DATABASE_RBDOUT", c.rbdout_dt, c.rbdout_dt_curve);
    force_history(model_.nodout, "*DATABASE_NODOUT", c.nodout_dt, c.nodout_dt_curve);
    force_history(model_.elout, "*DATABASE_ELOUT", c.elout_dt, c.elout_dt_curve);
    if (model_.bndout) {
      c.bndout = true;
      force_history(model_.bndout, "*DATABASE_BNDOUT", c.bndout_dt, c.bndout_dt_curve);
    }
    if (model_.matsum) {
      c.matsum = true;
      force_history(model_.matsum, "*DATABASE_MATSUM", c.matsum_dt, c.matsum_dt_curve);
      for (const auto& part : model_.parts) c.matsum_parts.push_back(part.id);
      std::sort(c.matsum_parts.begin(), c.matsum_parts.end());  // the deck's IDs are unique (validate)
    }
    if (model_.spcforc) {
      c.spcforc = true;
      force_history(model_.spcforc, "*DATABASE_SPCFORC", c.spcforc_dt, c.spcforc_dt_curve);
      for (const auto& f : problem_.formulations)
        if (!f->forces_on_held_nodes())
          fail_at(model_.spcforc->where, "*DATABASE_SPCFORC",
                  fmt::format("the {} computes no force on the particles an SPC holds in every direction (its "
                              "walls), so their reactions are not known; leave the card out",
                              f->name()));
    }
    if (model_.damping_global) {
      const auto& d = *model_.damping_global;
      if (d.rotation_scale != Vec3::Zero() && d.rotation_scale != Vec3::Ones())
        fail_at(d.where, "*DAMPING_GLOBAL", "SRX SRY SRZ: nodes carry no rotations to damp; leave them 0");
      c.damping = d.valdmp;
      c.damping_curve = curve(d.lcid, d.where, "*DAMPING_GLOBAL", "LCID");
      c.damping_scale = d.translation_scale;
    }
    // LS-DYNA manual: TYPE -1 and -2 are the standard viscosity (1) also applied to shells, -2 leaving
    // the shells' viscous energy out of the balance; solids always count it. SPH particles are solids.
    if (model_.bulk_viscosity.type == 2 && !model_.sph_elements.empty())
      fail_at(model_.bulk_viscosity.where, "*CONTROL_BULK_VISCOSITY",
              "TYPE 2 (Richards-Wilkins): only the standard bulk viscosity (TYPE 1, -1 or -2) is supported for SPH");
  }

  // *CONTROL_TIMESTEP DT2MS < 0: every formulation that can adds mass where its step is below |DT2MS|.
  void scale_masses() {
    const auto& ts = model_.timestep;
    for (auto& f : problem_.formulations)
      if (!f->scale_mass_below(problem_.controls.mass_scaling_step, ts.ms1st == 1))
        log::warning(fmt::format("{}: *CONTROL_TIMESTEP: DT2MS: the {} particles keep their mass (their density is "
                                 "the sum of the masses around them) and their own step still limits the run",
                                 to_string(ts.where), f->name()));
  }

  // The interval of a history (*DATABASE_RWFORC, _RCFORC, _RBDOUT): GLSTAT's without the card.
  void force_history(const std::optional<model::OutputInterval>& card, const char* keyword, Real& dt,
                     const model::Curve*& dt_curve) const {
    dt = problem_.controls.glstat_dt;
    if (!card) return;
    const auto& r = *card;
    dt = r.dt;
    dt_curve = curve(r.lcdt, r.where, keyword, "LCUR");
    if (dt_curve && r.ioopt != 1)
      fail_at(r.where, keyword, fmt::format("IOOPT {}: only 1 (next output at LCUR of the current time) is supported", r.ioopt));
    if (dt <= 0 && !dt_curve) fail_at(r.where, keyword, "DT: must be > 0 (or give LCUR)");
  }

  const model::Model& model_;
  const bool in_blocks_;
  Problem problem_;
  discretization::NodeIndex index_of_node_;  // node ID -> place in the node order (set up whole)
  std::vector<Index> model_node_;            // place in the node order -> index in model_.nodes (set up whole)
  std::optional<NodesInBlocks> blocks_;      // set up in blocks: this rank's block of the node order
  std::vector<std::pair<Id, Index>> named_;  // set up in blocks: (ID, place) of the nodes other cards name
  Index deck_nodes_ = 0;                     // every node of the deck
  Index first_row_ = 0;                      // the place in the node order of this rank's first row
};

// No shell, contact, rigid part or body, or coordinate system on nodes (which takes their positions
// from the cards, Model::axes): what a deck set up in blocks has none of.
bool has_nothing_whole(const model::Model& model) {
  if (!model.shell_elements.empty() || !model.contacts.empty() || !model.rcforc_moments.empty() ||
      !model.merged_rigid_bodies.empty())
    return false;
  if (std::any_of(model.parts.begin(), model.parts.end(), [&](const auto& part) { return model.rigid_material(part); }))
    return false;
  return std::none_of(model.coordinate_systems.begin(), model.coordinate_systems.end(),
                      [](const auto& system) { return system.second.nodes[0] != 0; });
}

}  // namespace

bool sets_up_in_blocks(const model::Model& model) {
  const parallel::Communicator& ranks = parallel::world();
  if (ranks.size() == 1 || !has_nothing_whole(model)) return false;
  // SPG alone: every solid element an SPG part's, and no particle.
  if (!model.solid_elements.empty())
    return model.sph_card_count() == 0 &&
           std::all_of(model.solid_elements.begin(), model.solid_elements.end(),
                       [&](const model::ElementSolid& e) { return spg::is_spg_part(model, e.pid); });
  // Every particle card a fluid's, or every one a solid's, over the ranks where each holds a share
  // of them. A solid that waits for *CONTROL_SPH START would be dealt anew before its first list
  // build, from every particle's constants (SolidFormulation::compute_forces).
  std::array<double, 2> some{0, 0};  // -1: some fluid particle [0], some solid particle [1]
  for (const model::ElementSph& e : model.sph_elements) some[sph::is_fluid_part(model, e.pid) ? 0 : 1] = -1;
  if (!model.cards.whole()) ranks.minimum(some);
  const bool fluid = some[0] < 0, solid = some[1] < 0;
  const bool waits = solid && model.control_sph && model.control_sph->start > 0;
  return !(fluid && solid) && !waits && model.sph_card_count() > 0;
}

Problem build_problem(const model::Model& model, SetUp set_up) { return Builder(model, set_up).build(); }

}  // namespace spall::solver
