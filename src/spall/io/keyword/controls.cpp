// *CONTROL_TERMINATION, *CONTROL_TIMESTEP, *CONTROL_BULK_VISCOSITY, *CONTROL_SPH,
// *SPALL_SPH_ARTIFICIAL_STRESS, *SPALL_SPH_COLOUR_FIELD, *SPALL_SPH_TIMESTEP, *SPALL_RESIDUAL_STRESS,
// *DATABASE_BINARY_D3PLOT, *DATABASE_BINARY_RUNRSF, *DATABASE_GLSTAT, *DATABASE_RWFORC,
// *DATABASE_RCFORC. Each
// reads its first card; the later optional cards of *CONTROL_TIMESTEP
// (mass-scaling details) and *DATABASE_BINARY_D3PLOT (IOOPT, RATE, ...) are not used by Spall.
#include <cmath>

#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {
// Blank and 0 read alike in LS-DYNA, so a 0 takes the documented default.
Real zero_means_default(Real value, Real fallback) { return value == 0.0 ? fallback : value; }

void refuse_second(const CardCursor& cursor, bool already_read, const SourceLocation& first) {
  if (already_read)
    cursor.context().fail(cursor.line_of_block(), "given twice (first at " + to_string(first) + ")");
}
}  // namespace

void read_control_termination(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  refuse_second(cursor, model.termination.has_value(),
                model.termination ? model.termination->where : SourceLocation{});
  const Card card = cursor.next(standard_fields, "card 1 (ENDTIM ENDCYC DTMIN ENDENG ENDMAS)");
  model::ControlTermination termination;
  termination.endtim = card.required_real(0, "ENDTIM");
  if (termination.endtim <= 0.0)
    card.fail("ENDTIM", quoted(card.text(0)) + " must be greater than 0");
  termination.endcyc = card.int32(1, "ENDCYC", 0);
  termination.dtmin = card.real(2, "DTMIN", 0.0);
  termination.endeng = card.real(3, "ENDENG", 0.0);
  termination.endmas = zero_means_default(card.real(4, "ENDMAS", 0.0), 1.0e8);
  termination.where = card.where();
  model.termination = termination;
}

// SOLN 0 is the structural analysis Spall runs; the other fields (NLQ ISNAN LCINT ...) tune the
// thermal solver or the input checks, and are not read.
void read_control_solution(CardCursor& cursor, const KeywordCall&, model::Model&) {
  const Card card = cursor.next(standard_fields, "card 1 (SOLN NLQ ISNAN LCINT ...)");
  const auto soln = card.integer(0, "SOLN", 0);
  if (soln == 1 || soln == 2)
    card.fail("SOLN", std::string(soln == 1 ? "1 (thermal only)" : "2 (coupled thermal-structural)") +
                          ": Spall solves no heat equation and cannot run a thermal analysis; SOLN 0 is "
                          "the structural one");
  if (soln != 0) card.fail("SOLN", quoted(card.text(0)) + " is not 0, 1 or 2");
}

void read_control_timestep(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (DTINIT TSSFAC ISDO TSLIMT DT2MS LCTM ERODE MS1ST)");
  model::ControlTimestep timestep;
  timestep.dtinit = card.real(0, "DTINIT", 0.0);
  // TSSFAC < 0 is the ID of a curve of the factor over time, kept negative as LS-DYNA has it.
  timestep.tssfac = zero_means_default(card.real(1, "TSSFAC", 0.0), 0.9);
  if (timestep.tssfac < 0 && (timestep.tssfac != std::trunc(timestep.tssfac) || timestep.tssfac < -largest_id))
    card.fail("TSSFAC", quoted(card.text(1)) + ": a negative TSSFAC is a curve ID, a whole number");
  timestep.isdo = card.int32(2, "ISDO", 0);
  timestep.tslimt = card.real(3, "TSLIMT", 0.0);
  timestep.dt2ms = card.real(4, "DT2MS", 0.0);
  timestep.lctm = card.integer(5, "LCTM", 0);
  // ERODE: its digits switch erosion on for solids (units), shells (tens) and beams (hundreds).
  timestep.erode = card.int32(6, "ERODE", 0);
  const int e = timestep.erode;
  if (e < 0 || e > 111 || e % 10 > 1 || e / 10 % 10 > 1)
    card.fail("ERODE", quoted(card.text(6)) + " is not 0, 1, 10, 11, 100, 101, 110 or 111");
  timestep.ms1st = card.int32(7, "MS1ST", 0);
  timestep.where = card.where();
  model.timestep = timestep;
}

