// The cell: views rejected with their reason (beyond reach, behind the base), a rotary
// table bringing the far side within reach, the spec's cell section, and plans that keep
// every view reachable and move the joints smoothly.

#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/planning/robot_steps.h>
#include <scanplan/registration/sequencing.h>
#include <scanplan/robot/cell.h>
#include <scanplan/robot/motion.h>
#include <scanplan/robot/program.h>

#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepTools.hxx>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <random>

namespace scanplan {
namespace {

// A view with its camera at `camera` looking at `target`.
View viewAt(const Vec3& camera, const Vec3& target) {
  View view;
  view.camera_to_world = lookAt(camera, target);
  view.target = target;
  return view;
}

Cell irb2400At(const Vec3& position) {
  Cell cell;
  cell.robot = robotPreset("abb-irb2400-10");
  cell.base.translation() = position;
  cell.mount.translation() = Vec3(0, 0, 150);
  return cell;
}

TEST(Cell, ViewBeyondReachIsRejectedAsOutOfReach) {
  const Cell cell = irb2400At(Vec3::Zero());
  const CellReach near = reachView(cell, viewAt({900, 0, 600}, {900, 0, 0}));
  EXPECT_TRUE(near.reachable());
  const CellReach far = reachView(cell, viewAt({3000, 0, 600}, {3000, 0, 0}));
  EXPECT_FALSE(far.reachable());
  EXPECT_EQ(far.failure, CellFailure::OutOfReach);
}

// A view straight behind the base needs axis 1 at 180°, its limit: reached with no margin
// to the limits, refused with the default margin of 2° (cell.joint_margin), as with a
// cell that fences axis 1 to +-90°.
TEST(Cell, ViewBehindTheBaseNeedsJointOneToTurn) {
  Cell cell = irb2400At(Vec3::Zero());
  const View behind = viewAt({-900, 0, 600}, {-900, 0, 0});
  EXPECT_NEAR(cell.joint_margin, radians(2), 1e-12);
  const CellReach on_the_limit = reachView(cell, behind);
  EXPECT_FALSE(on_the_limit.reachable());
  EXPECT_EQ(on_the_limit.failure, CellFailure::JointLimits);
  cell.joint_margin = 0;
  const CellReach reached = reachView(cell, behind);
  ASSERT_TRUE(reached.reachable());  // axis 1 turns +-180°
  for (const CellPose& pose : reached.poses) EXPECT_NEAR(std::abs(pose.joints[0]), M_PI, 1e-6);
  cell.robot.lower[0] = -M_PI / 2;  // a cell that fences axis 1 to +-90°
  cell.robot.upper[0] = M_PI / 2;
  const CellReach fenced = reachView(cell, behind);
  EXPECT_FALSE(fenced.reachable());
  EXPECT_EQ(fenced.failure, CellFailure::JointLimits);
}

TEST(Cell, RotaryTableBringsTheFarSideWithinReach) {
  // A robot 1.3 m from a part; a view of the part's far side, 500 mm beyond it.
  Cell cell = irb2400At({-1300, 50, 0});
  const View far_side = viewAt({550, 50, 50}, {100, 50, 50});
  EXPECT_FALSE(reachView(cell, far_side).reachable());
  cell.table = RotaryTable{};
  cell.table->origin = Vec3(50, 50, 0);
  const CellReach turned = reachView(cell, far_side);
  ASSERT_TRUE(turned.reachable());
  EXPECT_GT(std::abs(turned.poses.front().table_angle), M_PI / 2);
  // The joints found put the scanner where the turned view is.
  for (const CellPose& pose : turned.poses) {
    const Pose flange = forwardKinematics(cell.robot, pose.joints);
    EXPECT_TRUE(flange.isApprox(flangeFor(cell, far_side, pose.table_angle), 1e-9));
  }
}

Spec specWith(const test::TempDir& dir, const std::string& text) {
  test::writeText(dir.file("spec.yaml"), text);
  return loadSpec(dir.file("spec.yaml"));
}

TEST(Cell, SpecReadsTheCell) {
  test::TempDir dir;
  const Spec spec =
      specWith(dir,
               "cell:\n"
               "  robot: {preset: abb-irb4600-60-205, link_radii: [150, 120, 80],\n"
               "          base: {position: [-1000, 0, 0], rotation: [0, 0, 90]}}\n"
               "  mount: {position: [0, 0, 120], rotation: [0, 0, 0]}\n"
               "  table: {origin: [0, 0, 0], axis: [0, 0, 1], range: [-90, 90], "
               "step: 10, unit: orbit_a}\n"
               "  tool: {mass: 2.7, centre: [0, 10, 95], inertia: [0.02, 0.03, 0.01]}\n"
               "  signals: {view: 17, trigger: 2, acknowledge: 3, "
               "table: {angle: 1, move: 4, ready: 5}, timeout: 2.5}\n"
               "  home: [0, -10, 20, 0, 45, 0]\n  approach: 80\n"
               "  joint_margin: 3\n");
  ASSERT_TRUE(spec.cell);
  EXPECT_EQ(spec.cell->tool.mass, 2.7);
  EXPECT_TRUE(spec.cell->tool.centre->isApprox(Vec3(0, 10, 95)));
  EXPECT_EQ(spec.cell->tool.inertia, Vec3(0.02, 0.03, 0.01));
  EXPECT_EQ(spec.cell->signals.view, 17);
  EXPECT_EQ(spec.cell->signals.acknowledge, 3);
  ASSERT_TRUE(spec.cell->signals.table);
  EXPECT_EQ(spec.cell->signals.table->ready, 5);
  EXPECT_EQ(spec.cell->signals.timeout, 2.5);
  ASSERT_TRUE(spec.cell->home);
  EXPECT_NEAR((*spec.cell->home)[4], M_PI / 4, 1e-12);
  EXPECT_EQ(spec.cell->approach, 80);
  EXPECT_NEAR(spec.cell->joint_margin, radians(3), 1e-12);
  EXPECT_EQ(spec.cell->robot.name, "abb-irb4600-60-205");
  EXPECT_EQ(spec.cell->robot.link_radii[0], 150);
  EXPECT_EQ(spec.cell->robot.link_radii[2], 80);
  EXPECT_TRUE(spec.cell->base.translation().isApprox(Vec3(-1000, 0, 0)));
  EXPECT_TRUE((spec.cell->base.linear() * Vec3::UnitX()).isApprox(Vec3::UnitY()));
  EXPECT_NEAR(spec.cell->mount.translation().z(), 120, 1e-12);
  ASSERT_TRUE(spec.cell->table);
  EXPECT_NEAR(spec.cell->table->upper, M_PI / 2, 1e-12);
  EXPECT_EQ(spec.cell->table->unit, "orbit_a");
  EXPECT_NEAR(spec.cell->table->step, M_PI / 18, 1e-12);
  // Explicit parameters instead of a preset.
  const Spec custom = specWith(dir,
                               "cell:\n  robot: {a1: 100, a2: -135, b: 0, c1: 615, c2: 705, "
                               "c3: 755, c4: 85,\n    lower: [-180, -100, -60, -200, -120, -400],\n"
                               "    upper: [180, 110, 65, 200, 120, 400], offsets: [0, 0, -90, 0, "
                               "0, 0]}\n");
  ASSERT_TRUE(custom.cell);
  const RobotModel preset = robotPreset("abb-irb2400-10");
  const Joints q{0.3, 0.2, -0.1, 0.5, 0.4, 0.1};
  EXPECT_TRUE(forwardKinematics(custom.cell->robot, q).isApprox(forwardKinematics(preset, q)));
}

TEST(Cell, SpecRejectsABadCell) {
  test::TempDir dir;
  for (const char* text :
       {"cell:\n  robot: {preset: kuka-kr1000}\n",
        "cell:\n  robot: {preset: abb-irb2400-10}\n  table: {range: [10, 90]}\n",
        "cell:\n  robot: {preset: abb-irb2400-10}\n  table: {range: [-1e7, 1e7]}\n",
        "cell:\n  mount: {position: [0, 0, 100]}\n", "cell:\n  robot: {a1: 100}\n",
        "cell:\n  robot: {preset: abb-irb2400-10, base: {turn: [0, 0, 1]}}\n",
        "cell:\n  robot: {preset: ur5e, c2: 400}\n",
        "cell:\n  robot: {preset: ur5e}\n  tool: {mass: -1}\n",
        "cell:\n  robot: {preset: ur5e}\n  tool: {inertia: [0.1, -0.1, 0.1]}\n",
        "cell:\n  robot: {preset: ur5e}\n  signals: {trigger: -2}\n",
        "cell:\n  robot: {preset: ur5e}\n  signals: {table: {angle: 1}}\n",
        "cell:\n  robot: {preset: ur5e}\n  signals: {timeout: 0}\n",
        "cell:\n  robot: {preset: abb-irb2400-10}\n  table: {unit: 1st}\n",
        "cell:\n  robot: {preset: abb-irb2400-10}\n  table: {unit: \"STN\\\";Stop;\"}\n",
        "cell:\n  robot: {preset: ur5e}\n  signals: {timeout: 1e9}\n",
        "cell:\n  robot: {preset: abb-irb2400-10}\n  home: [0, 0, 0, 0, 0, 500]\n",
        "cell:\n  robot: {preset: ur5e}\n  motion_step: 2\n",
        "cell:\n  robot: {preset: ur5e}\n  joint_margin: -1\n",
        "cell:\n  robot: {preset: ur5e}\n  joint_margin: 11\n"}) {
    test::writeText(dir.file("bad.yaml"), text);
    try {
      loadSpec(dir.file("bad.yaml"));
      ADD_FAILURE() << "accepted: " << text;
    } catch (const InputError& e) {
      EXPECT_NE(std::string(e.what()).find("bad.yaml"), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find("cell"), std::string::npos) << e.what();
    }
  }
}

// A 100 mm cube on the plane, an IRB 2400 1.3 m away on one side: its far side is out of
// reach, unless a table turns the cube.
Plan cubePlanInCell(const test::TempDir& dir, bool table) {
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 100, 100).Shape(), dir.file("cube.brep").c_str());
  const Part part = importPart(dir.file("cube.brep"));
  Spec spec = defaultSpec();
  spec.cell = irb2400At({-1300, 50, 0});
  if (table) {
    spec.cell->table = RotaryTable{};
    spec.cell->table->origin = Vec3(50, 50, 0);
  }
  return planViews(part, spec);
}

