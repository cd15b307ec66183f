// *MAT_PLASTIC_KINEMATIC (003), *MAT_PIECEWISE_LINEAR_PLASTICITY (024), *MAT_JOHNSON_COOK (015)
// and *MAT_NULL (009): the materials whose stress src/spall/materials updates. Each of the
// multi-card keywords defines one material (*MAT_NULL's one-line cards may repeat). A trailing
// card marked optional may be left out; its fields then take their defaults. Field values the
// constitutive library cannot run are refused here, at their line.
#include <fmt/format.h>

#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {

void require_positive(const Card& card, std::string_view name, Real value) {
  if (!(value > 0)) card.fail(name, fmt::format("must be positive (found {:g})", value));
}

void require_poisson_ratio(const Card& card, Real pr) {
  if (pr < 0 || pr >= 0.5) card.fail("PR", fmt::format("{:g} is outside [0, 0.5)", pr));
}

model::Material start_material(const Card& card, std::string keyword) {
  model::Material material;
  material.id = card.required_integer(0, "MID");
  material.keyword = std::move(keyword);
  material.where = card.where();
  return material;
}

}  // namespace

void read_mat_plastic_kinematic(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card1 = cursor.next(standard_fields, "card 1 (MID RO E PR SIGY ETAN BETA)");
  model::Material material = start_material(card1, "*MAT_PLASTIC_KINEMATIC");
  model::MatPlasticKinematic plastic;
  plastic.ro = card1.required_real(1, "RO");
  plastic.e = card1.required_real(2, "E");
  plastic.pr = card1.real(3, "PR", 0.0);
  plastic.sigy = card1.required_real(4, "SIGY");
  plastic.etan = card1.real(5, "ETAN", 0.0);
  plastic.beta = card1.real(6, "BETA", 0.0);
  require_positive(card1, "RO", plastic.ro);
  require_positive(card1, "E", plastic.e);
  require_poisson_ratio(card1, plastic.pr);
  require_positive(card1, "SIGY", plastic.sigy);
  // The plastic hardening modulus E ETAN / (E - ETAN) needs 0 <= ETAN < E.
  if (plastic.etan < 0 || plastic.etan >= plastic.e)
    card1.fail("ETAN",
               fmt::format("{:g} must be at least 0 and below E = {:g}", plastic.etan, plastic.e));
  if (plastic.beta < 0 || plastic.beta > 1)
    card1.fail("BETA",
               fmt::format("{:g} is outside [0, 1] (0 kinematic, 1 isotropic)", plastic.beta));

  if (const auto card2 = cursor.next_if_any(standard_fields)) {
    plastic.src = card2->real(0, "SRC", 0.0);
    plastic.srp = card2->real(1, "SRP", 0.0);
    plastic.fs = card2->real(2, "FS", 0.0);
    plastic.vp = card2->int32(3, "VP", 0);
    if (plastic.src < 0) card2->fail("SRC", fmt::format("{:g} is negative", plastic.src));
    if (plastic.src > 0 && !(plastic.srp > 0))
      card2->fail("SRP",
                  fmt::format("{:g}: the Cowper-Symonds exponent must be positive when SRC > 0",
                              plastic.srp));
    if (plastic.fs < 0)
      card2->fail("FS", fmt::format("{:g}: a negative FS (shell thinning failure) is not supported",
                                    plastic.fs));
    if (plastic.vp == 1)
      card2->fail(
          "VP",
          "1 (viscoplastic rate formulation) is not implemented; use 0 (scale the yield stress)");
    if (plastic.vp != 0) card2->fail("VP", fmt::format("{} is not 0 or 1", plastic.vp));
  }
  cursor.expect_end("card 2", "one *MAT_PLASTIC_KINEMATIC defines one material");
  material.params = plastic;
  insert_unique(model.materials, material.id, std::move(material), card1, "material");
}

