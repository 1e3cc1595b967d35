#pragma once
// The inspection cell (docs/cell.md): the robot carrying the scanner, where it stands, how
// the scanner is mounted on its flange, and an optional rotary table under the part.
// A view is feasible when the robot reaches it (some table angle, some inverse-kinematics
// solution within the joint limits).

#include <scanplan/robot.h>
#include <scanplan/view.h>

#include <optional>
#include <string_view>
#include <vector>

namespace scanplan {

// A turntable carrying the part: it turns about `axis` through `origin` (world frame).
// The plan is made with the table at angle 0; at angle a, the part and every view of it
// are turned by a about the axis.
struct RotaryTable {
  Vec3 origin = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();           // unit
  double lower = -M_PI, upper = M_PI;  // radians
  double step = 5 * M_PI / 180;        // angles tried, radians
};

struct Cell {
  RobotModel robot;
  Pose base = Pose::Identity();   // the robot's base frame in the world
  Pose mount = Pose::Identity();  // the scanner frame S in the flange frame
  std::optional<RotaryTable> table;
};

// Where the robot must put its flange (base frame) for the scanner to be at `view` with
// the table turned by `table_angle`.
Pose flangeFor(const Cell& cell, const View& view, double table_angle = 0);

// How the cell takes a view: the table angle and the joints.
struct CellPose {
  double table_angle = 0;  // radians
  Joints joints{};
};

// Why a view cannot be taken (the best reason over all table angles: joint limits before
// out of reach).
enum class CellFailure { None, OutOfReach, JointLimits };
std::string_view toString(CellFailure failure);

struct CellReach {
  std::vector<CellPose> poses;  // every solution at the first table angle that has one
  CellFailure failure = CellFailure::None;
  bool reachable() const { return !poses.empty(); }
};

// The solutions for `view`: the table angles are tried from `preferred_angle` outwards
// (0, +step, -step, ...), the joints taken nearest to `near`.
CellReach reachView(const Cell& cell, const View& view, const Joints& near = {},
                    double preferred_angle = 0);

}  // namespace scanplan
