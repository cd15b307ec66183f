#include "spall/spg/rk_shape.hpp"

#include <Eigen/Cholesky>

namespace spall::spg {

namespace {
using Vec4 = Eigen::Matrix<Real, 4, 1>;
using Mat4 = Eigen::Matrix<Real, 4, 4>;

KernelValue window(KernelShape shape, const KernelSample& s) {
  KernelValue k = kernel_value(shape, s.map * s.y, s.support);
  if (k.value != 0) k.gradient = s.map.transpose() * k.gradient;  // chain rule through the map
  return k;
}
}  // namespace

Real rk_shape_functions(KernelShape shape, std::span<const KernelSample> samples, const Vec3& scale,
                        std::span<Real> psi, std::span<Vec3> grad) {
  const Vec3 inv_s = scale.cwiseInverse();
  Mat4 M = Mat4::Zero();
  Mat4 dM[3] = {Mat4::Zero(), Mat4::Zero(), Mat4::Zero()};
  // First pass: the moment matrix and its derivatives. The windows are kept in psi / grad until
  // the second pass overwrites them.
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const KernelValue w = window(shape, samples[k]);
    psi[k] = w.value;
    grad[k] = w.gradient;
    if (w.value == 0 && w.gradient.isZero()) continue;
    Vec4 H;
    H << 1, samples[k].y.cwiseProduct(inv_s);
    const Mat4 HH = H * H.transpose();
    M.noalias() += w.value * HH;
    for (int j = 0; j < 3; ++j) {
      // H_,j = e_{j+1} / s_j: (H_,j H^T + H H_,j^T) phi + H H^T phi_,j
      Mat4 d = w.gradient[j] * HH;
      d.row(j + 1) += (w.value * inv_s[j]) * H.transpose();
      d.col(j + 1) += (w.value * inv_s[j]) * H;
      dM[j] += d;
    }
  }
  const Eigen::LDLT<Mat4> ldlt(M);
  // The smallest over the largest pivot of the pivoted LDL^T: zero (to round-off) exactly when M
  // is singular, and small when it is nearly so. (Eigen's rcond() does not see zero pivots.)
  const auto D = ldlt.vectorD().cwiseAbs();
  const Real rcond = ldlt.info() == Eigen::Success && D.maxCoeff() > 0 ? D.minCoeff() / D.maxCoeff() : 0;
  if (!(rcond >= min_moment_rcond)) return rcond;
  const Vec4 b = ldlt.solve(Vec4::UnitX());
  Vec4 db[3];
  for (int j = 0; j < 3; ++j) db[j] = -ldlt.solve(dM[j] * b);
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const Real phi = psi[k];
    const Vec3 dphi = grad[k];
    if (phi == 0 && dphi.isZero()) continue;
    Vec4 H;
    H << 1, samples[k].y.cwiseProduct(inv_s);
    const Real bH = b.dot(H);
    psi[k] = bH * phi;
    for (int j = 0; j < 3; ++j)
      grad[k][j] = db[j].dot(H) * phi + b[j + 1] * inv_s[j] * phi + bH * dphi[j];
  }
  return rcond;
}

bool shepard_shape_functions(KernelShape shape, std::span<const KernelSample> samples,
                             std::span<Real> psi, std::span<Vec3> grad) {
  Real sum = 0;
  Vec3 dsum = Vec3::Zero();
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const KernelValue w = window(shape, samples[k]);
    psi[k] = w.value;
    grad[k] = w.gradient;
    sum += w.value;
    dsum += w.gradient;
  }
  if (!(sum > 0)) return false;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    // (phi / S)_,j = phi_,j / S - phi S_,j / S^2
    grad[k] = grad[k] / sum - psi[k] * dsum / (sum * sum);
    psi[k] /= sum;
  }
  return true;
}

}  // namespace spall::spg
