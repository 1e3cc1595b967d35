#pragma once
// Basic geometric value types shared by every stage. Millimetres throughout.

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <cmath>
#include <limits>
#include <numbers>

namespace scanplan {

using Vec3 = Eigen::Vector3d;
using Vec3i = Eigen::Vector3i;

// Angles: degrees in specs, files and messages, radians in computations.
constexpr double kRadiansPerDegree = std::numbers::pi / 180;
constexpr double kDegreesPerRadian = 180 / std::numbers::pi;
constexpr double radians(double degrees) { return degrees * kRadiansPerDegree; }
constexpr double degrees(double radians) { return radians * kDegreesPerRadian; }

// The Euler angles of a rotation about Z, then the new Y, then the new X, degrees:
// r = Rz(a) Ry(b) Rx(c), b within [-90, 90], no -0. KUKA's A, B, C; FANUC's W, P, R
// (about the fixed X, Y, Z) are c, b, a.
inline Vec3 zyxAngles(const Eigen::Matrix3d& r) {
  const Vec3 abc(degrees(std::atan2(r(1, 0), r(0, 0))),
                 degrees(std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)))),
                 degrees(std::atan2(r(2, 1), r(2, 2))));
  return abc + Vec3::Zero();
}

// The longest length an input may give (mm, 100 m): parts, scanner and robot sizes. Beyond
// it, rays lose the precision the ray caster needs.
constexpr double kLongestLength = 100'000;

// Axis-aligned bounding box; empty until a point is added.
struct Box {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());

  bool empty() const { return (min.array() > max.array()).any(); }
  void add(const Vec3& p) {
    min = min.cwiseMin(p);
    max = max.cwiseMax(p);
  }
  void add(const Box& b) {
    if (!b.empty()) {
      add(b.min);
      add(b.max);
    }
  }
  Vec3 size() const { return empty() ? Vec3::Zero() : Vec3(max - min); }
  Vec3 center() const { return 0.5 * (min + max); }
  double diagonal() const { return size().norm(); }
};

}  // namespace scanplan
