#pragma once
// The inspection cell's robot (docs/cell.md), a 6-axis arm of one of two families:
// - an industrial arm with a spherical wrist, described by its ortho-parallel ("OPW")
//   parameters, with the closed-form inverse kinematics of Brandstötter, Angerer and
//   Hofbaur, "An analytical solution of the inverse kinematics problem of industrial serial
//   manipulators with an ortho-parallel basis and a spherical wrist", Austrian Robotics
//   Workshop 2014;
// - an offset-wrist arm (Universal Robots), described by its Denavit-Hartenberg lengths,
//   with the closed form of Hawkins, "Analytic Inverse Kinematics for the Universal Robots
//   UR-5/UR-10 Arms" (2013).

#include <scanplan/core/view.h>

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace scanplan {

using Joints = std::array<double, 6>;  // radians, as the controller counts them

// An offset-wrist arm's standard Denavit-Hartenberg lengths, mm (the manufacturer's
// table): base height d1, upper arm a2 and forearm a3 (negative, as Universal Robots give
// them), wrist offsets d4, d5 and flange d6. The twists are the family's: 90°, 0, 0, 90°,
// -90°, 0.
struct OffsetWrist {
  double d1 = 0, a2 = 0, a3 = 0, d4 = 0, d5 = 0, d6 = 0;
};

// Ortho-parallel parameters (the paper's figure 1), mm: a1 shoulder offset along x, a2
// elbow offset, b lateral offset, c1 base height, c2 upper arm, c3 forearm, c4 wrist to
// flange. Joint i as the controller counts it is (model angle + offset[i]) * sign[i],
// axis 3 then less j23_coupling times axis 2 (FANUC counts axis 3 from the horizontal).
struct RobotModel {
  std::string name;
  // Whose controller runs it: "kuka", "abb", "fanuc", "universal-robots"; empty for an
  // arm given by its parameters. Each program format is for its maker's arms.
  std::string maker;
  double j23_coupling = 0;  // 1 for FANUC, 0 for the others
  double a1 = 0, a2 = 0, b = 0, c1 = 0, c2 = 0, c3 = 0, c4 = 0;
  Joints offsets{};  // radians
  std::array<int, 6> signs{1, 1, 1, 1, 1, 1};
  Joints lower{}, upper{};  // joint limits, radians
  Joints speeds{};          // largest joint speeds, radians per second
  Joints accelerations{};   // largest joint accelerations, radians per second² (docs/cycle.md)
  // Radii of the upper arm, the forearm and the wrist for collisions, mm; 0: sized from
  // the lengths (upper arm and forearm 0.1 x length + 20 mm, wrist 60 mm).
  std::array<double, 3> link_radii{};
  // Set: an offset-wrist arm, whose model angles are the Denavit-Hartenberg angles; the
  // ortho-parallel lengths are then unused.
  std::optional<OffsetWrist> offset_wrist;

  // Distance from the shoulder axis to the wrist centre (to the flange, for an offset
  // wrist) when stretched, mm.
  double reach() const;
};

// Checks `robot`: lengths within 100 m (an ortho-parallel arm's c2 and c3 positive, c4 not
// negative), each joint's lower limit below its upper, positive speeds.
// \throw InputError naming `source` and `key`.
void validate(const RobotModel& robot, const std::string& source, const std::string& key);

// The presets: "kuka-kr6-r700-sixx", "kuka-kr10-r1100-2", "kuka-kr16-r1610-2",
// "abb-irb2400-10", "abb-irb4600-60-205", "fanuc-m20id-25", "fanuc-lrmate200id", "ur5e",
// "ur10e", "ur16e".
std::vector<std::string> robotPresets();
// \throw InputError (naming `source`) for an unknown preset.
RobotModel robotPreset(std::string_view name, const std::string& source = "spec");

// The controller's joints at the zero pose (every model angle 0: upper arm and forearm
// straight up).
Joints zeroPose(const RobotModel& robot);

// The flange pose in the robot's base frame for `joints`.
Pose forwardKinematics(const RobotModel& robot, const Joints& joints);

// The arm's joint centres in the base frame for `joints`: shoulder (axis 2), elbow (axis
// 3), wrist centre (of an offset wrist: axis 4), flange.
std::array<Vec3, 4> jointCentres(const RobotModel& robot, const Joints& joints);

// Where the upper arm, the forearm and the wrist have moved to at `joints` from the
// zero pose (every model angle 0: upper arm and forearm straight up): rigid transforms of
// the base frame. The wrist moves with the flange.
std::array<Pose, 3> linkMotions(const RobotModel& robot, const Joints& joints);

// Every solution (up to 8: shoulder left/right x elbow up/down x wrist flip) that puts the
// flange at `flange` (base frame) within the joint limits; each joint taken as the
// equivalent (a multiple of 360° away) nearest to `near` that the limits allow. Empty when
// the pose is out of reach or every solution breaks a limit.
std::vector<Joints> inverseKinematics(const RobotModel& robot, const Pose& flange,
                                      const Joints& near = {});

// Why inverseKinematics found nothing: out of reach (no arm configuration at all), or
// configurations that all break a joint limit.
enum class Reach { Reachable, OutOfReach, JointLimits };
std::string_view toString(Reach reach);
Reach reachOf(const RobotModel& robot, const Pose& flange);
// True when some arm configuration puts the flange there, joint limits aside.
bool armReaches(const RobotModel& robot, const Pose& flange);

// The seconds of a move over `distance` (≥ 0) by a trapezoidal speed profile: up at
// `acceleration` to `speed`, on at that speed, down at `acceleration`; a triangle when the
// move is too short to reach the speed. Any consistent units (rad, rad/s, rad/s²; mm,
// mm/s, mm/s²). An acceleration of 0 or less stands for an instant one.
double trapezoidSeconds(double distance, double speed, double acceleration);

// The time of a joint move between two joint vectors, seconds: the joints move together,
// in the slowest joint's time, each by its speed and acceleration (trapezoidSeconds).
double travelTime(const RobotModel& robot, const Joints& from, const Joints& to);

// The accelerations of joints the maker gives none for: each reaches its top speed in
// half a second (docs/cycle.md).
Joints rampAccelerations(const Joints& speeds);

}  // namespace scanplan