void read_mat_piecewise_linear_plasticity(CardCursor& cursor, const KeywordCall& call,
                                          model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card1 = cursor.next(standard_fields, "card 1 (MID RO E PR SIGY ETAN FAIL TDEL)");
  model::Material material = start_material(card1, "*MAT_PIECEWISE_LINEAR_PLASTICITY");
  model::MatPiecewiseLinearPlasticity plastic;
  plastic.ro = card1.required_real(1, "RO");
  plastic.e = card1.required_real(2, "E");
  plastic.pr = card1.real(3, "PR", 0.0);
  plastic.sigy = card1.real(4, "SIGY", 0.0);
  plastic.etan = card1.real(5, "ETAN", 0.0);
  plastic.fail = card1.real(6, "FAIL", 1.0e21);
  plastic.tdel = card1.real(7, "TDEL", 0.0);
  require_positive(card1, "RO", plastic.ro);
  require_positive(card1, "E", plastic.e);
  require_poisson_ratio(card1, plastic.pr);
  if (plastic.fail < 0)
    card1.fail("FAIL", fmt::format("{:g}: a user failure subroutine (FAIL < 0) is not supported",
                                   plastic.fail));
  if (plastic.tdel != 0)
    card1.fail("TDEL", "deleting elements by their time step is not implemented; leave TDEL 0");

  const Card card2 = cursor.next(standard_fields, "card 2 (C P LCSS LCSR VP)");
  plastic.c = card2.real(0, "C", 0.0);
  plastic.p = card2.real(1, "P", 0.0);
  plastic.lcss = card2.integer(2, "LCSS", 0);
  plastic.lcsr = card2.integer(3, "LCSR", 0);
  plastic.vp = card2.int32(4, "VP", 0);
  if (plastic.c < 0) card2.fail("C", fmt::format("{:g} is negative", plastic.c));
  if (plastic.c > 0 && !(plastic.p > 0))
    card2.fail("P", fmt::format("{:g}: the Cowper-Symonds exponent must be positive when C > 0",
                                plastic.p));
  if (plastic.lcss < 0) card2.fail("LCSS", fmt::format("{} is not a curve ID", plastic.lcss));
  if (plastic.lcsr != 0)
    card2.fail("LCSR",
               "a strain-rate scaling curve is not implemented; use C and P (Cowper-Symonds)");
  if (plastic.vp == 1 || plastic.vp == 3)
    card2.fail("VP", fmt::format("{} ({}) is not implemented; use 0 or -1", plastic.vp,
                                 plastic.vp == 1 ? "viscoplastic" : "filtered rate, shells"));
  if (plastic.vp != 0 && plastic.vp != -1)
    card2.fail("VP", fmt::format("{} is not -1, 0, 1 or 3", plastic.vp));

  // Cards 3-4: up to eight (EPS, ES) points. A blank field reads as 0, and LS-DYNA ends the table
  // after the last point with a nonzero EPS or ES: LS-PrePost writes both cards all zero when LCSS
  // is used (or no table is), and zero pairs after the last point of a shorter table.
  const auto card3 = cursor.next_if_any(standard_fields);
  const auto card4 = card3 ? cursor.next_if_any(standard_fields) : std::nullopt;
  if (card3 && card4) {
    static constexpr const char* eps_names[8] = {"EPS1", "EPS2", "EPS3", "EPS4",
                                                 "EPS5", "EPS6", "EPS7", "EPS8"};
    static constexpr const char* es_names[8] = {"ES1", "ES2", "ES3", "ES4",
                                                "ES5", "ES6", "ES7", "ES8"};
    Real eps[8];
    Real es[8];
    int count = 0;
    for (int i = 0; i < 8; ++i) {
      eps[i] = card3->real(i, eps_names[i], 0.0);
      es[i] = card4->real(i, es_names[i], 0.0);
      if (eps[i] != 0 || es[i] != 0) count = i + 1;
    }
    for (int i = 0; i < count; ++i) {
      if (eps[i] < 0) card3->fail(eps_names[i], fmt::format("{:g} is negative", eps[i]));
      if (i > 0 && eps[i] <= eps[i - 1])
        card3->fail(eps_names[i], fmt::format("{:g} does not increase (the previous point is at {:g})",
                                              eps[i], eps[i - 1]));
      plastic.points.emplace_back(eps[i], es[i]);
    }
    if (plastic.points.size() == 1)
      card3->fail("EPS2", "one point does not make a hardening curve; give at least two");
  } else if (card3) {
    cursor.context().fail(card3->line(), "card 3 (EPS1..EPS8) needs card 4 (ES1..ES8) after it");
  }
  // Without a curve or points the yield stress is SIGY + Ep * eps_p, Ep = E ETAN / (E - ETAN).
  if (plastic.lcss == 0 && plastic.points.empty()) {
    require_positive(card1, "SIGY", plastic.sigy);
    if (plastic.etan < 0 || plastic.etan >= plastic.e)
      card1.fail("ETAN", fmt::format("{:g} must be at least 0 and below E = {:g}", plastic.etan,
                                     plastic.e));
  }
  cursor.expect_end("card 4", "one *MAT_PIECEWISE_LINEAR_PLASTICITY defines one material");
  material.params = std::move(plastic);
  insert_unique(model.materials, material.id, std::move(material), card1, "material");
}

