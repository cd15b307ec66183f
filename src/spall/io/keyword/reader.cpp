// read_deck: files -> keyword blocks -> one reader per keyword. Also the deck-structure keywords
// themselves: *KEYWORD, *TITLE, *INCLUDE, *PARAMETER(_LOCAL), *PARAMETER_EXPRESSION(_LOCAL).
#include "spall/io/keyword/reader.hpp"

#include <array>
#include <cmath>
#include <string>
#include <system_error>

#include "spall/io/keyword/deck_lines.hpp"
#include "spall/io/keyword/keyword_readers.hpp"
#include "spall/io/keyword/numbers.hpp"

namespace spall::io::keyword {

namespace {

struct SupportedKeyword {
  std::string_view name;
  KeywordReader reader;
  bool title_option = false;
  bool id_option = false;
};

// Every keyword Spall reads, but the contacts (split_contact_keyword: their options combine in any
// order). Any other keyword goes to Model::unsupported.
constexpr SupportedKeyword supported_keywords[] = {
    {"NODE", read_node},
    {"PART", read_part},
    {"PART_INERTIA", read_part_inertia},
    {"ELEMENT_SOLID", read_element_solid},
    {"ELEMENT_SHELL", read_element_shell},
    {"ELEMENT_SHELL_THICKNESS", read_element_shell},
    {"ELEMENT_SHELL_BETA", read_element_shell},
    {"ELEMENT_SHELL_MCID", read_element_shell},
    {"ELEMENT_SPH", read_element_sph},
    {"ELEMENT_SPH_VOLUME", read_element_sph},
    {"DEFINE_SPH_MESH_BOX", read_define_sph_mesh_box},
    {"DEFINE_COORDINATE_SYSTEM", read_define_coordinate_system, true},
    {"DEFINE_COORDINATE_VECTOR", read_define_coordinate_vector, true},
    {"DEFINE_COORDINATE_NODES", read_define_coordinate_nodes, true},
    {"DEFINE_VECTOR", read_define_vector, true},
    {"SECTION_SOLID", read_section_solid, true},
    {"SECTION_SOLID_SPG", read_section_solid_spg, true},
    {"SECTION_SPH", read_section_sph, true},
    {"SECTION_SHELL", read_section_shell, true},
    {"HOURGLASS", read_hourglass, true},
    {"MAT_ADD_EROSION", read_mat_add_erosion, true},
    {"CONTROL_HOURGLASS", read_control_hourglass},
    {"MAT_ELASTIC", read_mat_elastic, true},
    {"MAT_001", read_mat_elastic, true},
    {"MAT_RIGID", read_mat_rigid, true},
    {"MAT_020", read_mat_rigid, true},
    {"MAT_PLASTIC_KINEMATIC", read_mat_plastic_kinematic, true},
    {"MAT_003", read_mat_plastic_kinematic, true},
    {"MAT_PIECEWISE_LINEAR_PLASTICITY", read_mat_piecewise_linear_plasticity, true},
    {"MAT_024", read_mat_piecewise_linear_plasticity, true},
    {"MAT_JOHNSON_COOK", read_mat_johnson_cook, true},
    {"MAT_015", read_mat_johnson_cook, true},
    {"MAT_NULL", read_mat_null, true},
    {"MAT_009", read_mat_null, true},
    {"EOS_LINEAR_POLYNOMIAL", read_eos_linear_polynomial, true},
    {"EOS_GRUNEISEN", read_eos_gruneisen, true},
    {"EOS_MURNAGHAN", read_eos_murnaghan, true},
    {"SET_NODE", read_set_node_list, true},
    {"SET_NODE_LIST", read_set_node_list, true},
    {"SET_NODE_LIST_GENERATE", read_set_node_list_generate, true},
    {"SET_PART", read_set_part_list, true},
    {"SET_PART_LIST", read_set_part_list, true},
    {"SET_SEGMENT", read_set_segment, true},
    {"SET_SOLID", read_set_solid, true},
    {"DEFINE_CURVE", read_define_curve, true},
    {"BOUNDARY_SPC_NODE", read_boundary_spc, false, true},
    {"BOUNDARY_SPC_SET", read_boundary_spc, false, true},
    {"BOUNDARY_PRESCRIBED_MOTION_NODE", read_boundary_prescribed_motion, false, true},
    {"BOUNDARY_PRESCRIBED_MOTION_SET", read_boundary_prescribed_motion, false, true},
    {"BOUNDARY_PRESCRIBED_MOTION_RIGID", read_boundary_prescribed_motion, false, true},
    {"INITIAL_VELOCITY", read_initial_velocity},
    {"INITIAL_VELOCITY_NODE", read_initial_velocity_node},
    {"INITIAL_VELOCITY_GENERATION", read_initial_velocity_generation},
    {"LOAD_BODY_X", read_load_body},
    {"LOAD_BODY_Y", read_load_body},
    {"LOAD_BODY_Z", read_load_body},
    {"RIGIDWALL_PLANAR", read_rigidwall_planar, false, true},
    {"CONSTRAINED_RIGID_BODIES", read_constrained_rigid_bodies},
    {"RIGIDWALL_PLANAR_MOVING", read_rigidwall_planar, false, true},
    {"RIGIDWALL_PLANAR_FINITE", read_rigidwall_planar, false, true},
    {"RIGIDWALL_PLANAR_FINITE_MOVING", read_rigidwall_planar, false, true},
    {"CONTROL_TERMINATION", read_control_termination},
    {"CONTROL_SOLUTION", read_control_solution},
    {"CONTROL_TIMESTEP", read_control_timestep},
    {"CONTROL_BULK_VISCOSITY", read_control_bulk_viscosity},
    {"DAMPING_GLOBAL", read_damping_global},
    {"CONTROL_SPH", read_control_sph},
    {"CONTROL_CONTACT", read_control_contact},
    {"SPALL_SPH_ARTIFICIAL_STRESS", read_spall_sph_artificial_stress},
    {"SPALL_SPH_COLOUR_FIELD", read_spall_sph_colour_field},
    {"SPALL_SPH_TIMESTEP", read_spall_sph_timestep},
    {"SPALL_RESIDUAL_STRESS", read_spall_residual_stress},
    {"DATABASE_BINARY_D3PLOT", read_database_binary_d3plot},
    {"DATABASE_BINARY_RUNRSF", read_database_binary_runrsf},
    {"DATABASE_GLSTAT", read_database_glstat},
    {"DATABASE_RWFORC", read_database_history_file<&model::Model::rwforc>},
    {"DATABASE_RCFORC", read_database_history_file<&model::Model::rcforc>},
    {"DATABASE_RCFORC_MOMENT", read_database_rcforc_moment},
    {"DATABASE_RBDOUT", read_database_history_file<&model::Model::rbdout>},
    {"DATABASE_NODOUT", read_database_history_file<&model::Model::nodout, true>},
    {"DATABASE_SPCFORC", read_database_history_file<&model::Model::spcforc>},
    {"DATABASE_BNDOUT", read_database_history_file<&model::Model::bndout>},
    {"DATABASE_ELOUT", read_database_elout},
    {"DATABASE_MATSUM", read_database_history_file<&model::Model::matsum, true>},
    {"DATABASE_HISTORY_NODE", read_database_history},
    {"DATABASE_HISTORY_NODE_SET", read_database_history},
    {"DATABASE_HISTORY_SOLID", read_database_history},
    {"DATABASE_HISTORY_SOLID_SET", read_database_history},
};

bool ends_with(std::string_view text, std::string_view suffix) {
  return text.size() > suffix.size() && text.substr(text.size() - suffix.size()) == suffix;
}

// The reader for `name`, with the `_TITLE` / `_ID` option split off where the keyword has it.
const SupportedKeyword* find_supported(std::string_view name, KeywordCall& call) {
  for (const auto& keyword : supported_keywords)
    if (keyword.name == name) {
      call.base = keyword.name;
      return &keyword;
    }
  for (const auto& [suffix, is_title] : {std::pair{std::string_view("_TITLE"), true},
                                         std::pair{std::string_view("_ID"), false}}) {
    if (!ends_with(name, suffix)) continue;
    const std::string_view base = name.substr(0, name.size() - suffix.size());
    for (const auto& keyword : supported_keywords)
      if (keyword.name == base && (is_title ? keyword.title_option : keyword.id_option)) {
        call.base = keyword.name;
        call.title = is_title;
        call.id = !is_title;
        return &keyword;
      }
  }
  return nullptr;
}

constexpr int deepest_include = 32;

// Why `path` cannot be a deck file, empty when it can: a directory, or a device or pipe
// (`/dev/zero` would be read without end). A path that does not exist is left to the opening.
std::string not_a_deck_file(const std::filesystem::path& path) {
  std::error_code error;
  const std::filesystem::file_status status = std::filesystem::status(path, error);
  if (std::filesystem::is_directory(status)) return "is a directory, not a keyword file";
  if (std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    return "is not a regular file (a device or a pipe), not a keyword file";
  return {};
}

class DeckReader {
 public:
  explicit DeckReader(model::CardShare cards = {}) { model_.cards = cards; }

  model::Model read(const std::filesystem::path& path) {
    if (const std::string why = not_a_deck_file(path); !why.empty()) throw InputError(path.string() + ": " + why);
    DeckFile file;
    if (!file.load(path))
      throw InputError(path.string() + ": cannot open the deck file");
    return read(file);
  }

  model::Model read(const DeckFile& file) {
    if (const std::size_t nul = file.first_nul(); nul != std::string::npos)
      throw InputError(file.name() + ": not a keyword file (binary data: a NUL byte at offset " +
                       std::to_string(nul) + ")");
    read_file(file, 0);
    generate_sph_mesh_box_particles(model_);
    generate_node_set_ranges(model_);
    return std::move(model_);
  }

 private:
  void read_file(const DeckFile& file, int depth) {
    model_.files.push_back(file.name());
    parameters_.enter_file();
    file.for_each_block([&](const KeywordBlock& block) { read_block(file, block, depth); });
    parameters_.leave_file();
  }

  void read_block(const DeckFile& file, const KeywordBlock& block, int depth) {
    const bool long_format =
        block.width == WidthOverride::long_fields ||
        (block.width == WidthOverride::none && long_format_);
    const CardContext context{block, "*" + block.name, parameters_, long_format};
    CardCursor cursor(context);
    const std::string_view name = block.name;

    if (name == "KEYWORD") return read_keyword_options(block);
    if (name == "TITLE") {
      if (!cursor.done()) model_.title = cursor.next_text("title");
      return;
    }
    if (name == "INCLUDE") return read_include(file, cursor, depth);
    if (name == "COMMENT") return;  // free text up to the next keyword, as a `$` line is
    if (name == "PARAMETER" || name == "PARAMETER_LOCAL" || name == "PARAMETER_NOECHO")
      return read_parameter(cursor, name == "PARAMETER_LOCAL");
    if (name == "PARAMETER_EXPRESSION" || name == "PARAMETER_EXPRESSION_LOCAL" ||
        name == "PARAMETER_EXPRESSION_NOECHO")
      return read_parameter_expression(cursor, name == "PARAMETER_EXPRESSION_LOCAL");

    KeywordCall call;
    if (const SupportedKeyword* keyword = find_supported(name, call))
      return keyword->reader(cursor, call, model_);
    if (split_contact_keyword(name, call)) return read_contact(cursor, call, model_);
    if (is_thermal_material(name)) {
      call.title = ends_with(name, "_TITLE");
      return read_mat_thermal(cursor, call, model_);
    }
    record_unsupported(block, long_format);
  }

  // `*KEYWORD [memory] [LONG=Y|S]`: LONG=Y makes every following card 20-character fields.
  void read_keyword_options(const KeywordBlock& block) {
    std::string options(block.trailing);
    for (char& c : options) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
    const std::size_t at = options.find("LONG=");
    if (at != std::string::npos && at + 5 < options.size())
      long_format_ = options[at + 5] == 'Y';
  }

  // Each data line names one file; a name ending in ` +` continues on the next line.
  void read_include(const DeckFile& file, CardCursor& cursor, int depth) {
    std::string name;
    int line = cursor.line_of_block();
    while (!cursor.done()) {
      const DataLine& data = cursor.peek();
      std::string part = cursor.next_text("file name");
      if (name.empty()) line = data.line;
      const bool continued = part.size() >= 2 && part.ends_with(" +");
      if (continued) part.resize(part.size() - 2);
      name += trim(part);
      if (continued || name.empty()) continue;
      include(file, name, line, depth);
      name.clear();
    }
  }

  void include(const DeckFile& file, const std::string& name, int line, int depth) {
    const SourceLocation where{file.name(), line};
    if (depth + 1 > deepest_include)
      throw InputError(where, "*INCLUDE",
                       "includes nest deeper than " + std::to_string(deepest_include) +
                           " levels (does a file include itself?)");
    std::filesystem::path path(name);
    if (path.is_relative()) path = file.path().parent_path() / path;
    if (const std::string why = not_a_deck_file(path); !why.empty())
      throw InputError(where, "*INCLUDE", "'" + name + "' " + why);
    DeckFile included;
    if (!included.load(path))
      throw InputError(where, "*INCLUDE", "cannot open '" + name + "' (looked for " +
                                              path.lexically_normal().string() + ")");
    read_file(included, depth + 1);
  }

  // Pairs PRMR VAL, four per line: PRMR is the type letter (R, I, C) and the name.
  void read_parameter(CardCursor& cursor, bool local) {
    constexpr const char* prmr_names[4] = {"PRMR1", "PRMR2", "PRMR3", "PRMR4"};
    constexpr const char* val_names[4] = {"VAL1", "VAL2", "VAL3", "VAL4"};
    while (true) {
      cursor.skip_blank_lines();
      if (cursor.done()) break;
      const Card card = cursor.next(standard_fields, "parameter card");
      for (int pair = 0; pair < 4; ++pair) {
        const std::string_view prmr = card.text(2 * pair);
        const int field = 2 * pair + 1;
        // A blank pair is padding; a value without a name would be dropped without a word.
        if (prmr.empty() && !card.blank(field))
          card.fail(prmr_names[pair], std::string("is blank, but ") + val_names[pair] + " is " +
                                          quoted(card.text(field)) + ": a value needs a type letter and a name");
        if (prmr.empty()) continue;
        ParameterValue value;
        const std::string_view name = parameter_name(card, prmr, prmr_names[pair], value.type);
        if (value.type == 'C') value.text = std::string(card.text(field));
        else if (value.type == 'I') value.number = static_cast<double>(card.required_integer(field, val_names[pair]));
        else value.number = card.required_real(field, val_names[pair]);
        parameters_.define(name, std::move(value), local);
      }
    }
  }

  // PRMR(10) then the expression over the rest of the line. A long expression continues on the
  // lines after it whose PRMR columns are blank (such a line cannot start a definition).
  void read_parameter_expression(CardCursor& cursor, bool local) {
    while (true) {
      cursor.skip_blank_lines();
      if (cursor.done()) break;
      const DataLine& line = cursor.peek();
      // Not cut as a normal card: the expression may contain commas (`max(a,b)`). A comma
      // within the first 10 characters is free format's separator after PRMR.
      const std::size_t comma = line.text.substr(0, 10).find(',');
      const std::size_t split = comma == std::string_view::npos ? 10 : comma;
      const std::string_view prmr = trim(line.text.substr(0, std::min(split, line.text.size())));
      std::string expression(
          split < line.text.size() ? trim(line.text.substr(split + (comma == std::string_view::npos ? 0 : 1)))
                                   : std::string_view{});
      const Card card = cursor.next(standard_fields, "expression card");
      while (!cursor.done() && trim(cursor.peek().text.substr(0, 10)).empty() && !trim(cursor.peek().text).empty()) {
        expression += ' ';
        expression += cursor.next_text("expression continuation");
      }
      ParameterValue value;
      const std::string_view name = parameter_name(card, prmr, "PRMR", value.type);
      if (value.type == 'C') card.fail("PRMR", "a character parameter cannot take an expression");
      if (expression.empty()) card.fail("EXPRESSION", "is blank");
      std::string error;
      const auto result = parameters_.evaluate(expression, error);
      if (!result) card.fail("EXPRESSION", quoted(std::string_view(expression)) + ": " + error);
      // An integer parameter keeps the whole part, as a Fortran assignment to an integer does.
      value.number = value.type == 'I' ? std::trunc(*result) : *result;
      parameters_.define(name, std::move(value), local);
    }
  }

  static std::string_view parameter_name(const Card& card, std::string_view prmr,
                                         const char* field_name, char& type) {
    if (prmr.empty()) card.fail(field_name, "is blank");
    type = static_cast<char>(std::toupper(static_cast<unsigned char>(prmr.front())));
    const std::string_view name = trim(prmr.substr(1));
    if ((type != 'R' && type != 'I' && type != 'C') || name.empty())
      card.fail(field_name, quoted(prmr) + " is not a type letter (R, I or C) followed by a name");
    return name;
  }

  // Records the keyword for the warning list. For sections, materials, EOS, sets, curves, tables
  // and functions it also keeps the ID in the first field of the first data card (for *PART_
  // variants, the PID on the card after the heading), so that validate() can name the keyword a
  // reference points to. Never throws: an unreadable ID is 0.
  void record_unsupported(const KeywordBlock& block, bool long_format) {
    model::UnsupportedKeyword unsupported;
    unsupported.keyword = "*" + block.name;
    unsupported.where = {block.file, block.line};
    const std::string_view name = block.name;
    std::size_t card = block.data.size();  // the card with the ID; none by default
    if (name.starts_with("SECTION_") || name.starts_with("MAT_") || name.starts_with("EOS_") ||
        name.starts_with("SET_") || name.starts_with("DEFINE_CURVE") || name.starts_with("DEFINE_FUNCTION") ||
        name.starts_with("DEFINE_TABLE"))
      card = ends_with(name, "_TITLE") ? 1 : 0;
    else if (name.starts_with("PART_"))  // *PART_INERTIA etc.: a heading, then PID first
      card = 1;
    if (card < block.data.size()) unsupported.id = first_field_id(block.data[card].text, long_format);
    model_.unsupported.push_back(std::move(unsupported));
  }

  Id first_field_id(std::string_view text, bool long_format) const {
    const std::size_t comma = text.find(',');
    const std::size_t width = comma != std::string_view::npos ? comma : (long_format ? 20 : 10);
    std::string_view field = trim(text.substr(0, std::min(width, text.size())));
    if (!field.empty() && field.front() == '&') {
      const ParameterValue* value = parameters_.find(trim(field.substr(1)));
      // Only a value that is an ID converts: the cast of one beyond Id's range is undefined.
      const bool is_id = value && value->type != 'C' && std::abs(value->number) <= static_cast<double>(largest_id) &&
                         value->number == std::trunc(value->number);
      return is_id ? static_cast<Id>(value->number) : 0;
    }
    std::int64_t id = 0;
    return parse_integer(field, id) == IntegerParse::ok ? id : 0;
  }

  model::Model model_;
  Parameters parameters_;
  bool long_format_ = false;
};

}  // namespace

model::Model read_deck(const std::filesystem::path& path, model::CardShare cards) {
  return DeckReader(cards).read(path);
}

model::Model read_deck_text(std::string text, const std::filesystem::path& path, model::CardShare cards) {
  DeckFile file;
  file.assign(std::move(text), path);
  return DeckReader(cards).read(file);
}

}  // namespace spall::io::keyword