void read_control_bulk_viscosity(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (Q1 Q2 TYPE)");
  model::ControlBulkViscosity viscosity;
  viscosity.q1 = zero_means_default(card.real(0, "Q1", 0.0), 1.5);
  viscosity.q2 = zero_means_default(card.real(1, "Q2", 0.0), 0.06);
  viscosity.type = card.int32(2, "TYPE", 0);
  if (viscosity.type == 0) viscosity.type = 1;
  if (viscosity.type < -2 || viscosity.type > 2)
    card.fail("TYPE", quoted(card.text(2)) + " is not -2, -1, 1 or 2");
  viscosity.where = card.where();
  model.bulk_viscosity = viscosity;
}

void read_damping_global(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  refuse_second(cursor, model.damping_global.has_value(),
                model.damping_global ? model.damping_global->where : SourceLocation{});
  const Card card = cursor.next(standard_fields, "card 1 (LCID VALDMP STX STY STZ SRX SRY SRZ)");
  model::DampingGlobal damping;
  damping.lcid = card.integer(0, "LCID", 0);
  damping.valdmp = card.real(1, "VALDMP", 0.0);
  static constexpr const char* names[6] = {"STX", "STY", "STZ", "SRX", "SRY", "SRZ"};
  Real scale[6];
  bool all_zero = true;
  for (int k = 0; k < 6; ++k) {
    scale[k] = card.real(2 + k, names[k], 0.0);
    if (scale[k] < 0) card.fail(names[k], quoted(card.text(2 + k)) + " is negative");
    all_zero = all_zero && scale[k] == 0;
  }
  // LS-DYNA: when all six scale factors are 0, all six default to 1.
  for (int k = 0; k < 3; ++k) {
    damping.translation_scale[k] = all_zero ? 1.0 : scale[k];
    damping.rotation_scale[k] = all_zero ? 1.0 : scale[3 + k];
  }
  if (damping.valdmp < 0) card.fail("VALDMP", quoted(card.text(1)) + " is negative");
  damping.where = card.where();
  model.damping_global = damping;
}

void read_control_sph(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  refuse_second(cursor, model.control_sph.has_value(),
                model.control_sph ? model.control_sph->where : SourceLocation{});
  model::ControlSph sph;
  const Card card1 = cursor.next(standard_fields, "card 1 (NCBS BOXID DT IDIM NMNEIGH FORM START MAXV)");
  sph.ncbs = card1.int32(0, "NCBS", 1);
  if (sph.ncbs == 0) sph.ncbs = 1;
  sph.boxid = card1.integer(1, "BOXID", 0);
  sph.dt = zero_means_default(card1.real(2, "DT", 0.0), 1.0e20);
  sph.idim = card1.int32(3, "IDIM", 3);
  if (sph.idim == 0) sph.idim = 3;
  sph.nmneigh = card1.int32(4, "NMNEIGH", 150);
  sph.form = card1.int32(5, "FORM", 1);
  sph.start = card1.real(6, "START", 0.0);
  sph.maxv = zero_means_default(card1.real(7, "MAXV", 0.0), 1.0e15);
  if (sph.ncbs < 0) card1.fail("NCBS", quoted(card1.text(0)) + " is negative");
  if (sph.idim != 3 && sph.idim != 2 && sph.idim != -2)
    card1.fail("IDIM", quoted(card1.text(3)) + " is not 3, 2 or -2");
  sph.where = card1.where();
  sph.card_where[0] = card1.where();
  if (auto card2 = cursor.next_if_any(standard_fields)) {
    sph.cont = card2->int32(0, "CONT", 0);
    sph.deriv = card2->int32(1, "DERIV", 0);
    sph.ini = card2->int32(2, "INI", 0);
    sph.ishow = card2->int32(3, "ISHOW", 0);
    sph.ierod = card2->int32(4, "IEROD", 0);
    sph.icont = card2->int32(5, "ICONT", 0);
    sph.iavis = card2->int32(6, "IAVIS", 0);
    sph.isymp = card2->int32(7, "ISYMP", 100);
    sph.card_where[1] = card2->where();
    if (auto card3 = cursor.next_if_any(standard_fields)) {
      sph.ithk = card3->int32(0, "ITHK", 0);
      sph.istab = card3->int32(1, "ISTAB", 0);
      sph.ql = zero_means_default(card3->real(2, "QL", 0.0), 0.01);
      sph.sphsort = card3->int32(4, "SPHSORT", 0);
      sph.ishift = card3->int32(5, "ISHIFT", 0);
      sph.card_where[2] = card3->where();
    }
  }
  model.control_sph = sph;
}

