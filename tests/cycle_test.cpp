// The cycle-time model (robot/cycle.h) against hand-worked trapezoids and a time-stepped
// reference.
#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/robot/cycle.h>
#include <scanplan/robot/kinematics.h>
#include <scanplan/robot/program.h>

#include <cmath>

namespace scanplan {
namespace {

// 100 mm at 10 mm/s and 5 mm/s²: 2 s up to speed (10 mm), 8 s at it (80 mm), 2 s down.
TEST(Cycle, LongMoveRisesCruisesAndBrakes) {
  EXPECT_NEAR(trapezoidSeconds(100, 10, 5), 12.0, 1e-12);
  EXPECT_NEAR(trapezoidSeconds(100, 10, 5), test::steppedMoveSeconds(100, 10, 5), 1e-3 * 12);
}

// 10 mm at the same limits never reaches 10 mm/s: 5 mm up, 5 mm down, 2·√2 s in all, its
// top speed √50 ≈ 7.07 mm/s.
TEST(Cycle, ShortMoveIsATriangleBelowTheTopSpeed) {
  EXPECT_NEAR(trapezoidSeconds(10, 10, 5), 2 * std::sqrt(2.0), 1e-12);
  EXPECT_NEAR(trapezoidSeconds(10, 10, 5), test::steppedMoveSeconds(10, 10, 5), 1e-3 * 2.83);
  // Where the move just reaches the speed (20 mm), the two shapes meet: 4 s.
  EXPECT_NEAR(trapezoidSeconds(20, 10, 5), 4.0, 1e-12);
  EXPECT_NEAR(trapezoidSeconds(20 - 1e-9, 10, 5), 4.0, 1e-6);
  EXPECT_EQ(trapezoidSeconds(0, 10, 5), 0.0);
}

// A KR 6 turns joint 1 by 90° and joint 6 by 10°: the joints move together, in joint 1's
// time. Its 360°/s reached in half a second (720°/s²) would take 180°: 90° is a triangle,
// 2·√(90/720) s. The table turning 90° at 90°/s and 90°/s² takes 1 s up and 1 s down.
TEST(Cycle, JointsAndTableMoveTogetherInTheSlowestAxisTime) {
  Cell cell;
  cell.robot = robotPreset("kuka-kr6-r700-sixx");
  EXPECT_NEAR(degrees(cell.robot.accelerations[0]), 720, 1e-9);
  cell.table = RotaryTable{};
  cell.table->speed = radians(90);
  cell.table->acceleration = radians(90);
  CellPose a, b;
  b.joints[0] = radians(90);
  b.joints[5] = radians(10);
  MoveSeconds move = moveSeconds(cell, a, b);
  EXPECT_NEAR(move.arm, 2 * std::sqrt(90.0 / 720), 1e-12);
  EXPECT_NEAR(move.arm, test::steppedMoveSeconds(radians(90), radians(360), radians(720)),
              1e-3 * move.arm);
  EXPECT_EQ(move.table, 0.0);
  b.table_angle = radians(90);
  move = moveSeconds(cell, a, b);
  EXPECT_NEAR(move.table, 2.0, 1e-12);
  EXPECT_NEAR(move.total(), 2.0, 1e-12);
}

// A program of three views: its cycle is each move's time, the table's where it is the
// longer, and at each view the acquisition (10 patterns of 0.05 s), the settling and the
// handshake; the parts add up to the whole, and a second run after it doubles each.
TEST(Cycle, PartsOfAProgramsCycleAddUpToItsTotal) {
  Cell cell;
  cell.robot = robotPreset("abb-irb2400-10");
  cell.table = RotaryTable{};
  RobotProgram program;
  program.cell = cell;
  program.home = CellPose{};
  for (int k = 1; k <= 3; ++k) {
    ProgramStep step;
    step.view = k;
    step.pose.joints[0] = radians(30.0 * k);
    step.pose.table_angle = k == 3 ? radians(180) : 0;  // the table's move is the longer
    program.steps.push_back(step);
  }
  const Scanner scanner;  // the generic head's figures
  CycleSettings settings;
  settings.settle = 0.25;
  settings.handshake = 0.5;
  const CycleTime cycle = programCycle(program, scanner, settings);
  EXPECT_EQ(cycle.model, "cell");
  EXPECT_EQ(cycle.views, 3u);
  EXPECT_NEAR(cycle.acquisition, 3 * 10 * 0.05, 1e-12);
  EXPECT_NEAR(cycle.other, 3 * (0.25 + 0.5), 1e-12);
  // Home -> 30° -> 60° -> 90° with the table half a turn -> home (joint 1 back 90°, the
  // table back half a turn): the arm's first two moves, the table's two half turns, each
  // longer than joint 1's 30° or 90° beside it.
  const double v = cell.robot.speeds[0], a = cell.robot.accelerations[0];
  const double arm = 2 * test::steppedMoveSeconds(radians(30), v, a);
  const double table =
      2 * test::steppedMoveSeconds(radians(180), cell.table->speed, cell.table->acceleration);
  EXPECT_NEAR(cycle.motion, arm, 1e-3 * arm);
  EXPECT_NEAR(cycle.table, table, 1e-3 * table);
  EXPECT_NEAR(cycle.total(), cycle.acquisition + cycle.motion + cycle.table + cycle.other, 1e-12);
  CycleTime twice = cycle;
  twice += cycle;
  EXPECT_EQ(twice.views, 6u);
  EXPECT_NEAR(twice.total(), 2 * cycle.total(), 1e-12);
}

// Without a cell: moves of 1000 mm and 50 mm at 250 mm/s and 500 mm/s², a laser line
// sweeping its 60 mm stroke at 100 mm/s at each of the three views.
TEST(Cycle, GenericPositioningAndALaserLinesSweep) {
  Scanner line;
  line.fov_height = 60;
  line.sweep_speed = 100;
  EXPECT_NEAR(line.acquisitionSeconds(), 0.6, 1e-12);
  const CycleSettings settings;  // 250 mm/s, 500 mm/s²
  const std::vector<double> moves = {1000, 50};
  const CycleTime cycle = genericCycle(moves, 3, line, settings);
  EXPECT_EQ(cycle.model, "generic");
  // 1000 mm: 0.5 s up (62.5 mm), 3.5 s at speed, 0.5 s down; 50 mm: a triangle, 2·√0.1 s.
  EXPECT_NEAR(cycle.motion, 4.5 + 2 * std::sqrt(0.1), 1e-12);
  EXPECT_NEAR(cycle.motion,
              test::steppedMoveSeconds(1000, 250, 500) + test::steppedMoveSeconds(50, 250, 500),
              1e-3 * cycle.motion);
  EXPECT_NEAR(cycle.acquisition, 1.8, 1e-12);
  EXPECT_EQ(cycle.table, 0.0);
}

// The curve of the first k views' cycle: k times the view's standing time (acquisition
// 10 × 0.05 s, settling 0.3 s, handshake 0.2 s) plus the path through them; a later run's
// curve continues from the first run's total, and a run without a curve leaves none.
TEST(Cycle, CurveByViewsAddsTheStandingTimeAndContinuesOverRuns) {
  const Scanner scanner;  // 10 patterns of 0.05 s
  const CycleSettings settings;
  EXPECT_NEAR(viewSeconds(scanner, settings), 1.0, 1e-12);
  const std::vector<double> path = {0, 2, 5};
  EXPECT_EQ(cycleByViews(path, scanner, settings), (std::vector<double>{1, 4, 8}));
  CycleTime first = genericCycle(std::vector<double>{1000, 50}, 3, scanner, settings);
  first.by_views = cycleByViews(path, scanner, settings);
  CycleTime second = genericCycle(std::vector<double>{}, 1, scanner, settings);
  second.by_views = {1.0};
  CycleTime run = first;
  run += second;
  EXPECT_NEAR(run.total(), first.total() + second.total(), 1e-12);
  ASSERT_EQ(run.by_views.size(), 4u);
  EXPECT_NEAR(run.by_views[3], first.total() + 1.0, 1e-12);
  second.by_views.clear();
  run = first;
  run += second;
  EXPECT_TRUE(run.by_views.empty());
}

// Settings out of range are refused, naming the key.
TEST(Cycle, SettingsOutOfRangeAreRefused) {
  CycleSettings settings;
  settings.settle = -1;
  EXPECT_PRED2(test::contains,
               test::inputError("spec.yaml", [&] { validate(settings, "spec.yaml"); }),
               "cycle.settle must lie within [0, 60] s");
  settings = CycleSettings{};
  settings.speed = 0;
  EXPECT_PRED2(test::contains,
               test::inputError("spec.yaml", [&] { validate(settings, "spec.yaml"); }),
               "cycle.speed");
  Scanner scanner;
  scanner.patterns = 2.5;
  EXPECT_PRED2(test::contains, test::inputError("s", [&] { validate(scanner, "s"); }),
               "patterns must be a whole number");
}

// The spec sets the cycle's figures: its cycle section, a robot's accelerations, a
// table's speed and acceleration, a scanner's acquisition; each out of range is refused.
TEST(Cycle, SpecSetsEveryFigureOfTheCycle) {
  test::TempDir dir;
  const std::string path = dir.file("spec.yaml");
  test::writeText(path,
                  "scanner: {preset: laser-line, sweep_speed: 50}\n"
                  "cycle: {settle: 1, handshake: 0, speed: 100, acceleration: 200, turn_over: 40}\n"
                  "cell:\n  robot: {preset: ur10e, accelerations: [10, 20, 30, 40, 50, 60]}\n"
                  "  table: {speed: 45, acceleration: 30}\n");
  const Spec spec = loadSpec(path);
  EXPECT_NEAR(spec.scanner.acquisitionSeconds(), 60.0 / 50, 1e-12);
  EXPECT_EQ(spec.cycle.settle, 1);
  EXPECT_EQ(spec.cycle.handshake, 0);
  EXPECT_EQ(spec.cycle.speed, 100);
  EXPECT_EQ(spec.cycle.acceleration, 200);
  EXPECT_EQ(spec.cycle.turn_over, 40);
  ASSERT_TRUE(spec.cell && spec.cell->table);
  EXPECT_NEAR(degrees(spec.cell->robot.accelerations[5]), 60, 1e-9);
  EXPECT_NEAR(degrees(spec.cell->table->speed), 45, 1e-9);
  EXPECT_NEAR(degrees(spec.cell->table->acceleration), 30, 1e-9);
  // A robot given by its parameters and speeds reaches each speed in half a second.
  test::writeText(path,
                  "cell:\n  robot: {a1: 100, a2: -135, b: 0, c1: 615, c2: 705, c3: 755, c4: 85,\n"
                  "    lower: [-180, -100, -60, -200, -120, -400], upper: [180, 110, 65, 200, 120, "
                  "400],\n    speeds: [90, 90, 90, 90, 90, 90]}\n");
  EXPECT_NEAR(degrees(loadSpec(path).cell->robot.accelerations[0]), 180, 1e-9);
  for (const auto& [text, reason] : std::vector<std::pair<std::string, std::string>>{
           {"cycle: {settle: -1}\n", "cycle.settle must lie within [0, 60] s"},
           {"cycle: {sped: 1}\n", "unknown key 'sped' in cycle"},
           {"cycle: {acceleration: 0}\n", "cycle.acceleration must lie within"},
           {"cycle: {turn_over: 4000}\n", "cycle.turn_over must lie within [0, 3600] s"},
           {"cell:\n  robot: {preset: ur10e, accelerations: [0, 1, 1, 1, 1, 1]}\n",
            "cell.robot.accelerations: joint 1 needs an acceleration within [1, 36000] °/s²"},
           {"cell:\n  robot: {preset: ur10e}\n  table: {speed: 0}\n",
            "cell.table.speed must lie within [1, 3600] °/s"},
           {"scanner: {preset: laser-line, sweep_speed: 0.5}\n", "sweep_speed must be 0"}}) {
    test::writeText(path, text);
    EXPECT_PRED2(test::contains, test::inputError(path, [&] { loadSpec(path); }), reason) << text;
  }
}

// NIST FTC 11 planned in both its rest orientations: the part is turned over by hand once
// between the two runs, and the cycle counts cycle.turn_over for it. With 45 s the plan is
// the same and its cycle 45 s longer, the second setup's views on the curve too; plan.json
// keeps the turn.
TEST(Cycle, TurningThePartOverBetweenSetupsCountsItsSeconds) {
  const Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  Spec spec = defaultSpec();
  spec.rest_all = true;
  const PlanningOptions alone{.registration = false};
  const Plan free = planViews(part, spec, alone);
  spec.cycle.turn_over = 45;
  const Plan turned = planViews(part, spec, alone);
  ASSERT_EQ(turned.orientations.size(), 2u);
  ASSERT_TRUE(free.cycle && turned.cycle);
  EXPECT_EQ(turned.views.size(), free.views.size());
  EXPECT_EQ(turned.cycle->turns, 1u);
  EXPECT_EQ(free.cycle->turning, 0);
  EXPECT_NEAR(turned.cycle->total(), free.cycle->total() + 45, 1e-9);
  const std::size_t first = turned.orientations[0].views.size();
  ASSERT_EQ(turned.cycle->by_views.size(), turned.views.size());
  for (std::size_t k = 0; k < turned.views.size(); ++k)
    EXPECT_NEAR(turned.cycle->by_views[k], free.cycle->by_views[k] + (k < first ? 0 : 45), 1e-9)
        << "view " << k + 1;
  test::TempDir dir;
  writePlan(turned, dir.file("plan.json"));
  const Plan read = readPlan(dir.file("plan.json"));
  ASSERT_TRUE(read.cycle);
  EXPECT_EQ(read.cycle->turns, 1u);
  EXPECT_NEAR(read.cycle->total(), turned.cycle->total(), 1e-9);
}

}  // namespace
}  // namespace scanplan
