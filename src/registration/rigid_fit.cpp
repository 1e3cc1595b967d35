// The covariance of a least-squares rigid fit.

#include "registration/rigid_fit.h"

#include <Eigen/Dense>

#include <algorithm>
#include <vector>

namespace scanplan::detail {

Eigen::Matrix<double, 3, 6> motionAt(const Vec3& p) {
  Eigen::Matrix<double, 3, 6> m;
  m.leftCols<3>() << 0, p.z(), -p.y(), -p.z(), 0, p.x(), p.y(), -p.x(), 0;
  m.rightCols<3>() = Eigen::Matrix3d::Identity();
  return m;
}

TwistCovariance inverted(const TwistCovariance& information) {
  const double scale = std::max(information.trace(), 1e-300);
  return (information + 1e-12 * scale * TwistCovariance::Identity())
      .ldlt()
      .solve(TwistCovariance::Identity());
}

TwistCovariance heldInverse(const TwistCovariance& normal) {
  const Eigen::SelfAdjointEigenSolver<TwistCovariance> solver(normal);
  const Eigen::Matrix<double, 6, 1>& values = solver.eigenvalues();
  Eigen::Matrix<double, 6, 1> inverse = Eigen::Matrix<double, 6, 1>::Zero();
  std::vector<Eigen::Index> free;
  for (Eigen::Index i = 0; i < 6; ++i)
    if (values[i] > 1e-12 * values.maxCoeff())
      inverse[i] = 1 / values[i];
    else
      free.push_back(i);
  const TwistCovariance least = solver.eigenvectors() * inverse.asDiagonal() *
                                solver.eigenvectors().transpose();  // the least-norm solution
  if (free.empty()) return least;
  // Moved along the free directions V by z = -pinv(turn of V) (turn of the solution): the
  // turn left is the least they allow. V's columns are unit twists; a turn of theirs under
  // 1e-9 is rounding's worth, and that direction a slide, which leaves the turn as it is.
  Eigen::Matrix<double, 6, Eigen::Dynamic> v(6, static_cast<Eigen::Index>(free.size()));
  for (std::size_t k = 0; k < free.size(); ++k)
    v.col(static_cast<Eigen::Index>(k)) = solver.eigenvectors().col(free[k]);
  const Eigen::JacobiSVD<Eigen::MatrixXd> turn(v.topRows<3>(),
                                               Eigen::ComputeThinU | Eigen::ComputeThinV);
  Eigen::VectorXd inverse_turn = Eigen::VectorXd::Zero(turn.singularValues().size());
  for (Eigen::Index i = 0; i < inverse_turn.size(); ++i)
    if (turn.singularValues()[i] > 1e-9) inverse_turn[i] = 1 / turn.singularValues()[i];
  TwistCovariance hold = TwistCovariance::Identity();
  hold.leftCols<3>() -= v * turn.matrixV() * inverse_turn.asDiagonal() * turn.matrixU().transpose();
  return hold * least;
}

TwistCovariance rigidFitCovariance(std::span<const Vec3> points, double sigma) {
  TwistCovariance information = TwistCovariance::Zero();
  for (const Vec3& p : points) {
    const Eigen::Matrix<double, 3, 6> jacobian = motionAt(p);
    information += jacobian.transpose() * jacobian / (sigma * sigma);
  }
  return inverted(information);
}

}  // namespace scanplan::detail
