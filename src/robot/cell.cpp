// Reaching a view in the cell: the view turned with the table, carried into the robot's
// base frame and from the scanner frame to the flange, then the inverse kinematics.

#include <scanplan/core/errors.h>
#include <scanplan/robot/cell.h>

#include <algorithm>
#include <cctype>
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

void validate(const Cell& c, const std::string& source) {
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) throw InputError(source, "cell." + what);
  };
  validate(c.robot, source, "cell.robot");
  if (c.table) {
    const RotaryTable& t = *c.table;
    require(t.axis.allFinite() && t.axis.norm() > 0.5, "table.axis must not be zero");
    require(t.lower <= 0 && 0 <= t.upper,
            "table.range must hold 0 (the angle the plan is made at)");
    // A turn each way at most: angles beyond repeat the ones within, and each is tried.
    require(t.lower >= -2 * M_PI && t.upper <= 2 * M_PI,
            "table.range must lie within [-360, 360] degrees");
    require(t.step >= radians(0.1), "table.step must be at least 0.1 degrees");
    require(t.speed >= radians(1) && t.speed <= radians(3600),
            "table.speed must lie within [1, 3600] °/s");
    require(t.acceleration >= radians(1) && t.acceleration <= radians(36000),
            "table.acceleration must lie within [1, 36000] °/s²");
    const bool named = !t.unit.empty() && t.unit.size() <= 32 &&
                       std::isalpha(static_cast<unsigned char>(t.unit[0])) &&
                       std::all_of(t.unit.begin(), t.unit.end(), [](char ch) {
                         return std::isalnum(static_cast<unsigned char>(ch)) || ch == '_';
                       });
    require(named,
            "table.unit must be a name of at most 32 letters, digits and underscores, "
            "starting with a letter");
  }
  require(c.clearance >= 0 && c.clearance <= kLongestLength, "clearance must not be negative (mm)");
  require(c.tool.mass > 0 && c.tool.mass <= 1000, "tool.mass must be within (0, 1000] kg");
  require(!c.tool.centre || c.tool.centre->cwiseAbs().maxCoeff() <= kLongestLength,
          "tool.centre must be within 100,000 mm of the flange");
  require(!c.tool.inertia || (c.tool.inertia->minCoeff() >= 0 && c.tool.inertia->maxCoeff() <= 100),
          "tool.inertia must be three moments within [0, 100] kg·m²");
  std::vector<std::pair<std::string, int>> signals = {
      {"signals.view", c.signals.view},
      {"signals.trigger", c.signals.trigger},
      {"signals.acknowledge", c.signals.acknowledge}};
  if (c.signals.table)
    signals.insert(signals.end(), {{"signals.table.angle", c.signals.table->angle},
                                   {"signals.table.move", c.signals.table->move},
                                   {"signals.table.ready", c.signals.table->ready}});
  for (const auto& [key, number] : signals)
    require(number >= 0 && number <= 4095, key + " must be within [0, 4095]");
  require(c.signals.timeout >= 0.1 && c.signals.timeout <= 3600,
          "signals.timeout must be within [0.1, 3600] s");
  for (int i = 0; c.home && i < 6; ++i)
    require((*c.home)[i] >= c.robot.lower[i] && (*c.home)[i] <= c.robot.upper[i],
            "home: joint " + std::to_string(i + 1) + " is beyond its limits");
  require(c.approach >= 0 && c.approach <= 1000, "approach must be within [0, 1000] mm");
  require(c.joint_margin >= 0 && c.joint_margin <= radians(10),
          "joint_margin must be within [0, 10] degrees");
  for (int i = 0; i < 6; ++i)
    require(c.robot.upper[i] - c.robot.lower[i] > 2 * c.joint_margin,
            "joint_margin leaves joint " + std::to_string(i + 1) + " no range");
}

Vec3 loadInertia(const Cell& cell, const Box& scanner_body) {
  if (cell.tool.inertia) return *cell.tool.inertia;
  if (scanner_body.empty()) return Vec3::Zero();
  const Vec3 side = scanner_body.size() / 1000;  // m
  const Vec3 squared = side.cwiseProduct(side);
  const Eigen::Matrix3d box =
      (cell.tool.mass / 12 *
       Vec3(squared.y() + squared.z(), squared.x() + squared.z(), squared.x() + squared.y()))
          .asDiagonal();
  const Eigen::Matrix3d turn = cell.mount.linear();
  return (turn * box * turn.transpose()).diagonal();
}

Pose tableFrame(const RotaryTable& table) {
  const Vec3 z = table.axis.normalized();
  Vec3 x = Vec3::UnitX() - z * z.x();
  if (x.norm() < 1e-6) x = Vec3::UnitY() - z * z.y();
  Pose frame = Pose::Identity();
  frame.linear().col(0) = x.normalized();
  frame.linear().col(1) = z.cross(x.normalized());
  frame.linear().col(2) = z;
  frame.translation() = table.origin;
  return frame;
}

Pose tableTurn(const Cell& cell, double angle) {
  if (!cell.table) return Pose::Identity();
  return turnAbout(cell.table->origin, cell.table->axis, angle);
}

RobotModel workingRange(const Cell& cell) {
  RobotModel robot = cell.robot;
  for (int i = 0; i < 6; ++i) {
    robot.lower[i] += cell.joint_margin;
    robot.upper[i] -= cell.joint_margin;
  }
  return robot;
}

Pose flangeFor(const Cell& cell, const View& view, double table_angle) {
  return cell.base.inverse() * tableTurn(cell, table_angle) * view.camera_to_world *
         cell.mount.inverse();
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
  const RobotModel robot = workingRange(cell);
  for (double angle : angles) {
    const Pose flange = flangeFor(cell, view, angle);
    const std::vector<Joints> solutions = inverseKinematics(robot, flange, near);
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
