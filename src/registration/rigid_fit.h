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

// The matrix that solves a rigid motion's normal equations for their right-hand side:
// the directions they constrain exactly, however little they weigh; the directions they
// leave free (eigenvalues under 1e-12 of the largest) held so that the motion turns least
// (none about a datum axis that leaves a turn free), then slides least (none along a datum
// plane), whatever the origin of the coordinates.
TwistCovariance heldInverse(const TwistCovariance& normal);

// Covariance of the rigid fit that maps measured points onto known ones, each measured
// with independent noise of `sigma` mm per axis (point to point, first order).
TwistCovariance rigidFitCovariance(std::span<const Vec3> points, double sigma);

}  // namespace scanplan::detail
