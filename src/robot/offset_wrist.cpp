// Offset-wrist arms (Universal Robots): the forward kinematics is the chain of standard
// Denavit-Hartenberg transforms A_k = Rz(theta_k) Tz(d_k) Tx(a_k) Rx(alpha_k) with the
// twists (90°, 0, 0, 90°, -90°, 0). The inverse follows Hawkins (2013): joint 1 from the
// position of frame 5 (the flange moved back by d6), joint 5 from the flange's position
// across the shoulder plane, joint 6 from its orientation, then the planar arm of joints
// 2 and 3 to the origin of frame 4, and joint 4 what remains.

#include "robot/offset_wrist.h"

#include <cmath>
#include <limits>

namespace scanplan::detail {
namespace {

constexpr std::array<double, 6> kTwists = {M_PI / 2, 0, 0, M_PI / 2, -M_PI / 2, 0};

Pose dh(double theta, double d, double a, double alpha) {
  return Pose(Eigen::AngleAxisd(theta, Vec3::UnitZ()) * Eigen::Translation3d(0, 0, d) *
              Eigen::Translation3d(a, 0, 0) * Eigen::AngleAxisd(alpha, Vec3::UnitX()));
}

// Link k's transform (k = 0..5) at angle `theta`.
Pose link(const OffsetWrist& arm, int k, double theta) {
  const std::array<double, 6> d = {arm.d1, 0, 0, arm.d4, arm.d5, arm.d6};
  const std::array<double, 6> a = {0, arm.a2, arm.a3, 0, 0, 0};
  return dh(theta, d[k], a[k], kTwists[k]);
}

}  // namespace

std::array<Pose, 6> offsetWristFrames(const OffsetWrist& arm, const Joints& theta) {
  std::array<Pose, 6> frames;
  Pose to = Pose::Identity();
  for (int k = 0; k < 6; ++k) frames[k] = to = to * link(arm, k, theta[k]);
  return frames;
}

std::array<Joints, 8> offsetWristSolutions(const OffsetWrist& arm, const Pose& flange) {
  constexpr double nan = std::numeric_limits<double>::quiet_NaN();
  std::array<Joints, 8> out;
  out.fill(Joints{nan, nan, nan, nan, nan, nan});
  const Eigen::Matrix3d& r = flange.linear();
  const Vec3 p06 = flange.translation(), p05 = p06 - arm.d6 * r.col(2);
  const double across = std::hypot(p05.x(), p05.y());
  if (across < std::abs(arm.d4)) return out;  // NaN: the wrist cannot get that near the axis
  const double shoulder = std::acos(arm.d4 / across);
  int n = 0;
  for (const double side : {1.0, -1.0}) {
    const double q1 = std::atan2(p05.y(), p05.x()) + side * shoulder + M_PI / 2;
    const double s1 = std::sin(q1), c1 = std::cos(q1);
    const double wrist = std::acos((p06.x() * s1 - p06.y() * c1 - arm.d4) / arm.d6);
    for (const double up : {1.0, -1.0}) {
      const double q5 = up * wrist, s5 = std::sin(q5);
      // Joint 6 is free where the wrist is straight (joint 5 at 0): any value does.
      const double q6 = std::abs(s5) < 1e-12 ? 0.0
                                             : std::atan2((-r(0, 1) * s1 + r(1, 1) * c1) / s5,
                                                          (r(0, 0) * s1 - r(1, 0) * c1) / s5);
      // Frame 4 in frame 1: the planar arm, its origin d4 off the arm's plane.
      const Pose t14 = link(arm, 0, q1).inverse() * flange * link(arm, 5, q6).inverse() *
                       link(arm, 4, q5).inverse();
      const Vec3 p14 = t14.translation();
      const double reach2 = p14.x() * p14.x() + p14.y() * p14.y();
      const double elbow =
          std::acos((reach2 - arm.a2 * arm.a2 - arm.a3 * arm.a3) / (2 * arm.a2 * arm.a3));
      for (const double bend : {1.0, -1.0}) {
        const double q3 = bend * elbow;
        const double q2 = std::atan2(p14.y(), p14.x()) -
                          std::atan2(arm.a3 * std::sin(q3), arm.a2 + arm.a3 * std::cos(q3));
        const Pose t34 = (link(arm, 1, q2) * link(arm, 2, q3)).inverse() * t14;
        const double q4 = std::atan2(t34(1, 0), t34(0, 0));
        out[n++] = {q1, q2, q3, q4, q5, q6};
      }
    }
  }
  return out;
}

}  // namespace scanplan::detail
