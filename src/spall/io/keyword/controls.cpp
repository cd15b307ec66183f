// *CONTROL_TERMINATION, *CONTROL_TIMESTEP, *CONTROL_BULK_VISCOSITY, *DATABASE_BINARY_D3PLOT,
// *DATABASE_GLSTAT, *DATABASE_RWFORC. Each reads its first card; the later optional cards of *CONTROL_TIMESTEP
// (mass-scaling details) and *DATABASE_BINARY_D3PLOT (IOOPT, RATE, ...) are not used by Spall.
#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {
// Blank and 0 read alike in LS-DYNA, so a 0 takes the documented default.
Real zero_means_default(Real value, Real fallback) { return value == 0.0 ? fallback : value; }

void refuse_second(const CardCursor& cursor, bool already_read, const SourceLocation& first) {
  if (already_read)
    cursor.context().fail(cursor.line_of_block(), "given twice (first at " + first.file + ":" +
                                                      std::to_string(first.line) + ")");
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
  termination.endcyc = static_cast<int>(card.integer(1, "ENDCYC", 0));
  termination.dtmin = card.real(2, "DTMIN", 0.0);
  termination.endeng = card.real(3, "ENDENG", 0.0);
  termination.endmas = zero_means_default(card.real(4, "ENDMAS", 0.0), 1.0e8);
  termination.where = card.where();
  model.termination = termination;
}

void read_control_timestep(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (DTINIT TSSFAC ISDO TSLIMT DT2MS LCTM)");
  model::ControlTimestep timestep;
  timestep.dtinit = card.real(0, "DTINIT", 0.0);
  // TSSFAC < 0 is the ID of a curve of the factor over time, kept negative as LS-DYNA has it.
  timestep.tssfac = zero_means_default(card.real(1, "TSSFAC", 0.0), 0.9);
  timestep.isdo = static_cast<int>(card.integer(2, "ISDO", 0));
  timestep.tslimt = card.real(3, "TSLIMT", 0.0);
  timestep.dt2ms = card.real(4, "DT2MS", 0.0);
  timestep.lctm = card.integer(5, "LCTM", 0);
  timestep.where = card.where();
  model.timestep = timestep;
}

void read_control_bulk_viscosity(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (Q1 Q2 TYPE)");
  model::ControlBulkViscosity viscosity;
  viscosity.q1 = zero_means_default(card.real(0, "Q1", 0.0), 1.5);
  viscosity.q2 = zero_means_default(card.real(1, "Q2", 0.0), 0.06);
  viscosity.type = static_cast<int>(card.integer(2, "TYPE", 0));
  if (viscosity.type == 0) viscosity.type = 1;
  if (viscosity.type < -2 || viscosity.type > 2)
    card.fail("TYPE", quoted(card.text(2)) + " is not -2, -1, 1 or 2");
  viscosity.where = card.where();
  model.bulk_viscosity = viscosity;
}

void read_database_binary_d3plot(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (DT LCDT BEAM NPLTC PSETID)");
  model::OutputInterval output;
  output.dt = card.real(0, "DT", 0.0);
  output.lcdt = card.integer(1, "LCDT", 0);
  output.beam = static_cast<int>(card.integer(2, "BEAM", 0));
  output.npltc = static_cast<int>(card.integer(3, "NPLTC", 0));
  if (output.dt < 0.0) card.fail("DT", quoted(card.text(0)) + " is negative");
  output.where = card.where();
  model.d3plot = output;
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

void read_database_rwforc(CardCursor& cursor, const KeywordCall&, model::Model& model) {
  const Card card = cursor.next(standard_fields, "card 1 (DT BINARY LCUR IOOPT)");
  model::OutputInterval output;
  output.dt = card.real(0, "DT", 0.0);
  output.lcdt = card.integer(2, "LCUR", 0);
  // Blank and 0 read alike: IOOPT 1, the next output LCUR(now) after this one.
  output.ioopt = static_cast<int>(card.integer(3, "IOOPT", 0));
  if (output.ioopt == 0) output.ioopt = 1;
  if (output.dt < 0.0) card.fail("DT", quoted(card.text(0)) + " is negative");
  if (output.ioopt < 1 || output.ioopt > 3)
    card.fail("IOOPT", quoted(card.text(3)) + " is not 1, 2 or 3");
  output.where = card.where();
  model.rwforc = output;
}

}  // namespace spall::io::keyword
