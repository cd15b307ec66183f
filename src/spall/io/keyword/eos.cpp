// *EOS_LINEAR_POLYNOMIAL, *EOS_GRUNEISEN, *EOS_MURNAGHAN: the pressure of a part whose *PART
// names them by EOSID. Each keyword defines one equation of state; card 2 may be left out.
#include <fmt/format.h>

#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

namespace {

// V0, the initial relative volume: blank or 0 read as 1. A pre-compressed start (V0 != 1) would
// need the particles' initial density changed too, which Spall does not do.
Real read_v0(const Card& card, int field) {
  Real v0 = card.real(field, "V0", 0.0);
  if (v0 == 0) v0 = 1;
  if (v0 != 1)
    card.fail("V0",
              fmt::format("{:g}: an initial relative volume other than 1 is not implemented", v0));
  return v0;
}

model::Eos start_eos(const Card& card, std::string keyword) {
  model::Eos eos;
  eos.id = card.required_integer(0, "EOSID");
  eos.keyword = std::move(keyword);
  eos.where = card.where();
  return eos;
}

}  // namespace

void read_eos_linear_polynomial(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card1 = cursor.next(standard_fields, "card 1 (EOSID C0 C1 C2 C3 C4 C5 C6)");
  model::Eos eos = start_eos(card1, "*EOS_LINEAR_POLYNOMIAL");
  model::EosLinearPolynomial polynomial;
  static constexpr const char* names[7] = {"C0", "C1", "C2", "C3", "C4", "C5", "C6"};
  for (int i = 0; i < 7; ++i) polynomial.c[i] = card1.real(i + 1, names[i], 0.0);
  if (const auto card2 = cursor.next_if_any(standard_fields)) {
    polynomial.e0 = card2->real(0, "E0", 0.0);
    polynomial.v0 = read_v0(*card2, 1);
  }
  cursor.expect_end("card 2", "one *EOS_LINEAR_POLYNOMIAL defines one equation of state");
  eos.params = polynomial;
  insert_unique(model.eos, eos.id, std::move(eos), card1, "equation of state");
}

void read_eos_gruneisen(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card1 = cursor.next(standard_fields, "card 1 (EOSID C S1 S2 S3 GAMMA0 A E0)");
  model::Eos eos = start_eos(card1, "*EOS_GRUNEISEN");
  model::EosGruneisen gruneisen;
  gruneisen.c = card1.required_real(1, "C");
  gruneisen.s1 = card1.real(2, "S1", 0.0);
  gruneisen.s2 = card1.real(3, "S2", 0.0);
  gruneisen.s3 = card1.real(4, "S3", 0.0);
  gruneisen.gamma0 = card1.real(5, "GAMMA0", 0.0);
  gruneisen.a = card1.real(6, "A", 0.0);
  gruneisen.e0 = card1.real(7, "E0", 0.0);
  if (!(gruneisen.c > 0))
    card1.fail("C", fmt::format("{:g}: the sound speed must be positive", gruneisen.c));
  if (const auto card2 = cursor.next_if_any(standard_fields)) {
    gruneisen.v0 = read_v0(*card2, 0);
    gruneisen.lcid = card2->integer(2, "LCID", 0);
    if (gruneisen.lcid != 0)
      card2->fail("LCID", "an energy deposition curve is not implemented; leave LCID 0");
  }
  cursor.expect_end("card 2", "one *EOS_GRUNEISEN defines one equation of state");
  eos.params = gruneisen;
  insert_unique(model.eos, eos.id, std::move(eos), card1, "equation of state");
}

void read_eos_murnaghan(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  if (call.title) cursor.next_text("title");
  const Card card = cursor.next(standard_fields, "card 1 (EOSID GAMMA K0 V0)");
  model::Eos eos = start_eos(card, "*EOS_MURNAGHAN");
  model::EosMurnaghan murnaghan;
  murnaghan.gamma = card.required_real(1, "GAMMA");
  murnaghan.k0 = card.required_real(2, "K0");
  murnaghan.v0 = read_v0(card, 3);
  if (!(murnaghan.gamma > 0))
    card.fail("GAMMA", fmt::format("{:g} must be positive", murnaghan.gamma));
  if (!(murnaghan.k0 > 0)) card.fail("K0", fmt::format("{:g} must be positive", murnaghan.k0));
  cursor.expect_end("card 1", "one *EOS_MURNAGHAN defines one equation of state");
  eos.params = murnaghan;
  insert_unique(model.eos, eos.id, std::move(eos), card, "equation of state");
}

}  // namespace spall::io::keyword
