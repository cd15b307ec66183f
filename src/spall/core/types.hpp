#pragma once
// Scalar and small fixed-size types used everywhere in Spall.
#include <cstdint>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace spall {

using Real = double;
using Id = std::int64_t;         // user-facing IDs from the deck (node, part, element, set, curve)
using Index = std::int32_t;      // dense internal index into a store

using Vec3 = Eigen::Matrix<Real, 3, 1>;
using Mat3 = Eigen::Matrix<Real, 3, 3>;

}  // namespace spall
