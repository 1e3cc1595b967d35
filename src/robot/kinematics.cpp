// Forward and closed-form inverse kinematics of ortho-parallel robots with a spherical
// wrist (Brandstötter, Angerer, Hofbaur 2014): the wrist centre C = flange - c4 * z gives
// joints 1-3 (two shoulder solutions, each with elbow up and down), the rotation left for
// the wrist gives joints 4-6 (and the flipped wrist). Offset-wrist arms are solved in
// robot/offset_wrist.cpp; what follows is shared.

#include "robot/offset_wrist.h"

#include <scanplan/core/errors.h>
#include <scanplan/robot/kinematics.h>

#include <Eigen/SVD>

#include <cmath>

namespace scanplan {
namespace {

Joints degrees(std::initializer_list<double> values) {
  Joints q{};
  std::size_t i = 0;
  for (double v : values) q[i++] = radians(v);
  return q;
}

// The model angles (the paper's theta) of a controller joint vector, and back.
Joints modelAngles(const RobotModel& r, Joints q) {
  q[2] += r.j23_coupling * q[1];
  Joints theta{};
  for (int i = 0; i < 6; ++i) theta[i] = q[i] * r.signs[i] - r.offsets[i];
  return theta;
}

Joints controllerJoints(const RobotModel& r, const Joints& theta) {
  Joints q{};
  for (int i = 0; i < 6; ++i) q[i] = (theta[i] + r.offsets[i]) * r.signs[i];
  q[2] -= r.j23_coupling * q[1];
  return q;
}

// The equivalent of `angle` (a multiple of 2 pi away) within [lower, upper] nearest to
// `near`, if any.
std::optional<double> withinLimits(double angle, double lower, double upper, double near) {
  angle = near + std::remainder(angle - near, 2 * M_PI);
  if (angle >= lower && angle <= upper) return angle;
  // The nearest turn lies outside: try the others that the limits allow, nearest first.
  std::optional<double> best;
  for (int k = -3; k <= 3; ++k) {
    const double a = angle + 2 * M_PI * k;
    if (a >= lower && a <= upper && (!best || std::abs(a - near) < std::abs(*best - near)))
      best = a;
  }
  return best;
}

}  // namespace

double RobotModel::reach() const {
  if (offset_wrist) {
    const OffsetWrist& w = *offset_wrist;
    return std::abs(w.a2) + std::abs(w.a3) + w.d5 + w.d6;
  }
  return c2 + std::hypot(a2, c3) + c4;
}

void validate(const RobotModel& r, const std::string& source, const std::string& key) {
  auto fail = [&](const std::string& what) { throw InputError(source, key + what); };
  const OffsetWrist w = r.offset_wrist.value_or(OffsetWrist{});
  const double lengths[] = {r.a1, r.a2, r.b,  r.c1, r.c2, r.c3, r.c4,
                            w.d1, w.a2, w.a3, w.d4, w.d5, w.d6};
  for (double length : lengths)
    if (!(std::abs(length) <= kLongestLength)) fail(": lengths must be at most 100,000 mm");
  if (!r.offset_wrist && !(r.c2 > 0 && r.c3 > 0 && r.c4 >= 0))
    fail(": c2 and c3 must be positive and c4 not negative (mm)");
  if (r.j23_coupling != 0 && r.j23_coupling != 1 && r.j23_coupling != -1)
    fail(".j23_coupling must be -1, 0 or 1");
  if (!r.maker.empty() && r.maker != "kuka" && r.maker != "abb" && r.maker != "fanuc" &&
      r.maker != "universal-robots")
    fail(".maker must be kuka, abb, fanuc or universal-robots");
  for (int i = 0; i < 6; ++i) {
    if (!(r.lower[i] < r.upper[i]))
      fail(": joint " + std::to_string(i + 1) + " has lower >= upper");
    // The presets' joints run at 120-615 °/s; a speed outside [1, 3600] °/s is a typo
    // (radians for degrees, a unit per minute) and would print days or nothing of time.
    if (!(r.speeds[i] >= radians(1) && r.speeds[i] <= radians(3600)))
      fail(".speeds: joint " + std::to_string(i + 1) + " needs a speed within [1, 3600] °/s");
    if (!(r.accelerations[i] >= radians(1) && r.accelerations[i] <= radians(36000)))
      fail(".accelerations: joint " + std::to_string(i + 1) +
           " needs an acceleration within [1, 36000] °/s²");
  }
}

Joints zeroPose(const RobotModel& robot) { return controllerJoints(robot, Joints{}); }

std::vector<std::string> robotPresets() {
  return {"kuka-kr6-r700-sixx",
          "kuka-kr10-r1100-2",
          "kuka-kr16-r1610-2",
          "abb-irb2400-10",
          "abb-irb4600-60-205",
          "fanuc-m20id-25",
          "fanuc-lrmate200id",
          "ur5e",
          "ur10e",
          "ur16e"};
}

namespace {

// Universal Robots e-Series: Denavit-Hartenberg lengths from Universal Robots' "DH
// parameters for calculations of kinematics and dynamics"; every joint turns ±360°;
// speeds from the e-Series technical specifications.
std::optional<RobotModel> universalRobot(std::string_view name) {
  RobotModel r;
  r.name = std::string(name);
  if (name == "ur5e") {
    r.offset_wrist = OffsetWrist{162.5, -425, -392.2, 133.3, 99.7, 99.6};
    r.speeds = degrees({180, 180, 180, 180, 180, 180});
  } else if (name == "ur10e") {
    r.offset_wrist = OffsetWrist{180.7, -612.7, -571.55, 174.15, 119.85, 116.55};
    r.speeds = degrees({120, 120, 180, 180, 180, 180});
  } else if (name == "ur16e") {
    r.offset_wrist = OffsetWrist{180.7, -478.4, -360, 174.15, 119.85, 116.55};
    r.speeds = degrees({120, 120, 180, 180, 180, 180});
  } else {
    return std::nullopt;
  }
  r.maker = "universal-robots";
  r.lower = degrees({-360, -360, -360, -360, -360, -360});
  r.upper = degrees({360, 360, 360, 360, 360, 360});
  // Universal Robots publish no joint accelerations; 1.4 rad/s² is movej's default in
  // the URScript manual, what the controller uses when a program gives none.
  r.accelerations.fill(1.4);
  return r;
}

// KUKA arms: OPW form, offsets and signs as in ROS-Industrial's kuka_experimental
// support packages, axis ranges and speeds as their URDFs give them from KUKA's
// specifications.
std::optional<RobotModel> kukaRobot(std::string_view name) {
  RobotModel r;
  r.name = std::string(name);
  r.maker = "kuka";
  r.offsets = degrees({0, -90, 0, 0, 0, 0});
  r.signs = {-1, 1, 1, -1, 1, -1};
  if (name == "kuka-kr6-r700-sixx") {
    // KUKA KR 6 R700 sixx (KR AGILUS), 706 mm reach: KUKA's specification of the KR AGILUS
    // sixx.
    r.a1 = 25, r.a2 = -35, r.b = 0, r.c1 = 400, r.c2 = 315, r.c3 = 365, r.c4 = 80;
    r.lower = degrees({-170, -190, -120, -185, -120, -350});
    r.upper = degrees({170, 45, 156, 185, 120, 350});
    r.speeds = degrees({360, 300, 360, 381, 388, 615});
  } else if (name == "kuka-kr10-r1100-2") {
    // KUKA KR 10 R1100-2 (KR AGILUS), 1101 mm reach: kuka_kr10_support,
    // opw_parameters_kr10r1100_2.yaml and kr10r1100_2_macro.xacro.
    r.a1 = 25, r.a2 = -25, r.b = 0, r.c1 = 400, r.c2 = 560, r.c3 = 515, r.c4 = 90;
    r.lower = degrees({-170, -190, -120, -185, -120, -350});
    r.upper = degrees({170, 45, 156, 185, 120, 350});
    r.speeds = degrees({300, 225, 330, 360, 360, 433});
  } else if (name == "kuka-kr16-r1610-2") {
    // KUKA KR 16 R1610-2 (KR CYBERTECH), 1612 mm reach: kuka_kr16_support,
    // opw_parameters_kr16_r1610_2.yaml and kr16_r1610_2_macro.xacro.
    r.a1 = 160, r.a2 = -150, r.b = 0, r.c1 = 520, r.c2 = 780, r.c3 = 655, r.c4 = 153;
    r.lower = degrees({-185, -185, -138, -350, -130, -350});
    r.upper = degrees({185, 65, 175, 350, 130, 350});
    r.speeds = degrees({200, 175, 190, 430, 430, 630});
  } else {
    return std::nullopt;
  }
  return r;
}

// FANUC arms: OPW form, offsets and signs as in ROS-Industrial's fanuc support packages
// (the M-20iD/25's opw_parameters_m20id25.yaml; the LR Mate 200iD's the same form read off
// its URDF), axis ranges and speeds as their URDFs give them. FANUC counts axis 3 from the
// horizontal (fanuc_driver's J23 factor 1): the controller's J3 is the URDF's less J2.
std::optional<RobotModel> fanucRobot(std::string_view name) {
  RobotModel r;
  r.name = std::string(name);
  r.maker = "fanuc";
  r.j23_coupling = 1;
  r.offsets = degrees({0, 0, -90, 0, 0, 0});
  r.signs = {1, 1, -1, -1, -1, -1};
  if (name == "fanuc-m20id-25") {
    // FANUC M-20iD/25, 1831 mm reach: fanuc_m20id_support, m20id25_macro.xacro.
    r.a1 = 75, r.a2 = -215, r.b = 0, r.c1 = 425, r.c2 = 840, r.c3 = 890, r.c4 = 90;
    r.lower = degrees({-170, -100, -190, -200, -140, -270});
    r.upper = degrees({170, 160, 268.4, 200, 140, 270});
    r.speeds = degrees({210, 210, 265, 420, 420, 720});
  } else if (name == "fanuc-lrmate200id") {
    // FANUC LR Mate 200iD, 717 mm reach: fanuc_lrmate200id_support,
    // lrmate200id_macro.xacro.
    r.a1 = 50, r.a2 = -35, r.b = 0, r.c1 = 330, r.c2 = 330, r.c3 = 335, r.c4 = 80;
    r.lower = {-2.965, -1.745329, -2.450966, -3.315, -2.18, -6.285};
    r.upper = {2.965, 2.530727, 4.886922, 3.315, 2.18, 6.285};
    r.speeds = {7.85, 6.63, 9.08, 9.60, 9.51, 17.45};
  } else {
    return std::nullopt;
  }
  return r;
}

}  // namespace

RobotModel robotPreset(std::string_view name, const std::string& source) {
  if (std::optional<RobotModel> ur = universalRobot(name)) return *ur;
  std::optional<RobotModel> arm = kukaRobot(name);
  if (!arm) arm = fanucRobot(name);
  if (arm) {
    arm->accelerations = rampAccelerations(arm->speeds);  // KUKA and FANUC publish none
    return *arm;
  }
  RobotModel r;
  r.name = std::string(name);
  r.maker = "abb";
  if (name == "abb-irb2400-10") {
    // ABB IRB 2400/10, 1.55 m reach: ABB product specification IRB 2400 (3HAC042195),
    // axis working ranges and speeds of the /10 variant.
    r.a1 = 100, r.a2 = -135, r.b = 0, r.c1 = 615, r.c2 = 705, r.c3 = 755, r.c4 = 85;
    r.offsets = degrees({0, 0, -90, 0, 0, 0});
    r.lower = degrees({-180, -100, -60, -200, -120, -400});
    r.upper = degrees({180, 110, 65, 200, 120, 400});
    r.speeds = degrees({150, 150, 150, 360, 360, 450});
  } else if (name == "abb-irb4600-60-205") {
    // ABB IRB 4600-60/2.05, 2.05 m reach: ABB product specification IRB 4600
    // (3HAC032885), axis working ranges and speeds; OPW form as in ROS-Industrial's
    // abb_irb4600_support package.
    r.a1 = 175, r.a2 = -175, r.b = 0, r.c1 = 495, r.c2 = 900, r.c3 = 960, r.c4 = 135;
    r.offsets = degrees({0, 0, -90, 0, 0, 0});
    r.lower = degrees({-180, -90, -180, -400, -125, -400});
    r.upper = degrees({180, 150, 75, 400, 120, 400});
    r.speeds = degrees({175, 175, 175, 250, 250, 360});
  } else {
    std::string known;
    for (const std::string& p : robotPresets()) known += (known.empty() ? "" : ", ") + p;
    throw InputError(source,
                     "unknown robot preset '" + std::string(name) + "' (known: " + known + ")");
  }
  r.accelerations = rampAccelerations(r.speeds);  // ABB publishes none
  return r;
}

Pose forwardKinematics(const RobotModel& r, const Joints& joints) {
  const Joints q = modelAngles(r, joints);
  if (r.offset_wrist) return detail::offsetWristFrames(*r.offset_wrist, q)[5];
  const double psi3 = std::atan2(r.a2, r.c3), k = std::hypot(r.a2, r.c3);
  // Wrist centre in the plane of the arm, then turned by joint 1.
  const double x1 = r.c2 * std::sin(q[1]) + k * std::sin(q[1] + q[2] + psi3) + r.a1;
  const double z1 = r.c2 * std::cos(q[1]) + k * std::cos(q[1] + q[2] + psi3);
  const Vec3 centre(x1 * std::cos(q[0]) - r.b * std::sin(q[0]),
                    x1 * std::sin(q[0]) + r.b * std::cos(q[0]), z1 + r.c1);
  using Eigen::AngleAxisd;
  const Eigen::Matrix3d arm =
      (AngleAxisd(q[0], Vec3::UnitZ()) * AngleAxisd(q[1] + q[2], Vec3::UnitY())).toRotationMatrix();
  const Eigen::Matrix3d wrist = (AngleAxisd(q[3], Vec3::UnitZ()) * AngleAxisd(q[4], Vec3::UnitY()) *
                                 AngleAxisd(q[5], Vec3::UnitZ()))
                                    .toRotationMatrix();
  Pose flange = Pose::Identity();
  flange.linear() = arm * wrist;
  flange.translation() = centre + r.c4 * flange.linear().col(2);
  return flange;
}

std::array<Vec3, 4> jointCentres(const RobotModel& r, const Joints& joints) {
  const Joints q = modelAngles(r, joints);
  if (r.offset_wrist) {
    const std::array<Pose, 6> f = detail::offsetWristFrames(*r.offset_wrist, q);
    return {f[0].translation(), f[1].translation(), f[2].translation(), f[5].translation()};
  }
  const double psi3 = std::atan2(r.a2, r.c3), k = std::hypot(r.a2, r.c3);
  // In the arm's plane (x out, z up), then turned by joint 1.
  const Eigen::AngleAxisd turn(q[0], Vec3::UnitZ());
  auto placed = [&](double x, double z) { return Vec3(turn * Vec3(x, r.b, z)); };
  const Vec3 shoulder = placed(r.a1, r.c1);
  const Vec3 elbow = placed(r.a1 + r.c2 * std::sin(q[1]), r.c1 + r.c2 * std::cos(q[1]));
  const Vec3 wrist = placed(r.a1 + r.c2 * std::sin(q[1]) + k * std::sin(q[1] + q[2] + psi3),
                            r.c1 + r.c2 * std::cos(q[1]) + k * std::cos(q[1] + q[2] + psi3));
  return {shoulder, elbow, wrist, forwardKinematics(r, joints).translation()};
}

std::array<Pose, 3> linkMotions(const RobotModel& r, const Joints& joints) {
  const Joints q = modelAngles(r, joints);
  if (r.offset_wrist) {
    // Each link's frame at `joints` against its frame at the zero pose.
    const std::array<Pose, 6> at = detail::offsetWristFrames(*r.offset_wrist, q);
    const std::array<Pose, 6> zero = detail::offsetWristFrames(*r.offset_wrist, Joints{});
    return {at[1] * zero[1].inverse(), at[2] * zero[2].inverse(), at[5] * zero[5].inverse()};
  }
  const Vec3 shoulder(r.a1, r.b, r.c1), elbow(r.a1, r.b, r.c1 + r.c2);
  const Pose upper =
      Pose(Eigen::AngleAxisd(q[0], Vec3::UnitZ())) * turnAbout(shoulder, Vec3::UnitY(), q[1]);
  const Pose fore = upper * turnAbout(elbow, Vec3::UnitY(), q[2]);
  const Pose wrist =
      forwardKinematics(r, joints) * forwardKinematics(r, controllerJoints(r, Joints{})).inverse();
  return {upper, fore, wrist};
}

namespace {

// The up to 8 model-angle solutions, NaN where a configuration does not exist.
std::array<Joints, 8> solutions(const RobotModel& r, const Pose& flange) {
  if (r.offset_wrist) return detail::offsetWristSolutions(*r.offset_wrist, flange);
  const Eigen::Matrix3d& m = flange.linear();
  const Vec3 c = flange.translation() - r.c4 * m.col(2);
  const double nx1 = std::sqrt(c.x() * c.x() + c.y() * c.y() - r.b * r.b) - r.a1;
  const double towards = std::atan2(c.y(), c.x()), lateral = std::atan2(r.b, nx1 + r.a1);
  const double theta1[2] = {towards - lateral, towards + lateral - M_PI};
  const double height = c.z() - r.c1;
  const double s1_2 = nx1 * nx1 + height * height;
  const double s2_2 = (nx1 + 2 * r.a1) * (nx1 + 2 * r.a1) + height * height;
  const double kappa_2 = r.a2 * r.a2 + r.c3 * r.c3, c2_2 = r.c2 * r.c2;
  const double s1 = std::sqrt(s1_2), s2 = std::sqrt(s2_2);
  const double elbow1 = std::acos((s1_2 + c2_2 - kappa_2) / (2 * s1 * r.c2));
  const double elbow2 = std::acos((s2_2 + c2_2 - kappa_2) / (2 * s2 * r.c2));
  const double front = std::atan2(nx1, height), back = std::atan2(nx1 + 2 * r.a1, height);
  const double theta2[4] = {-elbow1 + front, elbow1 + front, -elbow2 - back, elbow2 - back};
  const double psi3 = std::atan2(r.a2, r.c3), k2 = 2 * r.c2 * std::sqrt(kappa_2);
  const double bend1 = std::acos((s1_2 - c2_2 - kappa_2) / k2);
  const double bend2 = std::acos((s2_2 - c2_2 - kappa_2) / k2);
  const double theta3[4] = {bend1 - psi3, -bend1 - psi3, bend2 - psi3, -bend2 - psi3};

  std::array<Joints, 8> out{};
  for (int i = 0; i < 4; ++i) {
    const double q1 = theta1[i / 2];
    const double sin1 = std::sin(q1), cos1 = std::cos(q1);
    const double s23 = std::sin(theta2[i] + theta3[i]), c23 = std::cos(theta2[i] + theta3[i]);
    const double cos5 = m(0, 2) * s23 * cos1 + m(1, 2) * s23 * sin1 + m(2, 2) * c23;
    const double q4 = std::atan2(m(1, 2) * cos1 - m(0, 2) * sin1,
                                 m(0, 2) * c23 * cos1 + m(1, 2) * c23 * sin1 - m(2, 2) * s23);
    const double q5 = std::atan2(std::sqrt(std::max(0.0, 1 - cos5 * cos5)), cos5);
    const double q6 = std::atan2(m(0, 1) * s23 * cos1 + m(1, 1) * s23 * sin1 + m(2, 1) * c23,
                                 -m(0, 0) * s23 * cos1 - m(1, 0) * s23 * sin1 - m(2, 0) * c23);
    out[i] = {q1, theta2[i], theta3[i], q4, q5, q6};
    out[i + 4] = {q1, theta2[i], theta3[i], q4 + M_PI, -q5, q6 - M_PI};
  }
  return out;
}

bool exists(const Joints& theta) {
  for (double t : theta)
    if (!std::isfinite(t)) return false;
  return true;
}

// The error of `flange` against `target`: position (mm) and rotation vector (radians).
Eigen::Matrix<double, 6, 1> poseError(const Pose& flange, const Pose& target) {
  Eigen::Matrix<double, 6, 1> e;
  e.head<3>() = target.translation() - flange.translation();
  const Eigen::AngleAxisd turn(target.linear() * flange.linear().transpose());
  e.tail<3>() = turn.angle() * turn.axis();
  return e;
}

// The closed form loses digits where acos works near +-1 (stretched arm, straight wrist):
// Gauss-Newton steps on the forward kinematics (numerical Jacobian, least-squares solve
// that tolerates the singular wrist) bring such a solution back to machine precision.
Joints refine(const RobotModel& r, Joints q, const Pose& target) {
  for (int iteration = 0; iteration < 4; ++iteration) {
    const Eigen::Matrix<double, 6, 1> e = poseError(forwardKinematics(r, q), target);
    if (e.head<3>().norm() < 1e-11 && e.tail<3>().norm() < 1e-13) break;
    Eigen::Matrix<double, 6, 6> jacobian;
    constexpr double h = 1e-7;
    for (int j = 0; j < 6; ++j) {
      Joints moved = q;
      moved[j] += h;
      jacobian.col(j) = -poseError(forwardKinematics(r, moved), forwardKinematics(r, q)) / h;
    }
    const Eigen::Matrix<double, 6, 1> step =
        jacobian.jacobiSvd(Eigen::ComputeFullU | Eigen::ComputeFullV).solve(-e);
    for (int j = 0; j < 6; ++j) q[j] -= step[j];
  }
  return q;
}

}  // namespace

std::vector<Joints> inverseKinematics(const RobotModel& r, const Pose& flange, const Joints& near) {
  std::vector<Joints> result;
  for (const Joints& theta : solutions(r, flange)) {
    if (!exists(theta)) continue;
    Joints q = refine(r, controllerJoints(r, theta), flange);
    bool inside = true;
    for (int i = 0; i < 6 && inside; ++i) {
      const std::optional<double> a = withinLimits(q[i], r.lower[i], r.upper[i], near[i]);
      inside = a.has_value();
      if (a) q[i] = *a;
    }
    if (inside) result.push_back(q);
  }
  return result;
}

std::string_view toString(Reach reach) {
  switch (reach) {
    case Reach::Reachable: return "reachable";
    case Reach::OutOfReach: return "out_of_reach";
    case Reach::JointLimits: return "joint_limits";
  }
  return "?";
}

bool armReaches(const RobotModel& r, const Pose& flange) {
  for (const Joints& theta : solutions(r, flange))
    if (exists(theta)) return true;
  return false;
}

Reach reachOf(const RobotModel& r, const Pose& flange) {
  if (!inverseKinematics(r, flange).empty()) return Reach::Reachable;
  return armReaches(r, flange) ? Reach::JointLimits : Reach::OutOfReach;
}

double trapezoidSeconds(double distance, double speed, double acceleration) {
  if (!(distance > 0)) return 0;
  if (!(acceleration > 0)) return distance / speed;
  // Up to speed and down again cover speed² / acceleration; a shorter move peaks below it.
  if (distance >= speed * speed / acceleration) return distance / speed + speed / acceleration;
  return 2 * std::sqrt(distance / acceleration);
}

double travelTime(const RobotModel& r, const Joints& from, const Joints& to) {
  double seconds = 0;
  for (int i = 0; i < 6; ++i)
    if (r.speeds[i] > 0)
      seconds = std::max(
          seconds, trapezoidSeconds(std::abs(to[i] - from[i]), r.speeds[i], r.accelerations[i]));
  return seconds;
}

Joints rampAccelerations(const Joints& speeds) {
  constexpr double kRampSeconds = 0.5;
  Joints accelerations{};
  for (int i = 0; i < 6; ++i) accelerations[i] = speeds[i] / kRampSeconds;
  return accelerations;
}

}  // namespace scanplan
