#pragma once
// The covariance of a small rigid motion fitted by least squares (docs/capability.md,
// "Error budget"): of markers' centres, for the registration's tree and for the capability.

#include <scanplan/core/geometry.h>

#include <Eigen/Core>

#include <span>

namespace scanplan::detail {

// Of a small rigid motion (rotation w, radians, then translation t, mm).
using TwistCovariance = Eigen::Matrix<double, 6, 6>;

// The matrix mapping a small rigid motion to the displacement of `p`: w x p + t.
Eigen::Matrix<double, 3, 6> motionAt(const Vec3& p);

// The inverse of an information matrix; directions it leaves free get a large variance
// rather than an infinity.
TwistCovariance inverted(const TwistCovariance& information);

// Covariance of the rigid fit that maps measured points onto known ones, each measured
// with independent noise of `sigma` mm per axis (point to point, first order).
TwistCovariance rigidFitCovariance(std::span<const Vec3> points, double sigma);

}  // namespace scanplan::detail
