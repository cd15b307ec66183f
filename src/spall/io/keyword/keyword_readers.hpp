#pragma once
// One reader per keyword group; reader.cpp dispatches each keyword block to one of them.
// Internal to io/keyword.
#include <map>
#include <string>
#include <string_view>
#include <variant>

#include "spall/io/keyword/card.hpp"
#include "spall/model/model.hpp"

namespace spall::io::keyword {

// The keyword as dispatched: its name without the `_TITLE` / `_ID` (/ `_MPP`) options, and which
// options were given.
struct KeywordCall {
  std::string_view base;
  bool title = false;  // `_TITLE`: a title line before card 1 (for *CONTACT_: the ID card, as `_ID`)
  bool id = false;     // `_ID`: an ID + HEADING card before card 1
  bool mpp = false;    // `_MPP` (*CONTACT_ only): MPP cards before card 1
};

using KeywordReader = void (*)(CardCursor&, const KeywordCall&, model::Model&);

template <class T>
const SourceLocation& location_of(const T& item) {
  return item.where;
}
template <class... T>
const SourceLocation& location_of(const std::variant<T...>& item) {
  return std::visit([](const auto& alternative) -> const SourceLocation& { return alternative.where; },
                    item);
}

// Adds `item` under `id`, or fails naming the earlier definition.
template <class Map, class Item>
void insert_unique(Map& map, std::int64_t id, Item&& item, const Card& card, std::string_view what) {
  auto [it, inserted] = map.try_emplace(id, std::forward<Item>(item));
  if (!inserted) {
    const SourceLocation& first = location_of(it->second);
    card.context().fail(card.line(), std::string(what) + " " + std::to_string(id) +
                                         " is defined twice (first at " + to_string(first) + ")");
  }
}

// The largest ID read where IDs are counted or generated (nodes, particles, set ranges): 2^53, below
// which every whole number is exactly a double (IDs come through real fields and parameters too),
// and far enough below int64's end that generated node numbers and range lengths cannot overflow.
inline constexpr Id largest_id = Id{1} << 53;

// geometry.cpp
// `id`, read from the card's field `name`, if it is a node ID (1 to largest_id); else fails there.
Id checked_node_id(const Card& card, const char* name, Id id);
void read_node(CardCursor&, const KeywordCall&, model::Model&);
void read_element_solid(CardCursor&, const KeywordCall&, model::Model&);
void read_element_sph(CardCursor&, const KeywordCall&, model::Model&);
void read_element_shell(CardCursor&, const KeywordCall&, model::Model&);
void read_part(CardCursor&, const KeywordCall&, model::Model&);
void read_part_inertia(CardCursor&, const KeywordCall&, model::Model&);
void read_define_coordinate_system(CardCursor&, const KeywordCall&, model::Model&);
void read_define_coordinate_vector(CardCursor&, const KeywordCall&, model::Model&);
void read_define_coordinate_nodes(CardCursor&, const KeywordCall&, model::Model&);
void read_define_vector(CardCursor&, const KeywordCall&, model::Model&);
// sph_mesh_box.cpp
void read_define_sph_mesh_box(CardCursor&, const KeywordCall&, model::Model&);
// After the whole deck is read: the nodes and particles of every *DEFINE_SPH_MESH_BOX.
void generate_sph_mesh_box_particles(model::Model&);
// What a particle a card generates costs: its records in the model (a node and an *ELEMENT_SPH)
// and about 1 kB for the run (docs/PERFORMANCE.md: 0.87 kB per SPH solid particle). A generation
// whose particles would not fit in the memory left is refused at its card (core/memory.hpp).
inline constexpr double particle_bytes = sizeof(model::Node) + sizeof(model::ElementSph) + 1000;
// The SPH particles this rank would hold with `more` of them: those read so far, those the mesh
// boxes read so far will generate and `more`, or its share of them where it holds a share of the
// cards (model::CardShare; a deck set up whole gathers them later, beyond this estimate).
double particles_held(const model::Model& model, double more);
// sections_materials.cpp
void read_section_solid(CardCursor&, const KeywordCall&, model::Model&);
void read_section_solid_spg(CardCursor&, const KeywordCall&, model::Model&);
void read_section_sph(CardCursor&, const KeywordCall&, model::Model&);
void read_section_shell(CardCursor&, const KeywordCall&, model::Model&);
void read_mat_elastic(CardCursor&, const KeywordCall&, model::Model&);
void read_mat_rigid(CardCursor&, const KeywordCall&, model::Model&);
// True for the keywords of thermal materials (`MAT_THERMAL_...`, `MAT_Tnn...`, without `*`).
bool is_thermal_material(std::string_view name);
void read_mat_thermal(CardCursor&, const KeywordCall&, model::Model&);
// add_erosion.cpp
void read_mat_add_erosion(CardCursor&, const KeywordCall&, model::Model&);
// hourglass.cpp
void read_hourglass(CardCursor&, const KeywordCall&, model::Model&);
void read_control_hourglass(CardCursor&, const KeywordCall&, model::Model&);
// materials_plastic.cpp
void read_mat_plastic_kinematic(CardCursor&, const KeywordCall&, model::Model&);
void read_mat_piecewise_linear_plasticity(CardCursor&, const KeywordCall&, model::Model&);
void read_mat_johnson_cook(CardCursor&, const KeywordCall&, model::Model&);
void read_mat_null(CardCursor&, const KeywordCall&, model::Model&);
// eos.cpp
void read_eos_linear_polynomial(CardCursor&, const KeywordCall&, model::Model&);
void read_eos_gruneisen(CardCursor&, const KeywordCall&, model::Model&);
void read_eos_murnaghan(CardCursor&, const KeywordCall&, model::Model&);
// sets.cpp
void read_set_node_list(CardCursor&, const KeywordCall&, model::Model&);
void read_set_node_list_generate(CardCursor&, const KeywordCall&, model::Model&);
// After the whole deck is read (and the mesh boxes' particles generated): the members of every
// *SET_NODE_LIST_GENERATE range, each refused where it holds more IDs than the deck has nodes.
void generate_node_set_ranges(model::Model&);
void read_set_part_list(CardCursor&, const KeywordCall&, model::Model&);
void read_set_segment(CardCursor&, const KeywordCall&, model::Model&);
void read_set_solid(CardCursor&, const KeywordCall&, model::Model&);
// curves.cpp
void read_define_curve(CardCursor&, const KeywordCall&, model::Model&);
// boundary_initial.cpp
void read_boundary_spc(CardCursor&, const KeywordCall&, model::Model&);
void read_boundary_prescribed_motion(CardCursor&, const KeywordCall&, model::Model&);
void read_initial_velocity(CardCursor&, const KeywordCall&, model::Model&);
void read_initial_velocity_node(CardCursor&, const KeywordCall&, model::Model&);
void read_initial_velocity_generation(CardCursor&, const KeywordCall&, model::Model&);
// loads.cpp
void read_load_body(CardCursor&, const KeywordCall&, model::Model&);
// rigid_walls.cpp
void read_rigidwall_planar(CardCursor&, const KeywordCall&, model::Model&);
void read_constrained_rigid_bodies(CardCursor&, const KeywordCall&, model::Model&);
// contact.cpp
// The four contact types Spall reads, with any of `_ID` or `_TITLE` and `_MPP` in any order: true
// and `call` filled in for one of them, false for every other *CONTACT_ name (those stay unsupported).
bool split_contact_keyword(std::string_view name, KeywordCall& call);
void read_contact(CardCursor&, const KeywordCall&, model::Model&);
void read_control_contact(CardCursor&, const KeywordCall&, model::Model&);
// controls.cpp
void read_control_termination(CardCursor&, const KeywordCall&, model::Model&);
void read_control_solution(CardCursor&, const KeywordCall&, model::Model&);
void read_control_timestep(CardCursor&, const KeywordCall&, model::Model&);
void read_control_bulk_viscosity(CardCursor&, const KeywordCall&, model::Model&);
void read_damping_global(CardCursor&, const KeywordCall&, model::Model&);
void read_control_sph(CardCursor&, const KeywordCall&, model::Model&);
void read_spall_sph_artificial_stress(CardCursor&, const KeywordCall&, model::Model&);
void read_spall_sph_colour_field(CardCursor&, const KeywordCall&, model::Model&);
void read_spall_sph_timestep(CardCursor&, const KeywordCall&, model::Model&);
void read_spall_residual_stress(CardCursor&, const KeywordCall&, model::Model&);
void read_database_binary_d3plot(CardCursor&, const KeywordCall&, model::Model&);
void read_database_binary_runrsf(CardCursor&, const KeywordCall&, model::Model&);
void read_database_glstat(CardCursor&, const KeywordCall&, model::Model&);
// *DATABASE_RWFORC, _RCFORC, _RBDOUT, _SPCFORC, _BNDOUT, _NODOUT, _ELOUT and _MATSUM: one card DT
// BINARY LCUR IOOPT (NODOUT's, ELOUT's and MATSUM's go on with DTHF BINHF), kept in model.*interval.
model::OutputInterval read_history_interval(CardCursor& cursor, bool high_frequency);
template <std::optional<model::OutputInterval> model::Model::*interval, bool high_frequency = false>
void read_database_history_file(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  model.*interval = read_history_interval(cursor, high_frequency);
}
void read_database_rcforc_moment(CardCursor&, const KeywordCall&, model::Model&);
void read_database_elout(CardCursor&, const KeywordCall&, model::Model&);
void read_database_history(CardCursor&, const KeywordCall&, model::Model&);

}  // namespace spall::io::keyword