TEST(Cell, PlanKeepsOnlyReachableViewsAndSaysWhatIsOutOfReach) {
  test::TempDir dir;
  const Plan plan = cubePlanInCell(dir, false);
  ASSERT_TRUE(plan.cell);
  ASSERT_EQ(plan.cell_poses.size(), plan.views.size());
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    ASSERT_TRUE(plan.cell_poses[v]) << plan.views[v].id;
    EXPECT_TRUE(forwardKinematics(plan.cell->robot, plan.cell_poses[v]->joints)
                    .isApprox(flangeFor(*plan.cell, plan.views[v], 0), 1e-9));
  }
  std::size_t unreachable = 0, far_side = 0;
  for (const PlannedSample& s : plan.samples) {
    if (s.sample.normal.x() > 0.99) {
      ++far_side;
      EXPECT_TRUE(s.measured_by.empty());
      EXPECT_EQ(s.uncoverable, Uncoverable::Unreachable);
    }
    unreachable += s.uncoverable == Uncoverable::Unreachable;
  }
  EXPECT_GT(far_side, 0u);
  EXPECT_GE(unreachable, far_side);
  // The reason and the joints are in plan.json.
  writePlan(plan, dir.file("plan.json"));
  const Plan back = readPlan(dir.file("plan.json"));
  std::size_t unreachable_back = 0;
  for (const PlannedSample& s : back.samples)
    unreachable_back += s.uncoverable == Uncoverable::Unreachable;
  EXPECT_EQ(unreachable_back, unreachable);
  const nlohmann::json json = planJson(plan);
  EXPECT_EQ(json["views"][0]["robot"]["joints"].size(), 6u);
  EXPECT_EQ(json["summary"]["robot"]["unreached_views"], 0);
}

// A 100 mm cube planned in a collaborative cell: a UR10e (offset wrist) beside a rotary
// table, read from the spec.
Plan cubePlanWithUr(const test::TempDir& dir) {
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 100, 100).Shape(), dir.file("cube.brep").c_str());
  const Part part = importPart(dir.file("cube.brep"));
  test::writeText(dir.file("spec.yaml"),
                  "cell:\n  robot: {preset: ur10e, base: {position: [-750, 50, 0]}}\n"
                  "  table: {origin: [50, 50, 0]}\n");
  return planViews(part, loadSpec(dir.file("spec.yaml")));
}

// The UR10e with its table measures every side of the cube but the one it stands on; each
// view's joints put the flange where the view needs it, at its table angle.
TEST(Cell, AUniversalRobotWithATableMeasuresEverySide) {
  test::TempDir dir;
  const Plan plan = cubePlanWithUr(dir);
  ASSERT_TRUE(plan.cell && plan.cell->robot.offset_wrist);
  ASSERT_FALSE(plan.views.empty());
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    ASSERT_TRUE(plan.cell_poses[v]) << plan.views[v].id;
    const CellPose& pose = *plan.cell_poses[v];
    EXPECT_TRUE(forwardKinematics(plan.cell->robot, pose.joints)
                    .isApprox(flangeFor(*plan.cell, plan.views[v], pose.table_angle), 1e-9));
  }
  for (const PlannedSample& s : plan.samples) {
    if (s.sample.normal.z() < -0.99) continue;  // the face the cube stands on
    EXPECT_FALSE(s.measured_by.empty()) << s.sample.position.transpose();
  }
  // plan.json carries the cell whole, and each view's joints.
  writePlan(plan, dir.file("plan.json"));
  const Plan back = readPlan(dir.file("plan.json"));
  ASSERT_TRUE(back.cell && back.cell->robot.offset_wrist && back.cell->table);
  EXPECT_EQ(back.cell->robot.offset_wrist->a3, -571.55);
  EXPECT_EQ(back.cell->robot.maker, "universal-robots");  // which program formats it runs
  EXPECT_TRUE(back.cell->base.isApprox(plan.cell->base));
  ASSERT_EQ(back.cell_poses.size(), plan.views.size());
  for (std::size_t v = 0; v < plan.views.size(); ++v)
    EXPECT_TRUE(
        forwardKinematics(back.cell->robot, back.cell_poses[v]->joints)
            .isApprox(forwardKinematics(plan.cell->robot, plan.cell_poses[v]->joints), 1e-9));
  // A FANUC arm keeps its maker and its J2-J3 coupling through plan.json, and the cell its
  // handshake's timeout.
  Plan fanuc = plan;
  fanuc.cell->robot = robotPreset("fanuc-m20id-25");
  fanuc.cell->signals.timeout = 2.5;
  fanuc.cell->table->unit = "STN_2";
  fanuc.cell_poses.assign(fanuc.views.size(), std::nullopt);
  writePlan(fanuc, dir.file("fanuc.json"));
  const Plan fanuc_back = readPlan(dir.file("fanuc.json"));
  EXPECT_EQ(fanuc_back.cell->robot.maker, "fanuc");
  EXPECT_EQ(fanuc_back.cell->robot.j23_coupling, 1);
  EXPECT_EQ(fanuc_back.cell->signals.timeout, 2.5);
  EXPECT_EQ(fanuc_back.cell->table->unit, "STN_2");
  // A cell that would hang or mislead the programs is refused: a table step of 0.
  nlohmann::json json = planJson(plan);
  json["cell"]["table"]["step"] = 0;
  test::writeText(dir.file("bad.json"), json.dump());
  EXPECT_THROW(readPlan(dir.file("bad.json")), InputError);
}