void read_mat_johnson_cook(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card1 = cursor.next(standard_fields, "card 1 (MID RO G E PR DTF VP RATEOP)");
  model::Material material = start_material(card1, "*MAT_JOHNSON_COOK");
  model::MatJohnsonCook jc;
  jc.ro = card1.required_real(1, "RO");
  jc.g = card1.required_real(2, "G");
  jc.e = card1.real(3, "E", 0.0);
  jc.pr = card1.real(4, "PR", 0.0);
  jc.dtf = card1.real(5, "DTF", 0.0);
  jc.vp = card1.int32(6, "VP", 0);
  jc.rateop = card1.int32(7, "RATEOP", 0);
  require_positive(card1, "RO", jc.ro);
  require_positive(card1, "G", jc.g);
  if (jc.e < 0) card1.fail("E", fmt::format("{:g} is negative", jc.e));
  require_poisson_ratio(card1, jc.pr);
  if (jc.dtf != 0)
    card1.fail("DTF", "deleting elements by their time step is not implemented; leave DTF 0");
  if (jc.vp != 0)
    card1.fail("VP", fmt::format("{}: only 0 (scale the yield stress) is implemented", jc.vp));
  if (jc.rateop != 0)
    card1.fail(
        "RATEOP",
        fmt::format("{}: only 0 (log-linear Johnson-Cook rate term) is implemented", jc.rateop));

  const Card card2 = cursor.next(standard_fields, "card 2 (A B N C M TM TR EPSO)");
  jc.a = card2.required_real(0, "A");
  jc.b = card2.real(1, "B", 0.0);
  jc.n = card2.real(2, "N", 0.0);
  jc.c = card2.real(3, "C", 0.0);
  jc.m = card2.real(4, "M", 0.0);
  jc.tm = card2.required_real(5, "TM");
  jc.tr = card2.real(6, "TR", 0.0);
  jc.epso = card2.real(7, "EPSO", 0.0);
  if (jc.a < 0)
    card2.fail("A",
               fmt::format("{:g}: a curve for the strain term (A < 0) is not implemented", jc.a));
  if (jc.b < 0) card2.fail("B", fmt::format("{:g} is negative", jc.b));
  if (jc.n < 0) card2.fail("N", fmt::format("{:g} is negative", jc.n));
  if (jc.c < 0) card2.fail("C", fmt::format("{:g} is negative", jc.c));
  // (1 - T*^M) with M = 0 would be 0 at every temperature: no strength at all.
  require_positive(card2, "M", jc.m);
  if (!(jc.tm > jc.tr))
    card2.fail("TM",
               fmt::format("{:g} must be above the room temperature TR = {:g}", jc.tm, jc.tr));

  const Card card3 = cursor.next(standard_fields, "card 3 (CP PC SPALL IT D1 D2 D3 D4)");
  jc.cp = card3.required_real(0, "CP");
  jc.pc = card3.real(1, "PC", 0.0);
  jc.spall = card3.int32(2, "SPALL", 2);
  if (jc.spall == 0) jc.spall = 2;  // LS-DYNA: 0 means the default, 2
  jc.it = card3.int32(3, "IT", 0);
  jc.d1 = card3.real(4, "D1", 0.0);
  jc.d2 = card3.real(5, "D2", 0.0);
  jc.d3 = card3.real(6, "D3", 0.0);
  jc.d4 = card3.real(7, "D4", 0.0);
  require_positive(card3, "CP", jc.cp);
  if (jc.pc > 0)
    card3.fail("PC", fmt::format("{:g}: the tensile cutoff must be 0 or negative", jc.pc));
  if (jc.spall < 1 || jc.spall > 3)
    card3.fail("SPALL", fmt::format("{} is not 1, 2 or 3", jc.spall));
  // SPALL 2 and 3 spall a point whose tension reaches -PC: with PC = 0, at the first tension.
  if (jc.spall != 1 && jc.pc == 0)
    card3.fail("PC", fmt::format("0 with SPALL {} would spall at any tension; give PC < 0 "
                                 "(the spall strength)",
                                 jc.spall));
  if (jc.it != 0 && jc.it != 1) card3.fail("IT", fmt::format("{} is not 0 or 1", jc.it));

  if (const auto card4 = cursor.next_if_any(standard_fields)) {
    jc.d5 = card4->real(0, "D5", 0.0);
    jc.c2 = card4->real(1, "C2/P/XNP/D", 0.0);
    jc.erod = card4->real(2, "EROD", 0.0);
    jc.efmin = card4->real(3, "EFMIN", 1.0e-6);
    jc.numint = card4->real(4, "NUMINT", 0.0);
    jc.k = card4->real(5, "K", 0.0);
    jc.eps1 = card4->real(6, "EPS1", 0.0);
    if (jc.efmin < 0) card4->fail("EFMIN", fmt::format("{:g} is negative", jc.efmin));
  }
  // The rate terms of the flow stress (C) and of the failure strain (D4) are logs of the plastic
  // strain rate over EPSO.
  if ((jc.c != 0 || jc.d4 != 0) && !(jc.epso > 0))
    card2.fail("EPSO", fmt::format("{:g}: the reference strain rate must be positive when C or D4 "
                                   "is not 0",
                                   jc.epso));
  cursor.expect_end("card 4", "one *MAT_JOHNSON_COOK defines one material");
  material.params = jc;
  insert_unique(model.materials, material.id, std::move(material), card1, "material");
}

