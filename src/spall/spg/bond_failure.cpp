#include "spall/spg/bond_failure.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>

namespace spall::spg {

Real max_principal_stress(const Mat3& sigma) {
  Eigen::SelfAdjointEigenSolver<Mat3> eigen;
  eigen.compute(Real(0.5) * (sigma + sigma.transpose()), Eigen::EigenvaluesOnly);
  return eigen.eigenvalues()(2);  // ascending
}

Real max_shear_strain(const Mat3& F) {
  Eigen::SelfAdjointEigenSolver<Mat3> eigen;
  eigen.compute(F * F.transpose(), Eigen::EigenvaluesOnly);  // b = V^2: eigenvalues lambda_i^2
  const auto& stretch2 = eigen.eigenvalues();
  // (ln lambda_1 - ln lambda_3) / 2 = ln(lambda_1^2 / lambda_3^2) / 4
  return Real(0.25) * std::log(stretch2(2) / stretch2(0));
}

}  // namespace spall::spg