// The plan's robot travel is its program's: the approach and retract moves at each view
// add to the joint travel between the views. The program gives each view's scanner pose
// in the part's frame, which is the view's camera pose in the part's frame whatever the
// table angle.
TEST(Cell, ThePlanCountsItsProgramsMotionAndGivesPosesInThePartsFrame) {
  test::TempDir dir;
  const Plan plan = cubePlanWithUr(dir);
  ASSERT_TRUE(plan.cell && plan.cell_motion);
  EXPECT_TRUE(plan.cell_motion->uncleared.empty());
  const JointMotion between =
      jointMotion(*plan.cell, plan.cell_poses, plan.views, visitingOrder(plan));
  EXPECT_GT(plan.cell_motion->seconds, between.seconds);
  writePlan(plan, dir.file("plan.json"));
  const Plan back = readPlan(dir.file("plan.json"));
  ASSERT_TRUE(back.cell_motion);
  EXPECT_DOUBLE_EQ(back.cell_motion->seconds, plan.cell_motion->seconds);

  const RobotProgram program = robotProgram(plan, *plan.cell, plan.cell_poses, "cube", "plan");
  ASSERT_EQ(program.steps.size(), plan.views.size());
  std::map<int, const View*> views;
  for (const View& v : plan.views) views[v.id] = &v;
  bool turned = false;
  for (const ProgramStep& step : program.steps) {
    turned = turned || step.pose.table_angle != 0;
    const Pose expected = plan.part_to_world.inverse() * views.at(step.view)->camera_to_world;
    EXPECT_TRUE(scannerInPart(program, step).isApprox(expected, 1e-9)) << step.view;
  }
  EXPECT_TRUE(turned);  // the check covers views at other table angles
}

// A program of two views of `cell`'s robot 50° either side of axis 1, the flange 850 mm out
// and `height` mm up, pointing down: each pose the first clear inverse-kinematics solution.
// Empty where a pose has none.
RobotProgram acrossJointOne(const Cell& cell, const CellCollisions& collisions, double height) {
  RobotProgram program;
  program.cell = cell;
  for (const double side : {1.0, -1.0}) {
    Pose flange = Pose::Identity();
    flange.linear() = Eigen::AngleAxisd(M_PI, Vec3::UnitX()).toRotationMatrix();
    flange.translation() =
        Vec3(850 * std::cos(radians(50)), side * 850 * std::sin(radians(50)), height);
    const std::vector<Joints> q = inverseKinematics(cell.robot, flange);
    if (q.empty() || collisions.collides({0, q.front()})) return {};
    program.steps.push_back({side > 0 ? 1 : 2, "global", {0, q.front()}, flange, {}, {}});
  }
  return program;
}

// An IRB 2400 and a 400 mm block 700 mm ahead of it; two poses on either side of the block,
// the flange 250 mm up and pointing down. Turning joint 1 straight from one to the other
// sweeps the arm through the block; planMotion lifts the move over it, and every
// configuration along the program, sampled eight times finer than the planner samples,
// is clear.
TEST(Cell, AMoveThroughThePartIsLiftedOverIt) {
  TriangleMesh block;
  test::addCube(block, Vec3(700, -200, 0), 400, 1);
  Cell cell = irb2400At(Vec3::Zero());
  const CellCollisions collisions(cell, Box{}, block, Pose::Identity(), {}, true, cell.clearance);
  RobotProgram program = acrossJointOne(cell, collisions, 250);
  ASSERT_EQ(program.steps.size(), 2u);
  ASSERT_FALSE(moveIsClear(collisions, program.steps[0].pose, program.steps[1].pose));
  planMotion(program, collisions, 420);
  EXPECT_TRUE(program.uncleared.empty());
  ASSERT_TRUE(program.home);
  EXPECT_FALSE(program.steps[1].via.empty());
  for (const ProgramStep& step : program.steps) EXPECT_TRUE(step.approach);
  const std::vector<Waypoint> path = waypoints(program);
  std::size_t checked = 0;
  for (std::size_t k = 1; k < path.size(); ++k)
    for (const CellPose& pose : sampledMove(collisions, path[k - 1].pose, path[k].pose, 8)) {
      EXPECT_FALSE(collisions.collides(pose)) << path[k - 1].what << " -> " << path[k].what;
      ++checked;
    }
  RecordProperty("configurations_checked", std::to_string(checked));
  EXPECT_GT(programSeconds(program), 0);
}

