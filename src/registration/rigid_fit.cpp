// The covariance of a least-squares rigid fit.

#include "registration/rigid_fit.h"

#include <Eigen/Dense>

#include <algorithm>

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

TwistCovariance rigidFitCovariance(std::span<const Vec3> points, double sigma) {
  TwistCovariance information = TwistCovariance::Zero();
  for (const Vec3& p : points) {
    const Eigen::Matrix<double, 3, 6> jacobian = motionAt(p);
    information += jacobian.transpose() * jacobian / (sigma * sigma);
  }
  return inverted(information);
}

}  // namespace scanplan::detail