void read_spall_sph_artificial_stress(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  refuse_second(cursor, model.sph_artificial_stress.has_value(),
                model.sph_artificial_stress ? model.sph_artificial_stress->where : SourceLocation{});
  model::SphArtificialStress stress;
  // The card is optional: the keyword alone switches the artificial stress on with the defaults.
  if (auto card = cursor.next_if_any(standard_fields)) {
    stress.epsilon = zero_means_default(card->real(0, "EPS", 0.0), 0.3);
    stress.exponent = zero_means_default(card->real(1, "N", 0.0), 4.0);
    if (stress.epsilon < 0) card->fail("EPS", quoted(card->text(0)) + " is negative");
    if (stress.exponent < 1) card->fail("N", quoted(card->text(1)) + " is below 1");
    stress.where = card->where();
  } else {
    stress.where = cursor.context().where(cursor.line_of_block());
  }
  model.sph_artificial_stress = stress;
}

void read_spall_sph_colour_field(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    const Card card = cursor.next(standard_fields, "card 1 (PID TREAT NFRAC NTHRESH LAYERS INTERVAL TFORM TAU)");
    model::SphColourField colour;
    colour.pid = card.integer(0, "PID", 0);
    colour.treat = card.int32(1, "TREAT", 0);
    colour.neighbour_fraction = zero_means_default(card.real(2, "NFRAC", 0.0), 0.8);
    colour.normal_threshold = zero_means_default(card.real(3, "NTHRESH", 0.0), 0.3);
    colour.layers = card.int32(4, "LAYERS", 1);
    colour.interval = card.int32(5, "INTERVAL", 1);
    if (colour.interval == 0) colour.interval = 1;
    colour.form = card.int32(6, "TFORM", 0);
    if (colour.form == 0) colour.form = 1;
    colour.relaxation = zero_means_default(card.real(7, "TAU", 0.0), 100.0);
    if (colour.pid < 0) card.fail("PID", quoted(card.text(0)) + " is negative");
    if (colour.treat != 0 && colour.treat != 1) card.fail("TREAT", quoted(card.text(1)) + " is not 0 or 1");
    if (colour.neighbour_fraction <= 0 || colour.neighbour_fraction > 1)
      card.fail("NFRAC", quoted(card.text(2)) + " is not in (0, 1]");
    if (colour.normal_threshold < 0) card.fail("NTHRESH", quoted(card.text(3)) + " is negative");
    if (colour.layers < 0) card.fail("LAYERS", quoted(card.text(4)) + " is negative");
    if (colour.interval < 0) card.fail("INTERVAL", quoted(card.text(5)) + " is negative");
    if (colour.form != 1 && colour.form != 2) card.fail("TFORM", quoted(card.text(6)) + " is not 1 or 2");
    if (colour.relaxation < 0) card.fail("TAU", quoted(card.text(7)) + " is negative");
    colour.where = card.where();
    for (const auto& other : model.sph_colour_fields)
      if (other.pid == colour.pid)
        card.fail("PID", "part " + std::to_string(colour.pid) + " already has a card (at " +
                             to_string(other.where) + ")");
    model.sph_colour_fields.push_back(colour);
  }
}

void read_spall_sph_timestep(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  refuse_second(cursor, model.sph_timestep.has_value(),
                model.sph_timestep ? model.sph_timestep->where : SourceLocation{});
  const Card card = cursor.next(standard_fields, "card 1 (RULE)");
  model::SphTimestep timestep;
  timestep.rule = card.zero_or_one(0, "RULE");
  timestep.where = card.where();
  model.sph_timestep = timestep;
}

void read_spall_residual_stress(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  refuse_second(cursor, model.sph_residual_stress.has_value(),
                model.sph_residual_stress ? model.sph_residual_stress->where : SourceLocation{});
  model::SphResidualStress residual;
  residual.where = cursor.context().where(cursor.line_of_block());
  if (auto card = cursor.next_if_any(standard_fields)) {
    residual.yield_fraction = zero_means_default(card->real(0, "FRAC", 0.0), 0.5);
    residual.strain_rate = card->real(1, "RATE", 0.0);
    residual.at_output = card->int32(2, "OUTPUT", 0);
    if (residual.yield_fraction < 0) card->fail("FRAC", quoted(card->text(0)) + " is negative");
    if (residual.strain_rate < 0) card->fail("RATE", quoted(card->text(1)) + " is negative");
    if (residual.at_output != 0 && residual.at_output != 1)
      card->fail("OUTPUT", quoted(card->text(2)) + " is not 0 or 1");
    residual.where = card->where();
  }
  model.sph_residual_stress = residual;
}