TEST(Cell, RotaryTableMeasuresTheFarSide) {
  test::TempDir dir;
  const Plan plan = cubePlanInCell(dir, true);
  bool turned = false;
  for (const std::optional<CellPose>& pose : plan.cell_poses) {
    ASSERT_TRUE(pose);
    turned = turned || std::abs(pose->table_angle) > 1e-9;
  }
  EXPECT_TRUE(turned);
  for (const PlannedSample& s : plan.samples) {
    if (s.sample.normal.z() < -0.99) continue;  // the face the cube stands on
    EXPECT_FALSE(s.measured_by.empty()) << s.sample.position.transpose();
  }
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

// The distance from the point `p` to the segment [u, v].
double segmentDistance(const Vec3& p, const Vec3& u, const Vec3& v) {
  const Vec3 d = v - u;
  const double t = std::clamp((p - u).dot(d) / std::max(d.squaredNorm(), 1e-300), 0.0, 1.0);
  return (p - (u + t * d)).norm();
}

// The distance from the point `p` to the triangle (a, b, c), by its plane where `p`
// projects inside it, else by its nearest edge.
double triangleDistance(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  auto segment = [&](const Vec3& u, const Vec3& v) { return segmentDistance(p, u, v); };
  const Vec3 n = (b - a).cross(c - a);
  if (n.squaredNorm() > 1e-24) {
    const Vec3 q = p - n.dot(p - a) / n.squaredNorm() * n;
    const bool inside = n.dot((b - a).cross(q - a)) >= 0 && n.dot((c - b).cross(q - b)) >= 0 &&
                        n.dot((a - c).cross(q - c)) >= 0;
    if (inside) return (p - q).norm();
  }
  return std::min({segment(a, b), segment(b, c), segment(c, a)});
}

// The least distance from the segment [a, b], sampled every millimetre, to `mesh`; only
// triangles whose bounds come within `within` of the segment's are looked at (farther
// ones count as `within`).
double axisDistance(const TriangleMesh& mesh, const Vec3& a, const Vec3& b, double within) {
  Box near;
  near.add(a);
  near.add(b);
  near.min -= Vec3::Constant(within);
  near.max += Vec3::Constant(within);
  const int steps = std::max(1, static_cast<int>(std::ceil((b - a).norm())));
  double least = within;
  for (const Vec3i& tri : mesh.triangles) {
    const Vec3 &p = mesh.vertices[tri[0]], &q = mesh.vertices[tri[1]], &r = mesh.vertices[tri[2]];
    const Vec3 lo = p.cwiseMin(q).cwiseMin(r), hi = p.cwiseMax(q).cwiseMax(r);
    if ((lo.array() > near.max.array()).any() || (hi.array() < near.min.array()).any()) continue;
    for (int s = 0; s <= steps; ++s) {
      const Vec3 x = a + (b - a) * s / steps;
      if (((lo.array() - x.array()) > within).any() || ((x.array() - hi.array()) > within).any())
        continue;  // this triangle lies farther than `within` from this point
      least = std::min(least, triangleDistance(x, p, q, r));
    }
  }
  return least;
}

// A NIST part (CTC 03, 303 x 485 x 163 mm) planned for its GD&T and whole shape in a cell
// with an IRB 4600 1.15 m from it: joints 1 to 5 chosen along the sequence never jump by
// 180° or more between consecutive views (joint 6 only turns the scanner about its axis,
// and may turn further where that is quickest).
TEST(Cell, JointStepsAlongTheSequenceOfANistPlanStayBoundedAndItsArmClear) {
  const Part part = importPart(test::testData("nist_ctc_03_asme1_ap242-e2.stp"));
  Spec spec = defaultSpec();
  spec.gdt_from_file = true;
  spec.tasks = {Task{TaskType::Gdt, {}, {}, {}}, Task{TaskType::Global, {}, {}, {}}};
  spec.planner.anchors = 60;          // a small pool and a short search: the joints are tested,
  spec.planner.selection_nodes = 20;  // not the views
  Cell cell;
  cell.robot = robotPreset("abb-irb4600-60-205");
  cell.base.translation() = Vec3(-1150, 240, 0);
  cell.mount.translation() = Vec3(0, 0, 150);
  spec.cell = cell;
  const Plan plan = planViews(part, spec);
  ASSERT_TRUE(plan.sequence);
  const JointMotion motion = jointMotion(cell, plan.cell_poses, plan.views, plan.sequence->views);
  EXPECT_EQ(motion.unreached, 0u);
  EXPECT_GT(plan.views.size(), 10u);
  // A wrist flip turns joint 4 by 180°, a base swing joint 1: every step stays below that.
  RecordProperty("largest_joint_step_degrees", std::to_string(degrees(motion.max_step)));
  RecordProperty("joint_travel_seconds", std::to_string(motion.seconds));
  std::map<int, std::size_t> index;
  for (std::size_t i = 0; i < plan.views.size(); ++i) index[plan.views[i].id] = i;
  const CellPose* previous = nullptr;
  for (int id : plan.sequence->views) {
    const std::optional<CellPose>& pose = plan.cell_poses[index.at(id)];
    if (!pose) continue;
    for (int j = 0; previous && j < 5; ++j)
      EXPECT_LT(std::abs(pose->joints[j] - previous->joints[j]), M_PI)
          << "joint " << j + 1 << " before view " << id;
    previous = &*pose;
  }
  // Ordered by joint travel, the robot moves for less time than along the order that
  // the scanner's Cartesian motion gives, with joints chosen the same way.
  const Simulator simulator(
      part, spec.scanner, simulationOptionsFor(resolveSpec(part, spec), part, plan.part_to_world));
  const CellCollisions collisions(cell, Box{}, part.mesh, plan.part_to_world, {}, true,
                                  cell.clearance);
  const Sequence cartesian = sequenceViews(simulator, plan.views, *plan.registration);
  const JointMotion along_cartesian = jointMotion(
      cell, cellPoses(cell, plan.views, cartesian.views, &collisions), plan.views, cartesian.views);
  RecordProperty("cartesian_order_joint_travel_seconds", std::to_string(along_cartesian.seconds));
  EXPECT_LT(motion.seconds, along_cartesian.seconds);

  // The arm's collisions by a second, simple geometry: each link's axis sampled every
  // millimetre against every triangle of the placed part (and the working plane), where
  // FCL tests capsules against a bounding-volume hierarchy. They agree on every pose where
  // the brute force is decisive (its sampling leaves half a millimetre of doubt): the
  // plan's poses, all clear, the same leant into the part, and random poses within the
  // joint limits.
  TriangleMesh world = part.mesh;
  for (Vec3& v : world.vertices) v = plan.part_to_world * v;
  std::vector<CellPose> poses;
  for (const std::optional<CellPose>& pose : plan.cell_poses)
    if (pose) poses.push_back(*pose);
  const std::size_t planned = poses.size();
  // Each planned pose with the upper arm leant 10 and 20 degrees further forward: the scanner
  // and the forearm go down into the part, above the plane.
  for (std::size_t k = 0; k < planned; ++k)
    for (const double lean : {10.0, 20.0}) {
      CellPose leant = poses[k];
      leant.joints[1] += radians(lean);
      poses.push_back(leant);
    }
  std::mt19937_64 random(9);
  for (int k = 0; k < 60; ++k) {
    CellPose pose;
    for (int j = 0; j < 6; ++j)
      pose.joints[j] =
          std::uniform_real_distribution<double>(cell.robot.lower[j], cell.robot.upper[j])(random);
    poses.push_back(pose);
  }
  std::size_t decisive = 0, collide = 0, through_part = 0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    bool surely = false, maybe = false, part_hit = false, plane_hit = false;
    for (const CellCollisions::Capsule& c : collisions.links(poses[k])) {
      const double reach = c.radius + cell.clearance;
      plane_hit = plane_hit || std::min(c.a.z(), c.b.z()) - reach < 0;
      surely = surely || plane_hit;
      const double d = axisDistance(world, c.a, c.b, reach + 1);
      part_hit = part_hit || d < reach;
      surely = surely || d < reach;
      maybe = maybe || d < reach + 0.5;
    }
    const bool fcl = collisions.collides(poses[k]);
    if (k < planned) {
      EXPECT_FALSE(fcl) << "planned pose " << k;
    }
    if (surely == maybe || surely) {
      ++decisive;
      EXPECT_EQ(fcl, surely) << "pose " << k;
      collide += surely;
      through_part += part_hit && !plane_hit;
    }
  }
  RecordProperty("collision_poses", std::to_string(decisive) + " decisive, " +
                                        std::to_string(collide) + " colliding, " +
                                        std::to_string(through_part) +
                                        " through the part above the plane");
  EXPECT_GE(decisive, poses.size() - 5);
  EXPECT_GT(through_part, 0u);
  EXPECT_GT(decisive - collide, planned);
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

// An axis-aligned box [lo, lo + size] as triangles.
TriangleMesh box(const Vec3& lo, const Vec3& size) {
  TriangleMesh mesh;
  test::addCube(mesh, Vec3::Zero(), 1, 1);
  for (Vec3& v : mesh.vertices) v = lo + v.cwiseProduct(size);
  return mesh;
}

TEST(Cell, ArmThroughAWallIsACollision) {
  Cell cell = irb2400At({-1300, 50, 0});
  const View above = viewAt({0, 50, 500}, {0, 50, 0});
  const TriangleMesh nothing;
  const CellCollisions open(cell, Box{}, nothing, Pose::Identity(), {}, true, 10);
  const CellReach free = reachView(cell, above, {}, 0, &open);
  ASSERT_TRUE(free.reachable());
  // The links end where the arm's joints are: the last one at the flange.
  for (const CellPose& pose : free.poses) {
    const std::vector<CellCollisions::Capsule> links = open.links(pose);
    ASSERT_EQ(links.size(), 3u);
    EXPECT_LT(
        (links.back().b - cell.base * forwardKinematics(cell.robot, pose.joints).translation())
            .norm(),
        1e-9);
  }
  // A wall 2 m high between the robot and the part: every arm configuration crosses it.
  const TriangleMesh wall = box({-700, -1000, 0}, {50, 2000, 2000});
  const CellCollisions walled(cell, Box{}, wall, Pose::Identity(), {}, true, 10);
  const CellReach blocked = reachView(cell, above, {}, 0, &walled);
  EXPECT_FALSE(blocked.reachable());
  EXPECT_EQ(blocked.failure, CellFailure::Collision);
  // The same wall as a fixture mesh beside an empty part.
  const CellCollisions fixture(cell, Box{}, nothing, Pose::Identity(), {wall}, true, 10);
  EXPECT_EQ(reachView(cell, above, {}, 0, &fixture).failure, CellFailure::Collision);
}

// Each link is a capsule of its radius grown by the clearance: a small square beside the
// middle of a link, parallel to its axis, collides when it lies 1 mm inside that reach and
// is clear 1 mm outside it. The distance is built from the capsule's own ends, so FCL's
// capsule, its placement or its radius going wrong shows.
TEST(Cell, ALinkReachesExactlyItsRadiusAndClearance) {
  constexpr double kClearance = 10;  // mm
  Cell cell = irb2400At({-1300, 50, 0});
  const View above = viewAt({0, 50, 500}, {0, 50, 0});
  const TriangleMesh nothing;
  const CellCollisions open(cell, Box{}, nothing, Pose::Identity(), {}, false, kClearance);
  const CellReach free = reachView(cell, above, {}, 0, &open);
  ASSERT_TRUE(free.reachable());
  const CellPose& pose = free.poses.front();
  const std::vector<CellCollisions::Capsule> links = open.links(pose);
  std::size_t tested = 0;
  for (std::size_t k = 0; k < links.size(); ++k) {
    const CellCollisions::Capsule& c = links[k];
    const Vec3 axis = (c.b - c.a).normalized(), middle = 0.5 * (c.a + c.b);
    const double reach = c.radius + kClearance;
    // The side away from the other links: of eight around the axis, the one whose square
    // lies farthest outside their reach.
    const Vec3 u = axis.unitOrthogonal(), w = axis.cross(u);
    Vec3 side = u;
    double best = -std::numeric_limits<double>::infinity();
    for (int turn = 0; turn < 8; ++turn) {
      const Vec3 candidate = std::cos(turn * M_PI / 4) * u + std::sin(turn * M_PI / 4) * w;
      const Vec3 at = middle + reach * candidate;
      double outside = std::numeric_limits<double>::infinity();
      for (std::size_t j = 0; j < links.size(); ++j)
        if (j != k)
          outside = std::min(
              outside, segmentDistance(at, links[j].a, links[j].b) - links[j].radius - kClearance);
      if (outside > best) {
        best = outside;
        side = candidate;
      }
    }
    // The square's corners reach 7 mm from its centre: a link whose neighbours come within
    // 20 mm of every side is too short to test this way.
    if (best <= 20) continue;
    ++tested;
    const Vec3 across = axis.cross(side);
    for (const double off : {-1.0, 1.0}) {
      TriangleMesh square;
      const Vec3 centre = middle + (reach + off) * side;
      for (const auto& [along, up] : {std::pair{-5, -5}, {5, -5}, {5, 5}, {-5, 5}})
        square.vertices.push_back(centre + along * axis + up * across);
      square.triangles = {{0, 1, 2}, {0, 2, 3}};
      square.triangle_faces = {1, 1};
      const CellCollisions beside(cell, Box{}, square, Pose::Identity(), {}, false, kClearance);
      EXPECT_EQ(beside.collides(pose), off < 0) << "link " << k << ", " << off << " mm";
    }
  }
  EXPECT_GE(tested, 2u);
}

TEST(Cell, WorkingPlaneAndClearanceCount) {
  const Cell cell = irb2400At({-1300, 50, 0});
  const TriangleMesh nothing;
  // A view along the plane, 60 mm above it: the wrist comes within its radius of it.
  const View low = viewAt({-300, 50, 60}, {100, 50, 60});
  const CellCollisions with_plane(cell, Box{}, nothing, Pose::Identity(), {}, true, 10);
  const CellCollisions without_plane(cell, Box{}, nothing, Pose::Identity(), {}, false, 10);
  EXPECT_TRUE(reachView(cell, low).reachable());
  EXPECT_FALSE(reachView(cell, low, {}, 0, &with_plane).reachable());
  EXPECT_TRUE(reachView(cell, low, {}, 0, &without_plane).reachable());
  // 120 mm above the plane the 60 mm wrist clears it by 10 mm, but not by 100 mm.
  const View higher = viewAt({-300, 50, 120}, {100, 50, 120});
  const CellCollisions tight(cell, Box{}, nothing, Pose::Identity(), {}, true, 100);
  EXPECT_TRUE(reachView(cell, higher, {}, 0, &with_plane).reachable());
  EXPECT_FALSE(reachView(cell, higher, {}, 0, &tight).reachable());
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

// A box around the segment a-b at the zero pose, `half` mm out on every side.
TriangleMesh boxAround(const Vec3& a, const Vec3& b, double half) {
  const Vec3 lo = a.cwiseMin(b) - Vec3::Constant(half), hi = a.cwiseMax(b) + Vec3::Constant(half);
  return box(lo, hi - lo);
}

TEST(Cell, LinkMeshesReplaceTheCapsules) {
  Cell cell = irb2400At({-1300, 50, 0});
  Joints zero{};
  for (int i = 0; i < 6; ++i) zero[i] = cell.robot.offsets[i] * cell.robot.signs[i];
  const std::array<Vec3, 4> j = jointCentres(cell.robot, zero);
  const View above = viewAt({0, 50, 500}, {0, 50, 0});
  const TriangleMesh nothing;
  // Slim boxes around the links: the view stays free.
  cell.link_meshes = {boxAround(j[0], j[1], 60), boxAround(j[1], j[2], 50),
                      boxAround(j[2], j[3], 40)};
  const CellCollisions slim(cell, Box{}, nothing, Pose::Identity(), {}, true, 10);
  EXPECT_TRUE(reachView(cell, above, {}, 0, &slim).reachable());
  // A forearm inside a box 1.5 m out on every side reaches the plane in every solution.
  cell.link_meshes[1] = boxAround(j[1], j[2], 1500);
  const CellCollisions hanging(cell, Box{}, nothing, Pose::Identity(), {}, true, 10);
  const CellReach blocked = reachView(cell, above, {}, 0, &hanging);
  EXPECT_FALSE(blocked.reachable());
  EXPECT_EQ(blocked.failure, CellFailure::Collision);
  // And the meshes meet the part: a post up through the wrist, 650 to 735 mm high here.
  cell.link_meshes[1] = boxAround(j[1], j[2], 50);
  const TriangleMesh post = box({-60, 0, 0}, {120, 100, 700});
  const CellCollisions with_post(cell, Box{}, post, Pose::Identity(), {}, true, 10);
  EXPECT_FALSE(reachView(cell, above, {}, 0, &with_post).reachable());
}

TEST(Cell, SpecReadsLinkMeshes) {
  test::TempDir dir;
  const std::string stl =
      "solid t\nfacet normal 0 0 1\nouter loop\nvertex 0 0 0\nvertex 10 0 0\nvertex 0 10 0\n"
      "endloop\nendfacet\nendsolid t\n";
  for (const char* name : {"upper.stl", "fore.stl", "wrist.stl"})
    test::writeText(dir.file(name), stl);
  const Spec spec =
      specWith(dir,
               "cell:\n  robot: {preset: abb-irb2400-10, link_meshes: [upper.stl, fore.stl, "
               "wrist.stl]}\n");
  ASSERT_TRUE(spec.cell);
  ASSERT_EQ(spec.cell->link_meshes.size(), 3u);
  EXPECT_EQ(spec.cell->link_meshes[0].triangles.size(), 1u);
  test::writeText(dir.file("bad.yaml"),
                  "cell:\n  robot: {preset: abb-irb2400-10, link_meshes: [upper.stl, none.stl, "
                  "wrist.stl]}\n");
  try {
    loadSpec(dir.file("bad.yaml"));
    ADD_FAILURE() << "a missing link mesh was accepted";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("none.stl"), std::string::npos) << e.what();
  }
}

// The points of the robot and the scanner whose paths the sampling must follow: the joint
// centres and the scanner body's corners, in the plan's frame (the part fixed).
std::vector<Vec3> trackedPoints(const Cell& cell, const Box& body, const CellPose& pose) {
  const Pose to_plan = tableTurn(cell, -pose.table_angle) * cell.base;
  std::vector<Vec3> points;
  for (const Vec3& c : jointCentres(cell.robot, pose.joints)) points.push_back(to_plan * c);
  const Pose scanner = to_plan * forwardKinematics(cell.robot, pose.joints) * cell.mount;
  for (int i = 0; i < 8; ++i)
    points.push_back(scanner * Vec3(i & 1 ? body.max.x() : body.min.x(),
                                    i & 2 ? body.max.y() : body.min.y(),
                                    i & 4 ? body.max.z() : body.min.z()));
  return points;
}

// Random joint moves with the table turning, of an ortho-parallel and an offset-wrist arm:
// between two configurations the move checks, no joint centre and no corner of the scanner
// body moves more than half the clearance, followed along the move in 16 times finer
// steps by the forward kinematics.
TEST(Cell, NoPointMovesMoreThanHalfTheClearanceBetweenCheckedConfigurations) {
  const Box body = Scanner().body();
  const TriangleMesh part = box({-100, -100, 0}, {200, 200, 150});
  std::mt19937_64 random(4);
  for (const char* preset : {"abb-irb2400-10", "ur10e"}) {
    Cell cell;
    cell.robot = robotPreset(preset);
    cell.base.translation() = Vec3(-900, 0, 0);
    cell.mount.translation() = Vec3(0, 0, 150);
    cell.table.emplace();
    const CellCollisions collisions(cell, body, part, Pose::Identity(), {}, true, 10);
    double largest = 0;
    for (int move = 0; move < 10; ++move) {
      CellPose a, b;
      for (CellPose* p : {&a, &b}) {
        p->table_angle = std::uniform_real_distribution<double>(-1, 1)(random);
        for (int j = 0; j < 6; ++j)
          p->joints[j] = std::uniform_real_distribution<double>(-1.5, 1.5)(random);
      }
      const std::vector<CellPose> checked = sampledMove(collisions, a, b);
      const std::vector<CellPose> fine = sampledMove(collisions, a, b, 16);
      ASSERT_EQ(fine.size() - 1, 16 * (checked.size() - 1));
      for (std::size_t k = 0; k + 1 < checked.size(); ++k) {
        const std::vector<Vec3> start = trackedPoints(cell, body, checked[k]);
        for (std::size_t f = 16 * k; f <= 16 * (k + 1); ++f) {
          const std::vector<Vec3> at = trackedPoints(cell, body, fine[f]);
          for (std::size_t i = 0; i < at.size(); ++i)
            largest = std::max(largest, (at[i] - start[i]).norm());
        }
      }
    }
    RecordProperty(std::string(preset) + "_largest_step_mm", std::to_string(largest));
    EXPECT_LE(largest, collisions.sampleSpacing() + 1e-9) << preset;
    EXPECT_GT(largest, 0.25 * collisions.sampleSpacing()) << preset;  // the bound is not loose
  }
}

// An IRB 2400 turning joint 1 (and 6, holding the scanner's orientation) between two poses
// 50° either side of a post 720 mm out. The flange passes 850 mm out and 600 mm up, the
// scanner's body reaching back over the post: the arm clears the post's top (460 mm), the
// body hanging 210 mm below the flange does not. Checked with the
// arm alone the move is clear; with the scanner it is caught, and planMotion lifts it: every
// configuration of the program, sampled four times finer than the planner samples, is clear
// of the post by FCL, the scanner included.
TEST(Cell, AMoveThatSweepsTheScannerThroughAPostIsCaughtAndCleared) {
  const TriangleMesh post = box({700, -20, 0}, {40, 40, 460});
  Cell cell = irb2400At(Vec3::Zero());
  cell.approach = 0;  // the views reached straight, so that the move is the one between them
  const Box body = Scanner().body();
  const CellCollisions arm(cell, Box{}, post, Pose::Identity(), {}, true, cell.clearance);
  const CellCollisions collisions(cell, body, post, Pose::Identity(), {}, true, cell.clearance);
  RobotProgram program = acrossJointOne(cell, collisions, 600);
  ASSERT_EQ(program.steps.size(), 2u);
  const CellPose &a = program.steps[0].pose, &b = program.steps[1].pose;
  ASSERT_TRUE(moveIsClear(arm, a, b));
  ASSERT_FALSE(moveIsClear(collisions, a, b));
  planMotion(program, collisions, viaLift(cell, Scanner()));
  EXPECT_TRUE(program.uncleared.empty());
  EXPECT_FALSE(program.steps[1].via.empty());
  const std::vector<Waypoint> path = waypoints(program);
  for (std::size_t k = 1; k < path.size(); ++k)
    for (const CellPose& pose : sampledMove(collisions, path[k - 1].pose, path[k].pose, 4))
      ASSERT_FALSE(collisions.collides(pose)) << path[k - 1].what << " -> " << path[k].what;
}

// An IRB 2400 scanning under a roof 500 mm deep, 850 to 890 mm up, that reaches from 850 mm
// out: the flange 900 mm out and 300 mm up below it, pointing down. Lifted straight up, the arm
// meets the roof; from home above it, the direct move and the move through home's joints cut
// through it. The way in and out is searched for in joint space (under the roof's front
// edge): the program is cleared, every configuration of it, sampled four times finer than
// the planner samples, clear of the roof, and the same path found again.
TEST(Cell, AViewUnderARoofIsReachedByASearchedPath) {
  const TriangleMesh roof = box({850, -400, 850}, {500, 800, 40});
  Cell cell = irb2400At(Vec3::Zero());
  cell.approach = 0;
  const CellCollisions collisions(cell, Scanner().body(), roof, Pose::Identity(), {}, true,
                                  cell.clearance);
  Pose flange = Pose::Identity();
  flange.linear() = Eigen::AngleAxisd(M_PI, Vec3::UnitX()).toRotationMatrix();
  flange.translation() = Vec3(900, 0, 300);
  std::optional<Joints> under;
  for (const Joints& q : inverseKinematics(workingRange(cell), flange))
    if (!under && !collisions.collides({0, q})) under = q;
  ASSERT_TRUE(under) << "no clear pose under the roof";
  RobotProgram program;
  program.cell = cell;
  program.steps.push_back({1, "global", {0, *under}, flange, {}, {}});
  planMotion(program, collisions, viaLift(cell, Scanner()));
  ASSERT_TRUE(program.home);
  EXPECT_TRUE(program.uncleared.empty());
  EXPECT_FALSE(program.steps[0].via.empty());
  EXPECT_FALSE(program.via_home.empty());
  const std::vector<Waypoint> path = waypoints(program);
  for (std::size_t k = 1; k < path.size(); ++k)
    for (const CellPose& pose : sampledMove(collisions, path[k - 1].pose, path[k].pose, 4))
      ASSERT_FALSE(collisions.collides(pose)) << path[k - 1].what << " -> " << path[k].what;

  RobotProgram again = program;
  again.home.reset();
  again.uncleared.clear();
  for (ProgramStep& step : again.steps) step.via.clear();
  again.via_home.clear();
  planMotion(again, collisions, viaLift(cell, Scanner()));
  auto joints = [](const std::vector<CellPose>& poses) {
    std::vector<Joints> q;
    for (const CellPose& p : poses) q.push_back(p.joints);
    return q;
  };
  EXPECT_EQ(joints(again.steps[0].via), joints(program.steps[0].via));
  EXPECT_EQ(joints(again.via_home), joints(program.via_home));
}

// Without cell.home the program starts and ends at a computed home: clear, the scanner
// looking down from above the part and its fixtures, and none of the program's view or
// approach poses.
TEST(Cell, TheDefaultHomeIsClearAboveThePartAndNoViewPose) {
  test::TempDir dir;
  const Plan plan = cubePlanWithUr(dir);
  ASSERT_TRUE(plan.cell && !plan.cell->home);
  const Part part = importPart(dir.file("cube.brep"));
  const CellCollisions collisions(*plan.cell, plan.scanner.body(), part.mesh, plan.part_to_world,
                                  {}, true, plan.cell->clearance);
  const RobotProgram program =
      safeProgram(plan, *plan.cell, collisions, plan.cell_poses, "cube", "plan");
  ASSERT_TRUE(program.home);
  EXPECT_TRUE(program.uncleared.empty());
  EXPECT_FALSE(collisions.collides(*program.home));
  const Pose flange = plan.cell->base * forwardKinematics(plan.cell->robot, program.home->joints);
  const Pose scanner =
      tableTurn(*plan.cell, -program.home->table_angle) * flange * plan.cell->mount;
  EXPECT_GT(scanner.translation().z(), 100 + plan.scanner.body_depth);  // above the 100 mm cube
  EXPECT_LT(scanner.linear().col(2).z(), -0.99);                        // looking down
  auto apart = [](const Joints& p, const Joints& q) {
    double largest = 0;
    for (int j = 0; j < 6; ++j) largest = std::max(largest, std::abs(p[j] - q[j]));
    return largest;
  };
  for (const ProgramStep& step : program.steps) {
    EXPECT_GT(apart(program.home->joints, step.pose.joints), radians(5)) << step.view;
    if (step.approach) {
      EXPECT_GT(apart(program.home->joints, *step.approach), radians(5)) << step.view;
    }
  }
}

// A 800 mm bar across the table and the scanner hanging low beside it, 45° round from the
// bar's end: turning the table a quarter turn there sweeps the bar through the scanner, so
// the turn is made with the arm raised over the part. Every table turn of the program is
// made with the arm standing still, and every move is clear.
TEST(Cell, ATableTurnThatWouldHitIsMadeAtAClearPose) {
  const TriangleMesh bar = box({-400, -20, 0}, {800, 40, 100});
  Cell cell = irb2400At({-900, 0, 0});
  cell.table.emplace();
  cell.approach = 0;
  const CellCollisions collisions(cell, Scanner().body(), bar, Pose::Identity(), {}, true,
                                  cell.clearance);
  RobotProgram program;
  program.cell = cell;
  int id = 0;
  for (const auto& [angle, y] : {std::pair{0.0, 250.0}, std::pair{M_PI / 2, -250.0}}) {
    Pose flange = Pose::Identity();
    flange.linear() = Eigen::AngleAxisd(M_PI, Vec3::UnitX()).toRotationMatrix();
    flange.translation() = cell.base.inverse() * Vec3(250, y, 300);
    const std::vector<Joints> q = inverseKinematics(cell.robot, flange);
    ASSERT_FALSE(q.empty());
    ASSERT_FALSE(collisions.collides({angle, q.front()}));
    program.steps.push_back({++id, "global", {angle, q.front()}, flange, {}, {}});
  }
  const CellPose& a = program.steps[0].pose;
  ASSERT_FALSE(moveIsClear(collisions, a, {M_PI / 2, a.joints}));  // the turn there hits
  planMotion(program, collisions, viaLift(cell, Scanner()));
  EXPECT_TRUE(program.uncleared.empty());
  const std::vector<Waypoint> path = waypoints(program);
  std::size_t turns = 0;
  for (std::size_t k = 1; k < path.size(); ++k) {
    const CellPose &from = path[k - 1].pose, &to = path[k].pose;
    if (from.table_angle != to.table_angle) {
      ++turns;
      EXPECT_EQ(from.joints, to.joints) << "the arm moves while the table turns, move " << k;
      EXPECT_NE(from.joints, a.joints) << "turned where the turn hits";
    }
    for (const CellPose& pose : sampledMove(collisions, from, to, 4))
      ASSERT_FALSE(collisions.collides(pose)) << path[k - 1].what << " -> " << path[k].what;
  }
  EXPECT_EQ(turns, 2u);  // to a quarter turn for the second view, and back home
}

// The joints chosen along the order are the least travel time, the first view's winding
// from the joints' turns nearest 0 and the last one's unwinding back included: on four
// views of an IRB 2400 (axis 6 ±400°), against every combination of the views' solutions.
TEST(Cell, JointsAlongTheOrderTravelLeastWithTheWindingCountedByBruteForce) {
  const Cell cell = irb2400At(Vec3::Zero());
  std::vector<View> views;
  for (int k = 0; k < 4; ++k) {
    const double a = radians(-60 + 40 * k);
    const Vec3 target(900, 200 * std::sin(a), 0);
    views.push_back(viewAt(target + Vec3(300 * std::cos(a), 300 * std::sin(a), 400), target));
    views.back().id = k + 1;
  }
  const CellSolutions solutions = cellSolutions(cell, views);
  const std::vector<int> order = {1, 2, 3, 4};
  const std::vector<std::optional<CellPose>> chosen = cellPoses(cell, views, order, solutions);
  auto cost = [&](const std::array<const CellPose*, 4>& p) {
    double t = unwindingTime(cell, *p[0]) + unwindingTime(cell, *p[3]);
    for (int k = 1; k < 4; ++k) t += moveTime(cell, *p[k - 1], *p[k]);
    return t;
  };
  double best = std::numeric_limits<double>::infinity();
  std::size_t combinations = 0;
  for (const CellPose& a : solutions[0])
    for (const CellPose& b : solutions[1])
      for (const CellPose& c : solutions[2])
        for (const CellPose& d : solutions[3]) {
          best = std::min(best, cost({&a, &b, &c, &d}));
          ++combinations;
        }
  RecordProperty("combinations", std::to_string(combinations));
  for (const std::optional<CellPose>& pose : chosen) ASSERT_TRUE(pose);
  EXPECT_GT(combinations, 1000u);
  EXPECT_NEAR(cost({&*chosen[0], &*chosen[1], &*chosen[2], &*chosen[3]}), best, 1e-9);
}

// The seconds between two views that the views are ordered by are the least move time
// over every pair of their solutions: on a UR10e, whose joints all turn ±360°, each view
// has up to 8 × 2⁶ solutions, compared one by one. And where a view's solutions are not
// every combination of their joints' turns, still the brute force's: axes 1 and 2 each a
// radian or a turn less, but never both a radian, so that one of them must travel far.
TEST(Cell, TravelTimesBetweenViewsAreTheLeastOverEverySolutionPair) {
  Cell cell;
  cell.robot = robotPreset("ur10e");
  cell.mount.translation() = Vec3(0, 0, 150);
  std::vector<View> views;
  for (int k = 0; k < 4; ++k) {
    const double a = radians(-50 + 35 * k);
    const Vec3 target(700 * std::cos(a), 700 * std::sin(a), 0);
    views.push_back(viewAt(target + Vec3(250 * std::cos(2 * a), 100, 450), target));
  }
  const auto bruteForce = [&](const CellSolutions& solutions, std::size_t i, std::size_t j) {
    double best = std::numeric_limits<double>::infinity();
    for (const CellPose& a : solutions[i])
      for (const CellPose& b : solutions[j]) best = std::min(best, moveTime(cell, a, b));
    return best;
  };
  const auto expectBruteForce = [&](const CellSolutions& solutions) {
    const Eigen::MatrixXd times = jointTravelTimes(cell, solutions);
    for (std::size_t i = 0; i < solutions.size(); ++i) {
      for (std::size_t j = 0; j < solutions.size(); ++j) {
        if (i == j) continue;
        EXPECT_EQ(times(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)),
                  bruteForce(solutions, i, j))
            << i << " -> " << j;
      }
    }
  };
  const CellSolutions solutions = cellSolutions(cell, views);
  for (const std::vector<CellPose>& s : solutions) ASSERT_GT(s.size(), 64u);
  expectBruteForce(solutions);

  const double turn = 2 * M_PI;
  const CellPose rest{0, {0, 0, 0, 0, 0, 0}}, first{0, {1, 1 - turn, 0, 0, 0, 0}},
      second{0, {1 - turn, 1, 0, 0, 0, 0}};
  expectBruteForce({{rest}, {first, second}});
  EXPECT_GT(jointTravelTimes(cell, {{rest}, {first, second}})(0, 1),
            moveTime(cell, rest, CellPose{0, {1, 1, 0, 0, 0, 0}}));
}

