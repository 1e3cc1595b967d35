#pragma once
// A scanner view: the pose of the scanner frame S in the world (DESIGN.md §3, §7).

#include <scanplan/geometry.h>
#include <scanplan/sensor.h>

#include <string>

namespace scanplan {

using Pose = Eigen::Isometry3d;

struct View {
  int id = 0;  // 1-based, as in plan.json
  Pose camera_to_world = Pose::Identity();
  Vec3 target = Vec3::Zero();  // point the view aims at, world, mm
  std::string task;            // inspection task that asked for it, may be empty

  Vec3 camera() const { return camera_to_world.translation(); }
  Vec3 axis() const { return camera_to_world.linear().col(2); }  // optical axis, unit
};

// Projector centre of `view` in the world.
inline Vec3 projectorPosition(const View& view, const Scanner& scanner) {
  return view.camera_to_world * scanner.projectorInScanner();
}

// The scanner pose with the camera at `camera` looking at `target`, its baseline (+X)
// as close as possible to `baseline_hint` (projected orthogonal to the view axis; any
// perpendicular when the hint is parallel to it). Precondition: camera != target.
Pose lookAt(const Vec3& camera, const Vec3& target, const Vec3& baseline_hint = Vec3::UnitX());

// True when `m` is a rigid transform: orthonormal rotation with determinant +1 (to
// `tolerance`), finite translation, last row (0, 0, 0, 1).
bool isRigid(const Eigen::Matrix4d& m, double tolerance = 1e-6);

}  // namespace scanplan