void read_database_binary_d3plot(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (DT LCDT BEAM NPLTC PSETID)");
  model::OutputInterval output;
  output.dt = card.real(0, "DT", 0.0);
  output.lcdt = card.integer(1, "LCDT", 0);
  output.beam = card.int32(2, "BEAM", 0);
  output.npltc = card.int32(3, "NPLTC", 0);
  if (output.dt < 0.0) card.fail("DT", quoted(card.text(0)) + " is negative");
  output.where = card.where();
  model.d3plot = output;
}

// CYCL and NR; the card's other fields (BEAM, NPLTC, PSETID) belong to the plot files of the
// same card layout and mean nothing for a restart file.
void read_database_binary_runrsf(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (CYCL NR BEAM NPLTC PSETID)");
  model::RestartOutput output;
  output.cycles = card.integer(0, "CYCL", 0);
  output.files = card.int32(1, "NR", 1);
  if (output.cycles <= 0) card.fail("CYCL", quoted(card.text(0)) + " is not a positive number of cycles");
  if (output.files == 0) output.files = 1;
  if (output.files < 0 || output.files > 99) card.fail("NR", quoted(card.text(1)) + " is not 1 to 99 files");
  static constexpr std::pair<int, const char*> plot_fields[] = {{2, "BEAM"}, {3, "NPLTC"}, {4, "PSETID"}};
  for (const auto& [field, name] : plot_fields)
    if (card.integer(field, name, 0) != 0)
      card.fail(name, quoted(card.text(field)) + " applies to plot files, not to restart files: leave it blank");
  output.where = card.where();
  model.runrsf = output;
}

void read_database_glstat(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (DT BINARY LCUR IOOPT)");
  model::OutputInterval output;
  output.dt = card.real(0, "DT", 0.0);
  output.lcdt = card.integer(2, "LCUR", 0);
  if (output.dt < 0.0) card.fail("DT", quoted(card.text(0)) + " is negative");
  output.where = card.where();
  model.glstat = output;
}

// BINARY is not read: Spall writes its CSV file whatever it says. DTHF BINHF give the interval of a
// second, high-frequency binout, which Spall does not write: DTHF must be 0 or blank.
model::OutputInterval read_history_interval(CardCursor& cursor, bool high_frequency) {
  const Card card = cursor.next(standard_fields, high_frequency ? "card 1 (DT BINARY LCUR IOOPT DTHF BINHF)"
                                                                : "card 1 (DT BINARY LCUR IOOPT)");
  if (high_frequency && card.real(4, "DTHF", 0.0) != 0.0)
    card.fail("DTHF", quoted(card.text(4)) + ": the high-frequency output is not written; give its interval as DT");
  model::OutputInterval output;
  output.dt = card.real(0, "DT", 0.0);
  output.lcdt = card.integer(2, "LCUR", 0);
  // Blank and 0 read alike: IOOPT 1, the next output LCUR(now) after this one.
  output.ioopt = card.int32(3, "IOOPT", 0);
  if (output.ioopt == 0) output.ioopt = 1;
  if (output.dt < 0.0) card.fail("DT", quoted(card.text(0)) + " is negative");
  if (output.ioopt < 1 || output.ioopt > 3)
    card.fail("IOOPT", quoted(card.text(3)) + " is not 1, 2 or 3");
  output.where = card.where();
  return output;
}

// ELOUT's optional card 2 asks for each element kind's extra history variables (solids, shells,
// thick shells, beams), which elout.csv does not hold: each must be 0 or blank.
void read_database_elout(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  model.elout = read_history_interval(cursor, true);
  if (cursor.done()) return;
  const Card card = cursor.next(standard_fields, "card 2 (OPTION1 OPTION2 OPTION3 OPTION4)");
  for (int k = 0; k < 4; ++k) {
    const std::string name = "OPTION" + std::to_string(k + 1);
    if (card.int32(k, name, 0) != 0)
      card.fail(name, quoted(card.text(k)) + ": elout.csv holds no history variables; leave it 0");
  }
}

// Cards of eight IDs (blank or 0: none), nodes' or elements' or, with _SET, node sets' or solid sets'.
void read_database_history(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  const bool solids = call.base.starts_with("DATABASE_HISTORY_SOLID");
  while (!cursor.done()) {
    const Card card = cursor.next(standard_fields, "card (ID1 ... ID8)");
    model::HistoryIds history;
    history.sets = call.base.ends_with("_SET");
    history.where = card.where();
    for (int k = 0; k < 8; ++k) {
      const Id id = card.integer(k, id_field_names[k], 0);
      if (id < 0) card.fail(id_field_names[k], quoted(card.text(k)) + " is negative");
      if (id != 0) history.ids.push_back(id);
    }
    (solids ? model.history_solids : model.history_nodes).push_back(std::move(history));
  }
}

}  // namespace spall::io::keyword
