#include "spall/model/curve.hpp"

#include <algorithm>

namespace spall::model {

Real Curve::value(Real t) const {
  if (points.empty()) return offo;
  // *DEFINE_CURVE: the abscissa is scaled by SFA and shifted by OFFA, the ordinate by SFO, OFFO.
  const Real a = (t - offa) / sfa;
  Real f;
  if (a <= points.front().first) {
    f = points.front().second;
  } else if (a >= points.back().first) {
    f = points.back().second;
  } else {
    auto upper = std::upper_bound(points.begin(), points.end(), a,
                                  [](Real x, const auto& p) { return x < p.first; });
    auto lower = upper - 1;
    const Real s = (a - lower->first) / (upper->first - lower->first);
    f = lower->second + s * (upper->second - lower->second);
  }
  return sfo * f + offo;
}

}  // namespace spall::model