// The table's frame, which RAPID's coordinated work object gives the part in: its origin,
// z along its axis, x the world's x laid across the axis (the world's y where the axis
// lies along x), y completing a right-handed frame. Against hand values: an axis tilted
// towards y keeps x the world's x; an axis along x takes the world's y.
TEST(Cell, TheTablesFrameHasItsAxisAsZAndTheWorldsXLaidAcrossIt) {
  RotaryTable table;
  table.origin = Vec3(200, -150, 30);
  table.axis = Vec3(0, 0.1, 1);
  const double a = 0.1 / std::sqrt(1.01), b = 1 / std::sqrt(1.01);
  Pose frame = tableFrame(table);
  EXPECT_TRUE(frame.translation().isApprox(table.origin, 1e-12));
  EXPECT_TRUE(frame.linear().col(0).isApprox(Vec3(1, 0, 0), 1e-12));
  EXPECT_TRUE(frame.linear().col(1).isApprox(Vec3(0, b, -a), 1e-12));
  EXPECT_TRUE(frame.linear().col(2).isApprox(Vec3(0, a, b), 1e-12));
  table.axis = Vec3(2, 0, 0);
  frame = tableFrame(table);
  EXPECT_TRUE(frame.linear().col(0).isApprox(Vec3(0, 1, 0), 1e-12));
  EXPECT_TRUE(frame.linear().col(1).isApprox(Vec3(0, 0, 1), 1e-12));
  EXPECT_TRUE(frame.linear().col(2).isApprox(Vec3(1, 0, 0), 1e-12));
}

