#pragma once
// *DEFINE_CURVE: a piecewise-linear function of time (or of any abscissa), with LS-DYNA's scale
// factors and offsets: value(t) = SFO * f((t - OFFA) / SFA) + OFFO, where the points are the curve
// as tabulated. Beyond the last point the curve is extrapolated with a constant value, as LS-DYNA
// does for load curves.
#include <utility>
#include <vector>

#include "spall/core/error.hpp"
#include "spall/core/types.hpp"

namespace spall::model {

struct Curve {
  Id id = 0;
  int sidr = 0;
  Real sfa = 1.0;
  Real sfo = 1.0;
  Real offa = 0.0;
  Real offo = 0.0;
  std::vector<std::pair<Real, Real>> points;  // (abscissa, ordinate) as read, strictly increasing
  SourceLocation where;

  Real value(Real t) const;
};

}  // namespace spall::model
