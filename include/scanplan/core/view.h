#pragma once
// A scanner view: the pose of the scanner frame S in the world (docs/design.md §3, §7).

#include <scanplan/core/geometry.h>

#include <string>

namespace scanplan {

using Pose = Eigen::Isometry3d;

// The turn by `angle` (radians, right-handed) about the line through `point` along `axis`
// (unit).
inline Pose turnAbout(const Vec3& point, const Vec3& axis, double angle) {
  return Pose(Eigen::Translation3d(point) * Eigen::AngleAxisd(angle, axis) *
              Eigen::Translation3d(-point));
}

struct View {
  int id = 0;  // 1-based, as in plan.json
  Pose camera_to_world = Pose::Identity();
  Vec3 target = Vec3::Zero();  // point the view aims at, world, mm
  std::string task;            // inspection task that asked for it, may be empty

  Vec3 camera() const { return camera_to_world.translation(); }
  Vec3 axis() const { return camera_to_world.linear().col(2); }  // optical axis, unit
};

// True when `m` is a rigid transform: orthonormal rotation with determinant +1 (to
// `tolerance`), finite translation, last row (0, 0, 0, 1).
bool isRigid(const Eigen::Matrix4d& m, double tolerance = 1e-6);

}  // namespace scanplan
