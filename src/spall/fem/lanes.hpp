#pragma once
// Vectors and tensors whose components are a Real, or a simd::Pack that holds one component of
// several elements at once (an element a lane): the one-point hexahedra run side by side in the
// lanes (solid_elements.cpp), and the hexahedron's kinematics (hexahedron.hpp) are written once for
// these and for Eigen's vectors. Every operation goes lane by lane, so that a lane's result does not
// depend on what the other lanes hold.
#include <array>

#include "spall/core/simd.hpp"
#include "spall/core/types.hpp"

namespace spall::fem {

template <typename T>
struct LaneVector {
  using Scalar = T;
  T c[3];

  LaneVector() = default;
  LaneVector(T x, T y, T z) : c{x, y, z} {}
  T& operator[](int d) { return c[d]; }
  const T& operator[](int d) const { return c[d]; }

  friend LaneVector operator+(const LaneVector& a, const LaneVector& b) {
    return {a[0] + b[0], a[1] + b[1], a[2] + b[2]};
  }
  friend LaneVector operator-(const LaneVector& a, const LaneVector& b) {
    return {a[0] - b[0], a[1] - b[1], a[2] - b[2]};
  }
  friend LaneVector operator*(T s, const LaneVector& a) { return {s * a[0], s * a[1], s * a[2]}; }
  LaneVector& operator+=(const LaneVector& b) { return *this = *this + b; }
  friend T dot(const LaneVector& a, const LaneVector& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
  friend LaneVector cross(const LaneVector& a, const LaneVector& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
  }
};

// The same two products for Eigen's vectors, so that a function written for one serves both.
inline Real dot(const Vec3& a, const Vec3& b) { return a.dot(b); }
inline Vec3 cross(const Vec3& a, const Vec3& b) { return a.cross(b); }

template <typename V>
V zero_vector() {
  using S = typename V::Scalar;
  return V(S(0), S(0), S(0));
}

// A 3 x 3 tensor, m[i][j].
template <typename T>
struct LaneMatrix {
  T m[3][3];

  static LaneMatrix zero() {
    LaneMatrix z;
    for (auto& row : z.m)
      for (T& x : row) x = T(0);
    return z;
  }
  T trace() const { return m[0][0] + m[1][1] + m[2][2]; }
  friend LaneVector<T> operator*(const LaneMatrix& a, const LaneVector<T>& u) {
    LaneVector<T> out;
    for (int i = 0; i < 3; ++i) out[i] = a.m[i][0] * u[0] + a.m[i][1] * u[1] + a.m[i][2] * u[2];
    return out;
  }
  friend LaneMatrix operator/(const LaneMatrix& a, T s) {
    LaneMatrix out;
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) out.m[i][j] = a.m[i][j] / s;
    return out;
  }
  // this += u (x) w
  void add_outer(const LaneVector<T>& u, const LaneVector<T>& w) {
    for (int i = 0; i < 3; ++i)
      for (int j = 0; j < 3; ++j) m[i][j] += u[i] * w[j];
  }
};

}  // namespace spall::fem
