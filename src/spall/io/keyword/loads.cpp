// *LOAD_BODY_X / _Y / _Z.
#include "spall/io/keyword/keyword_readers.hpp"

namespace spall::io::keyword {

void read_load_body(CardCursor& cursor, const KeywordCall& call, model::Model& model) {
  const char axis = call.base.back();  // LOAD_BODY_X, _Y or _Z
  const Card card = cursor.next(standard_fields, "card 1 (LCID SF LCIDDR XC YC ZC CID)");
  model::BodyLoad load;
  load.direction = axis - 'X';
  load.lcid = card.required_integer(0, "LCID");
  // Blank and 0 read alike in LS-DYNA: both are the default scale 1.0.
  load.sf = card.real(1, "SF", 0.0);
  if (load.sf == 0.0) load.sf = 1.0;
  load.lciddr = card.integer(2, "LCIDDR", 0);
  load.xc = Vec3(card.real(3, "XC", 0.0), card.real(4, "YC", 0.0), card.real(5, "ZC", 0.0));
  load.cid = card.integer(6, "CID", 0);
  load.where = card.where();
  model.body_loads.push_back(std::move(load));
}

}  // namespace spall::io::keyword