void read_mat_null(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  while (true) {
    cursor.skip_blank_lines();
    if (cursor.done()) break;
    if (call.title) cursor.next_text("title");
    const Card card = cursor.next(standard_fields, "card 1 (MID RO PC MU TEROD CEROD YM PR)");
    model::Material material = start_material(card, "*MAT_NULL");
    model::MatNull null;
    null.ro = card.required_real(1, "RO");
    null.pc = card.real(2, "PC", 0.0);
    null.mu = card.real(3, "MU", 0.0);
    null.terod = card.real(4, "TEROD", 0.0);
    null.cerod = card.real(5, "CEROD", 0.0);
    null.ym = card.real(6, "YM", 0.0);
    null.pr = card.real(7, "PR", 0.0);
    require_positive(card, "RO", null.ro);
    if (null.pc > 0)
      card.fail("PC", fmt::format("{:g}: the pressure cutoff must be 0 or negative", null.pc));
    if (null.mu < 0) card.fail("MU", fmt::format("{:g} is negative", null.mu));
    if (null.terod != 0 || null.cerod != 0)
      card.fail(null.terod != 0 ? "TEROD" : "CEROD",
                "erosion by relative volume is not implemented; leave TEROD and CEROD 0");
    material.params = null;
    insert_unique(model.materials, material.id, std::move(material), card, "material");
  }
}

}  // namespace spall::io::keyword
