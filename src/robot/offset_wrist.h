#pragma once
// Kinematics of offset-wrist arms (Universal Robots), in the model angles of the standard
// Denavit-Hartenberg convention (docs/cell.md): the library's kinematics call these for a
// RobotModel with offset_wrist set.

#include <scanplan/robot/kinematics.h>

#include <array>

namespace scanplan::detail {

// The frames of the six links in the base frame (frame k after joint k+1): frame 5 is the
// flange.
std::array<Pose, 6> offsetWristFrames(const OffsetWrist& arm, const Joints& theta);

// The up to 8 solutions of Hawkins, "Analytic Inverse Kinematics for the Universal Robots
// UR-5/UR-10 Arms" (2013): shoulder left/right x wrist up/down x elbow up/down; NaN where
// a configuration does not exist.
std::array<Joints, 8> offsetWristSolutions(const OffsetWrist& arm, const Pose& flange);

}  // namespace scanplan::detail