// The views the planner leaves out when the robot cannot clear their moves: those in two
// moves between views that no route clears; moves to or from home (which may itself
// collide) and a move alone (whose order may be what fails) blame no view.
TEST(Cell, TheViewsBehindMovesNotClearedAreThoseNoRouteReachesOrLeaves) {
  EXPECT_EQ(viewsBehind({{104, 111}, {111, 146}}), std::vector<int>{111});
  EXPECT_EQ(viewsBehind({{3, 4}, {4, 5}, {9, 2}, {2, 7}}), (std::vector<int>{2, 4}));
  EXPECT_TRUE(viewsBehind({{3, 4}, {9, 2}}).empty());
  EXPECT_TRUE(viewsBehind({{0, 5}, {5, 0}}).empty());
  EXPECT_TRUE(viewsBehind({{0, 5}, {5, 6}}).empty());
  EXPECT_TRUE(viewsBehind({}).empty());
}

// The payload's inertia: the scanner's body as a uniform box of the tool's mass, its axes
// turned into the flange's by the mount (a quarter turn about z swaps x and y), unless the
// spec gives it. A 2 kg box 0.3 × 0.12 × 0.26 m: Jx = m (b² + c²) / 12 and so on.
TEST(Cell, TheLoadsInertiaIsTheScannerBodyAsAUniformBoxUnlessGiven) {
  Cell cell;
  cell.tool.mass = 2;
  Box body;
  body.add(Vec3(-50, -60, -200));
  body.add(Vec3(250, 60, 60));
  const Vec3 box(2.0 / 12 * (0.12 * 0.12 + 0.26 * 0.26), 2.0 / 12 * (0.3 * 0.3 + 0.26 * 0.26),
                 2.0 / 12 * (0.3 * 0.3 + 0.12 * 0.12));
  EXPECT_TRUE(loadInertia(cell, body).isApprox(box, 1e-12));
  cell.mount.linear() = Eigen::AngleAxisd(M_PI / 2, Vec3::UnitZ()).toRotationMatrix();
  EXPECT_TRUE(loadInertia(cell, body).isApprox(Vec3(box.y(), box.x(), box.z()), 1e-12));
  cell.tool.inertia = Vec3(0.1, 0.2, 0.3);
  EXPECT_EQ(loadInertia(cell, body), Vec3(0.1, 0.2, 0.3));
}

}  // namespace
}  // namespace scanplan
