// Reaching a view in the cell: the view turned with the table, carried into the robot's
// base frame and from the scanner frame to the flange, then the inverse kinematics.

#include <scanplan/robot/cell.h>

#include <cmath>

namespace scanplan {

std::string_view toString(CellFailure failure) {
  switch (failure) {
    case CellFailure::None: return "none";
    case CellFailure::OutOfReach: return "out_of_reach";
    case CellFailure::JointLimits: return "joint_limits";
    case CellFailure::Collision: return "collision";
  }
  return "?";
}

Pose flangeFor(const Cell& cell, const View& view, double table_angle) {
  Pose turn = Pose::Identity();
  if (cell.table) {
    const RotaryTable& t = *cell.table;
    turn = Eigen::Translation3d(t.origin) * Eigen::AngleAxisd(table_angle, t.axis) *
           Eigen::Translation3d(-t.origin);
  }
  return cell.base.inverse() * turn * view.camera_to_world * cell.mount.inverse();
}

CellReach reachView(const Cell& cell, const View& view, const Joints& near, double preferred_angle,
                    const CellCollisions* collisions) {
  std::vector<double> angles{0};
  if (cell.table) {
    const RotaryTable& t = *cell.table;
    const double start = std::clamp(preferred_angle, t.lower, t.upper);
    angles = {start};
    for (double d = t.step; d <= t.upper - t.lower + 1e-12; d += t.step) {
      if (start + d <= t.upper + 1e-12) angles.push_back(start + d);
      if (start - d >= t.lower - 1e-12) angles.push_back(start - d);
    }
  }
  CellReach result;
  result.failure = CellFailure::OutOfReach;
  for (double angle : angles) {
    const Pose flange = flangeFor(cell, view, angle);
    const std::vector<Joints> solutions = inverseKinematics(cell.robot, flange, near);
    for (const Joints& q : solutions)
      if (!collisions || !collisions->collides({angle, q})) result.poses.push_back({angle, q});
    if (!result.poses.empty()) {
      result.failure = CellFailure::None;
      return result;
    }
    if (!solutions.empty())
      result.failure = CellFailure::Collision;
    else if (result.failure != CellFailure::Collision && armReaches(cell.robot, flange))
      result.failure = CellFailure::JointLimits;
  }
  return result;
}

}  // namespace scanplan
