// Robot kinematics: forward kinematics against hand-computed poses and against the makers'
// published geometry, and the closed-form inverse against forward kinematics on random
// poses of every preset (the ortho-parallel arms and the offset-wrist Universal Robots).

#include "support.h"

#include <scanplan/core/errors.h>
#include <scanplan/robot/kinematics.h>

#include <array>
#include <cmath>
#include <optional>
#include <random>

namespace scanplan {
namespace {

// Joint vectors uniform within the limits.
std::vector<Joints> randomJoints(const RobotModel& robot, int count, std::uint64_t seed) {
  std::mt19937_64 random(seed);
  std::vector<Joints> result(count);
  for (Joints& q : result)
    for (int i = 0; i < 6; ++i)
      q[i] = std::uniform_real_distribution<double>(robot.lower[i], robot.upper[i])(random);
  return result;
}

double poseError(const Pose& a, const Pose& b) {
  return std::max((a.translation() - b.translation()).norm(),
                  (a.linear() - b.linear()).cwiseAbs().maxCoeff());
}

TEST(Robot, HomePoseOfTheKukaIsItsDrawing) {
  // KR 6 R700 sixx at A2 = -90°, A3 = 90°: the upper arm vertical, the forearm and the
  // flange horizontal along +x.
  const RobotModel kuka = robotPreset("kuka-kr6-r700-sixx");
  const Pose home = forwardKinematics(kuka, {0, -M_PI / 2, M_PI / 2, 0, 0, 0});
  // Model angles (0, 0, 90°, 0, 0, 0): wrist centre at x = a1 + c3, z = c1 + c2 - a2.
  const Vec3 centre(kuka.a1 + kuka.c3, 0, kuka.c1 + kuka.c2 - kuka.a2);
  EXPECT_LT((home.translation() - (centre + kuka.c4 * home.linear().col(2))).norm(), 1e-12);
  EXPECT_LT((home.linear().col(2) - Vec3::UnitX()).norm(), 1e-12);
  EXPECT_NEAR(home.translation().x(), 25 + 365 + 80, 1e-9);
  EXPECT_NEAR(home.translation().z(), 400 + 315 + 35, 1e-9);
}

// A UR5e with every joint at 0, from its Denavit-Hartenberg table: the arm stretched
// along -x, the flange at (a2 + a3, -(d4 + d6), d1 - d5), its axis along -y.
TEST(Robot, ZeroPoseOfTheUr5eIsItsDrawing) {
  const RobotModel ur = robotPreset("ur5e");
  ASSERT_TRUE(ur.offset_wrist);
  const Pose zero = forwardKinematics(ur, Joints{});
  EXPECT_LT((zero.translation() - Vec3(-425 - 392.2, -(133.3 + 99.6), 162.5 - 99.7)).norm(), 1e-9);
  EXPECT_LT((zero.linear().col(2) - Vec3(0, -1, 0)).norm(), 1e-12);
  // Joint 1 at 90° turns it all about z; joint 2 at -90° lifts the arm straight up.
  const Pose turned = forwardKinematics(ur, {M_PI / 2, 0, 0, 0, 0, 0});
  EXPECT_LT((turned.translation() - Vec3(133.3 + 99.6, -425 - 392.2, 162.5 - 99.7)).norm(), 1e-9);
  const std::array<Vec3, 4> up = jointCentres(ur, {0, -M_PI / 2, 0, 0, 0, 0});
  EXPECT_LT((up[2] - Vec3(0, 0, 162.5 + 425 + 392.2)).norm(), 1e-9);
}

// The flange by the Denavit-Hartenberg table Universal Robots publish ("DH parameters for
// calculations of kinematics and dynamics", e-Series), in metres: frame i from frame i-1
// by Rz(theta_i) Tz(d_i) Tx(a_i) Rx(alpha_i). Written here from the table, apart from the
// library's presets and its own chain.
Pose urTableFlange(const std::array<double, 6>& a, const std::array<double, 6>& d,
                   const Joints& q) {
  const std::array<double, 6> alpha = {M_PI / 2, 0, 0, M_PI / 2, -M_PI / 2, 0};
  Eigen::Matrix4d t = Eigen::Matrix4d::Identity();
  for (int i = 0; i < 6; ++i) {
    const double c = std::cos(q[i]), s = std::sin(q[i]);
    const double ca = std::cos(alpha[i]), sa = std::sin(alpha[i]);
    Eigen::Matrix4d link;
    link << c, -s * ca, s * sa, 1000 * a[i] * c,  //
        s, c * ca, -c * sa, 1000 * a[i] * s,      //
        0, sa, ca, 1000 * d[i],                   //
        0, 0, 0, 1;
    t = t * link;
  }
  return Pose(t);
}

// The flange by the ROS-Industrial abb_irb4600_support description of the IRB 4600-60/2.05
// (irb4600_60_205_macro.xacro): joint origins in metres and joint axes, each joint turning
// its child link, tool0 turned by 90 degrees about y from link 6.
Pose irb4600TableFlange(const Joints& q) {
  const std::array<Vec3, 6> origin = {Vec3(0, 0, 0.495), Vec3(0.175, 0, 0), Vec3(0, 0, 0.9),
                                      Vec3(0, 0, 0.175), Vec3(0.960, 0, 0), Vec3(0.135, 0, 0)};
  const std::array<Vec3, 6> axis = {Vec3::UnitZ(), Vec3::UnitY(), Vec3::UnitY(),
                                    Vec3::UnitX(), Vec3::UnitY(), Vec3::UnitX()};
  Pose t = Pose::Identity();
  for (int i = 0; i < 6; ++i) {
    t.translate(1000 * origin[i]);
    t.rotate(Eigen::AngleAxisd(q[i], axis[i]));
  }
  t.rotate(Eigen::AngleAxisd(M_PI / 2, Vec3::UnitY()));
  return t;
}

// Forward kinematics of the presets against the makers' published geometry, at random
// joints within the limits: a wrong length or offset in a preset shows here, where a
// round trip through the inverse could not show it.
TEST(Robot, ForwardKinematicsOfThePresetsMatchesTheMakersGeometry) {
  struct Ur {
    const char* name;
    std::array<double, 6> a, d;
  };
  for (const Ur& ur :
       {Ur{"ur10e", {0, -0.6127, -0.57155, 0, 0, 0}, {0.1807, 0, 0, 0.17415, 0.11985, 0.11655}},
        Ur{"ur16e", {0, -0.4784, -0.36, 0, 0, 0}, {0.1807, 0, 0, 0.17415, 0.11985, 0.11655}}}) {
    const RobotModel robot = robotPreset(ur.name);
    for (const Joints& q : randomJoints(robot, 50, 3))
      EXPECT_LT(poseError(forwardKinematics(robot, q), urTableFlange(ur.a, ur.d, q)), 1e-9)
          << ur.name;
  }
  const RobotModel irb = robotPreset("abb-irb4600-60-205");
  for (const Joints& q : randomJoints(irb, 50, 4)) {
    const Pose library = forwardKinematics(irb, q), table = irb4600TableFlange(q);
    EXPECT_LT((library.translation() - table.translation()).norm(), 1e-9);
    EXPECT_LT((library.linear() - table.linear()).cwiseAbs().maxCoeff(), 1e-12);
  }
}

// A serial chain as a ROS-Industrial URDF gives it: per joint its origin in the parent link
// (m), a turn of the origin about y (rpy (0, y, 0), radians) and its axis.
struct UrdfJoint {
  Vec3 origin;
  double pitch;
  Vec3 axis;
};

// The last link's frame for the URDF's joint angles `q`, mm.
Pose urdfFlange(const std::array<UrdfJoint, 6>& chain, const Joints& q) {
  Pose t = Pose::Identity();
  for (int i = 0; i < 6; ++i) {
    t.translate(1000 * chain[i].origin);
    t.rotate(Eigen::AngleAxisd(chain[i].pitch, Vec3::UnitY()));
    t.rotate(Eigen::AngleAxisd(q[i], chain[i].axis));
  }
  return t;
}

// The KUKA and FANUC presets against the joint chains of ROS-Industrial's URDFs
// (kr10r1100_2_macro.xacro, kr16_r1610_2_macro.xacro, m20id25_macro.xacro,
// lrmate200id_macro.xacro), at random joints within the limits: the flange lies where the
// URDF puts its last link, turned by one fixed rotation (the two flange conventions). The
// URDF counts FANUC's axis 3 from the upper arm, the controller from the horizontal: the
// URDF's J3 is the controller's J3 plus J2 (ROS-Industrial's fanuc_driver, J23 factor 1 for
// both FANUC arms, 0 for KUKA's).
TEST(Robot, KukaAndFanucPresetsMatchTheirRosIndustrialUrdfs) {
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  const double quarter = M_PI / 2;
  struct Arm {
    const char* name;
    double j23_factor;  // fanuc_driver's
    std::array<UrdfJoint, 6> chain;
  };
  const std::vector<Arm> arms = {{"kuka-kr10-r1100-2",
                                  0,
                                  {{{{0, 0, 0.400}, 0, -z},
                                    {{0.025, 0, 0}, 0, y},
                                    {{0.560, 0, 0}, 0, y},
                                    {{0.515, 0, 0.025}, 0, -x},
                                    {{0, 0, 0}, 0, y},
                                    {{0.090, 0, 0}, 0, -x}}}},
                                 {"kuka-kr16-r1610-2",
                                  0,
                                  {{{{0, 0, 0.520}, 0, -z},
                                    {{0.16, 0, 0}, 0, y},
                                    {{0.78, 0, 0}, 0, y},
                                    {{0.655, 0, 0.150}, 0, -x},
                                    {{0, 0, 0}, 0, y},
                                    {{0.153, 0, 0}, 0, -x}}}},
                                 {"fanuc-m20id-25",
                                  1,
                                  {{{{0, 0, 0.425}, 0, z},
                                    {{0.075, 0, 0}, 0, y},
                                    {{0, 0, 0.840}, quarter, -y},
                                    {{-0.215, 0, 0.890}, 0, -z},
                                    {{0, 0, 0}, 0, -y},
                                    {{0, 0, 0.09}, 0, -z}}}},
                                 {"fanuc-lrmate200id",
                                  1,
                                  {{{{0, 0, 0.330}, 0, z},
                                    {{0.050, 0, 0}, 0, y},
                                    {{0, 0, 0.330}, 0, -y},
                                    {{0, 0, 0.035}, 0, -x},
                                    {{0.335, 0, 0}, 0, -y},
                                    {{0.080, 0, 0}, 0, -x}}}}};
  for (const auto& [name, j23_factor, chain] : arms) {
    SCOPED_TRACE(name);
    const RobotModel robot = robotPreset(name);
    std::optional<Eigen::Matrix3d> turn;
    for (const Joints& q : randomJoints(robot, 200, 12)) {
      Joints urdf = q;
      urdf[2] += j23_factor * q[1];
      const Pose library = forwardKinematics(robot, q), reference = urdfFlange(chain, urdf);
      EXPECT_LT((library.translation() - reference.translation()).norm(), 1e-6);
      const Eigen::Matrix3d relative = reference.linear().transpose() * library.linear();
      if (!turn) turn = relative;
      EXPECT_LT((relative - *turn).cwiseAbs().maxCoeff(), 1e-9);
    }
  }
  // FANUC's J3 is the forearm's angle from the horizontal: turning J2 alone keeps the
  // forearm level, the flange 425 + 840 cos 30° + 215 mm up.
  const RobotModel m20 = robotPreset("fanuc-m20id-25");
  EXPECT_LT((forwardKinematics(m20, {}).translation() - Vec3(1055, 0, 1480)).norm(), 1e-6);
  const Vec3 leant = forwardKinematics(m20, {0, radians(30), 0, 0, 0, 0}).translation();
  EXPECT_LT((leant - Vec3(75 + 420 + 890 + 90, 0, 425 + 840 * std::cos(radians(30)) + 215)).norm(),
            1e-6);
}

TEST(Robot, InverseOfForwardOnRandomPosesOfEveryPreset) {
  for (const std::string& name : robotPresets()) {
    SCOPED_TRACE(name);
    const RobotModel robot = robotPreset(name);
    double worst = 0;
    int found_original = 0;
    for (const Joints& q : randomJoints(robot, 10000, 7)) {
      const Pose pose = forwardKinematics(robot, q);
      const std::vector<Joints> solutions = inverseKinematics(robot, pose, q);
      ASSERT_FALSE(solutions.empty());
      ASSERT_LE(solutions.size(), 8u);
      bool original = false;
      for (const Joints& s : solutions) {
        worst = std::max(worst, poseError(forwardKinematics(robot, s), pose));
        for (int i = 0; i < 6; ++i) {
          ASSERT_GE(s[i], robot.lower[i]);
          ASSERT_LE(s[i], robot.upper[i]);
        }
        double difference = 0;
        for (int i = 0; i < 6; ++i) difference = std::max(difference, std::abs(s[i] - q[i]));
        original = original || difference < 1e-6;
      }
      found_original += original;
    }
    EXPECT_LT(worst, 1e-9) << "mm and rotation entries";
    // The original joints are among the solutions, but where the wrist is nearly straight
    // (joint 5 near 0) and joints 4 and 6 are not unique.
    EXPECT_GE(found_original, 9990);
  }
}

TEST(Robot, PosesBeyondReachHaveNoSolution) {
  for (const std::string& name : robotPresets()) {
    const RobotModel robot = robotPreset(name);
    Pose far = Pose::Identity();
    far.translation() = Vec3(robot.reach() * 1.5 + robot.a1, 0, robot.c1);
    EXPECT_TRUE(inverseKinematics(robot, far).empty()) << name;
    EXPECT_EQ(reachOf(robot, far), Reach::OutOfReach) << name;
  }
}

TEST(Robot, SolutionsOutsideTheLimitsAreRejectedWithTheirReason) {
  RobotModel robot = robotPreset("abb-irb2400-10");
  const Pose pose = forwardKinematics(robot, {1, 0.2, 0.1, 0.3, 0.5, 0.2});
  EXPECT_EQ(reachOf(robot, pose), Reach::Reachable);
  robot.lower[0] = -0.1;  // joint 1 may no longer turn to 1 rad (nor to 1 - pi)
  robot.upper[0] = 0.1;
  EXPECT_TRUE(inverseKinematics(robot, pose).empty());
  EXPECT_EQ(reachOf(robot, pose), Reach::JointLimits);
}

TEST(Robot, TravelTimeIsTheSlowestJoint) {
  const RobotModel robot = robotPreset("abb-irb2400-10");
  Joints to{};
  // Each joint reaches its top speed in half a second: joint 1 turns 150° in 0.5 s up to
  // 150°/s, 0.5 s at it and 0.5 s down; joint 6 turns 225° in 0.5 s up to 450°/s and
  // 0.5 s down.
  to[0] = radians(150);
  to[5] = radians(225);
  EXPECT_NEAR(travelTime(robot, {}, to), 1.5, 1e-12);
  to[0] = 0;
  EXPECT_NEAR(travelTime(robot, {}, to), 1.0, 1e-12);
}

TEST(Robot, UnknownPresetIsAnInputError) { EXPECT_THROW(robotPreset("kuka-kr1000"), InputError); }

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

TEST(Robot, LinkMotionsCarryTheZeroPoseJointsToTheirPlaces) {
  for (const std::string& name : robotPresets()) {
    const RobotModel robot = robotPreset(name);
    Joints zero{};
    for (int i = 0; i < 6; ++i) zero[i] = robot.offsets[i] * robot.signs[i];  // model angles 0
    const std::array<Vec3, 4> at_zero = jointCentres(robot, zero);
    for (const Joints& q : randomJoints(robot, 200, 3)) {
      const std::array<Vec3, 4> now = jointCentres(robot, q);
      const std::array<Pose, 3> motion = linkMotions(robot, q);
      EXPECT_LT((motion[0] * at_zero[1] - now[1]).norm(), 1e-9) << name;  // elbow on the upper arm
      EXPECT_LT((motion[1] * at_zero[2] - now[2]).norm(), 1e-9) << name;  // wrist on the forearm
      EXPECT_LT((motion[2] * at_zero[3] - now[3]).norm(), 1e-9) << name;  // flange on the wrist
    }
  }
}

}  // namespace
}  // namespace scanplan
