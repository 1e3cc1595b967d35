// Robot programs against golden files, and each checked line by line against the grammar
// of the statements it uses (KUKA KRL, ABB RAPID, URScript) and read back: the joints and
// poses in the text are the program's.
//
// SCANPLAN_UPDATE_GOLDEN=1 rewrites the golden files from the current writers.

#include "support.h"

#include <scanplan/core/errors.h>
#include <scanplan/robot/program.h>

#include <nlohmann/json.hpp>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <optional>
#include <random>
#include <regex>
#include <set>
#include <sstream>

namespace scanplan {
namespace {

// Three views of an IRB 2400 on a rotary table; one view left out as unreachable.
RobotProgram program() {
  RobotProgram p;
  p.name = "ctc01_plan";
  p.source = "plan.json";
  p.cell.robot = robotPreset("abb-irb2400-10");
  p.cell.base.translation() = Vec3(-1000, 0, 0);
  p.cell.mount.translation() = Vec3(0, 0, 150);
  p.cell.table = RotaryTable{};
  // The part 1 m ahead of the robot (at the world's origin), turned 30° about z.
  p.work_object = Eigen::Translation3d(1000, 0, 0) * Eigen::AngleAxisd(radians(30), Vec3::UnitZ());
  const Joints joints[3] = {{0.1, 0.2, -0.3, 0.4, 0.5, 0.6},
                            {-0.2, 0.4, 0.1, -1.0, 0.8, 2.0},
                            {0.5, -0.1, 0.3, 0.2, -0.6, -1.5}};
  const double table[3] = {0, M_PI / 2, 0};
  const int views[3] = {4, 2, 7};
  const char* tasks[3] = {"gdt", "global", ""};
  for (int k = 0; k < 3; ++k)
    p.steps.push_back({views[k],
                       tasks[k],
                       CellPose{table[k], joints[k]},
                       forwardKinematics(p.cell.robot, joints[k]),
                       {},
                       {}});
  p.unreached = {9};
  // Safe motion as planMotion gives it: home, an approach, a via point.
  p.home = CellPose{0, {0, -0.3, 0.2, 0, 0.6, 0}};
  p.steps[0].approach = Joints{0.1, 0.1, -0.2, 0.4, 0.5, 0.6};
  p.steps[1].via = {CellPose{0.8, {-0.1, -0.2, 0.1, -0.5, 0.7, 1.0}}};
  p.cell.tool.mass = 3.2;
  p.cell.tool.centre = Vec3(0, 0, 90);
  p.load_inertia = Vec3(0.021, 0.034, 0.017);
  p.cell.signals.view = 9;
  p.cell.signals.trigger = 3;
  p.cell.signals.acknowledge = 4;
  return p;
}

// The program of another arm: its robot, and each step's flange for the same joints.
RobotProgram withRobot(RobotProgram p, const std::string& preset) {
  p.cell.robot = robotPreset(preset);
  for (ProgramStep& step : p.steps) step.flange = forwardKinematics(p.cell.robot, step.pose.joints);
  return p;
}

// Three views of a UR10e on a rotary table driven through its signals.
RobotProgram urProgram() {
  RobotProgram p;
  p.name = "ur_plan";
  p.source = "plan.json";
  p.cell.robot = robotPreset("ur10e");
  p.cell.mount.translation() = Vec3(0, 0, 120);
  p.cell.table = RotaryTable{};
  p.cell.signals.table = TableSignals{2, 5, 6};
  const Joints joints[3] = {{0.1, -1.2, 1.3, -1.6, -1.5, 0.6},
                            {-0.2, -1.4, 1.1, -1.0, -1.4, 2.0},
                            {0.5, -1.1, 1.4, -1.9, -1.6, -1.5}};
  const double table[3] = {0, 0, M_PI / 2};
  for (int k = 0; k < 3; ++k)
    p.steps.push_back({k + 1,
                       "global",
                       CellPose{table[k], joints[k]},
                       forwardKinematics(p.cell.robot, joints[k]),
                       {},
                       {}});
  p.home = CellPose{0, {0, -1.57, 1.2, -1.2, -1.57, 0}};
  p.steps[2].approach = Joints{0.5, -1.2, 1.3, -1.7, -1.6, -1.5};
  return p;
}

std::vector<std::string> lines(const std::string& text) {
  std::vector<std::string> result;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);) result.push_back(line);
  return result;
}

void expectGolden(const std::string& text, const std::string& name) {
  const std::string path = test::testData("golden/" + name);
  if (std::getenv("SCANPLAN_UPDATE_GOLDEN")) std::ofstream(path, std::ios::binary) << text;
  std::ifstream in(path, std::ios::binary);
  ASSERT_TRUE(in) << path;
  const std::string golden{std::istreambuf_iterator<char>(in), {}};
  EXPECT_EQ(text, golden) << name << " differs from its golden file";
}

std::vector<double> numbersIn(const std::string& text) {
  static const std::regex number(R"([-+]?\d+(\.\d+)?([eE][-+]?\d+)?)");
  std::vector<double> values;
  for (auto it = std::sregex_iterator(text.begin(), text.end(), number);
       it != std::sregex_iterator(); ++it)
    values.push_back(std::stod(it->str()));
  return values;
}

// Every robtarget of `p`'s RAPID program, in its work object wPart as the controller reads
// it (the object frame in the table's frame turned to the step's angle), is the step's
// flange on the scanner's mount.
void expectRobtargetsHoldTheFlange(const RobotProgram& p) {
  const auto pose = [](const double* n) {
    Pose result = Pose::Identity();
    result.translation() = Vec3(n[0], n[1], n[2]);
    result.linear() = Eigen::Quaterniond(n[3], n[4], n[5], n[6]).normalized().toRotationMatrix();
    return result;
  };
  std::optional<Pose> object;
  std::size_t k = 0;
  for (const std::string& line : lines(rapidProgram(p))) {
    if (line.find("PERS wobjdata wPart") != std::string::npos) {
      const std::vector<double> n = numbersIn(line.substr(line.find(":=")));
      ASSERT_GE(n.size(), 14u);  // ..., uframe, oframe: each [x,y,z],[q1,q2,q3,q4]
      object = pose(n.data() + n.size() - 7);
    }
    if (line.find("CONST robtarget") == std::string::npos) continue;
    ASSERT_TRUE(object) << "a robtarget before the work object";
    ASSERT_LT(k, p.steps.size());
    const ProgramStep& step = p.steps[k++];
    const Pose target = pose(numbersIn(line.substr(line.find(":="))).data());
    const Pose world = tableTurn(p.cell, step.pose.table_angle) * tableFrame(*p.cell.table) *
                       *object * target * p.cell.mount.inverse();
    EXPECT_TRUE((p.cell.base.inverse() * world).isApprox(step.flange, 1e-5)) << step.view;
  }
  EXPECT_EQ(k, p.steps.size());
}

// A KRL FRAME's pose from its numbers X, Y, Z (mm), A, B, C (degrees): turned by A about z,
// then B about the new y, then C about the newest x (KUKA's convention).
Pose krlPose(const double* n) {
  Pose pose = Pose::Identity();
  pose.translation() = Vec3(n[0], n[1], n[2]);
  pose.linear() = (Eigen::AngleAxisd(radians(n[3]), Vec3::UnitZ()) *
                   Eigen::AngleAxisd(radians(n[4]), Vec3::UnitY()) *
                   Eigen::AngleAxisd(radians(n[5]), Vec3::UnitX()))
                      .toRotationMatrix();
  return pose;
}

// Every view's scanner pose in `p`'s KRL program (the E6POS comment), in the base the
// controller makes of EK's offset (the table's frame turned to the E6POS's E1), is the step's
// flange on the scanner's mount.
void expectKrlScannerPosesHoldTheFlange(const RobotProgram& p) {
  std::optional<Pose> offset;
  std::size_t k = 0;
  for (const std::string& line : lines(krlProgram(p))) {
    if (line.find("$BASE = EK(MACHINE_DEF[2].ROOT, MACHINE_DEF[2].MECH_TYPE, {") == 2)
      offset = krlPose(numbersIn(line.substr(line.find('{'))).data());
    if (line.find("; scanner {E6POS:") == std::string::npos) continue;
    ASSERT_TRUE(offset) << "a scanner pose before the coupled base";
    ASSERT_LT(k, p.steps.size());
    const ProgramStep& step = p.steps[k++];
    const std::vector<double> n = numbersIn(line.substr(line.find("E6POS:") + 6));
    ASSERT_EQ(n.size(), 8u) << line;  // X, Y, Z, A, B, C, then E1's number and angle
    const Pose world = tableTurn(p.cell, radians(n[7])) * tableFrame(*p.cell.table) * *offset *
                       krlPose(n.data()) * p.cell.mount.inverse();
    EXPECT_TRUE((p.cell.base.inverse() * world).isApprox(step.flange, 1e-5)) << step.view;
  }
  EXPECT_EQ(k, p.steps.size());
}

TEST(RobotProgram, KrlFollowsItsGrammarAndHoldsTheJoints) {
  const RobotProgram p = withRobot(program(), "kuka-kr16-r1610-2");
  const std::string text = krlProgram(p);
  expectGolden(text, "program.src");
  // The statements the writer uses (KUKA System Software 8 programming manual).
  const std::string n = R"([-+]?\d+(\.\d+)?)";
  std::string axes;
  for (int j = 1; j <= 6; ++j) axes += "A" + std::to_string(j) + " " + n + ", ";
  const std::vector<std::regex> grammar = {
      std::regex(R"(&ACCESS RVP|&REL \d+)"),
      std::regex(R"(\s*;.*)"),
      std::regex(R"(DEF [A-Za-z_][A-Za-z0-9_]{0,23}\(\)|DEF SCAN\(VIEW:IN\))"),
      std::regex(R"(END|\s*INT VIEW|)"),
      std::regex(R"(\s*BAS\(#(INITMOV|VEL_PTP|ACC_PTP), \d+\))"),
      std::regex(
          R"(\s*\$(TOOL|BASE) = (EK\(MACHINE_DEF\[2\]\.ROOT, MACHINE_DEF\[2\]\.MECH_TYPE, )?)"
          R"(\{X )" +
          n + ", Y " + n + ", Z " + n + ", A " + n + ", B " + n + ", C " + n + R"(\}\)?)"),
      std::regex(R"(\s*\$LOAD\.M = )" + n),
      std::regex(R"(\s*\$LOAD\.CM = \{X )" + n + ", Y " + n + ", Z " + n + R"(, A 0, B 0, C 0\})"),
      std::regex(R"(\s*\$LOAD\.J = \{X )" + n + ", Y " + n + ", Z " + n + R"(\})"),
      std::regex(R"(\s*SIGNAL VIEW_NO \$OUT\[\d+\] TO \$OUT\[\d+\]|\s*VIEW_NO = VIEW)"),
      std::regex(R"(\s*PTP X[A-Z]+\d*)"),
      std::regex(R"(\s*SCAN\(\d+\))"),
      std::regex(R"(\s*WAIT SEC )" + n +
                 R"(|\s*WAIT FOR (NOT )?\$IN\[\d+\]( OR \$TIMER_FLAG\[1\])?)"
                 R"(|\s*\$OUT\[\d+\] = (TRUE|FALSE))"),
      std::regex(R"(\s*\$TIMER_STOP\[1\] = (TRUE|FALSE)|\s*\$TIMER\[1\] = -\d+)"),
      std::regex(R"(\s*IF (NOT )?\$IN\[\d+\] THEN|\s*ENDIF|\s*HALT( ;.*)?)"),
  };
  // The tool, the work object, the load and the handshake's signals are the cell's.
  EXPECT_NE(text.find("$TOOL = {X 0.000, Y 0.000, Z 150.000,"), std::string::npos);
  // The base turns with the table: coupled to it by EK, the part on the table's axis at the
  // world's origin, turned 30° about z. Without a table, it stands still in the robot's base
  // frame: the part 1 m ahead of it.
  EXPECT_NE(text.find("$BASE = EK(MACHINE_DEF[2].ROOT, MACHINE_DEF[2].MECH_TYPE, {X 0.000, Y "
                      "0.000, Z 0.000, A 30.0000, B 0.0000, C 0.0000})"),
            std::string::npos);
  RobotProgram fixed = p;
  fixed.cell.table.reset();
  EXPECT_NE(krlProgram(fixed).find(
                "  $BASE = {X 1000.000, Y 0.000, Z 0.000, A 30.0000, B 0.0000, C 0.0000}\n"),
            std::string::npos);
  EXPECT_NE(text.find("$LOAD.M = 3.200\n  $LOAD.CM = {X 0.000, Y 0.000, Z 90.000,"),
            std::string::npos);
  EXPECT_NE(text.find("$LOAD.J = {X 0.02100, Y 0.03400, Z 0.01700}"), std::string::npos);
  // The approach to a view and its retract run slowed, then the travel speed again.
  EXPECT_NE(text.find("  BAS(#VEL_PTP, 5)\n  PTP XVIEW4\n  SCAN(4)\n  ; retract view 4\n"
                      "  PTP XAPPROACH4\n  BAS(#VEL_PTP, 20)\n"),
            std::string::npos);
  EXPECT_NE(text.find("SIGNAL VIEW_NO $OUT[9] TO $OUT[24]"), std::string::npos);
  // The trigger reset at the start; each wait bounded by timer 1, the trigger dropped and the
  // program halted when the acknowledgement does not come.
  EXPECT_NE(text.find("A 30.0000, B 0.0000, C 0.0000})\n  $OUT[3] = FALSE\n"), std::string::npos);
  EXPECT_NE(text.find("  $OUT[3] = TRUE\n  $TIMER_STOP[1] = TRUE\n  $TIMER[1] = -10000\n"
                      "  $TIMER_STOP[1] = FALSE\n  WAIT FOR $IN[4] OR $TIMER_FLAG[1]\n"
                      "  $TIMER_STOP[1] = TRUE\n  IF NOT $IN[4] THEN\n    $OUT[3] = FALSE\n"
                      "    HALT ; no acknowledgement within 10 s\n  ENDIF\n  $OUT[3] = FALSE\n"),
            std::string::npos);
  EXPECT_NE(text.find("  WAIT FOR NOT $IN[4] OR $TIMER_FLAG[1]\n  $TIMER_STOP[1] = TRUE\n"
                      "  IF $IN[4] THEN\n    $OUT[3] = FALSE\n"),
            std::string::npos);
  // The points, named in the .dat: DEFDAT under the program's name, one E6AXIS each.
  const std::string data = krlData(p);
  expectGolden(data, "program.dat");
  const std::regex point(R"(  DECL E6AXIS (X[A-Z]+\d*)=\{)" + axes + "E1 " + n +
                         R"(, E2 0\.0, E3 0\.0, E4 0\.0, E5 0\.0, E6 0\.0\})");
  std::map<std::string, std::vector<double>> points;
  for (const std::string& line : lines(data)) {
    std::smatch named;
    if (std::regex_match(line, named, point)) {
      EXPECT_TRUE(points.emplace(named[1], numbersIn(line.substr(line.find('{')))).second) << line;
      continue;
    }
    EXPECT_TRUE(std::regex_match(line, std::regex(R"(&ACCESS RVP|&REL \d+|DEFDAT ctc01_plan|)"
                                                  R"(\s*;.*|ENDDAT)")))
        << "not a KRL .dat line the writer may use: " << line;
  }
  int defs = 0, ends = 0;
  std::vector<std::vector<double>> ptp;
  for (const std::string& line : lines(text)) {
    bool known = false;
    for (const std::regex& rule : grammar) known = known || std::regex_match(line, rule);
    EXPECT_TRUE(known) << "not a KRL statement the writer may use: " << line;
    defs += line.rfind("DEF ", 0) == 0;
    ends += line == "END";
    if (line.rfind("  PTP ", 0) == 0) {
      ASSERT_TRUE(points.count(line.substr(6))) << "not declared in the .dat: " << line;
      ptp.push_back(points.at(line.substr(6)));
    }
  }
  EXPECT_EQ(defs, 2);
  EXPECT_EQ(ends, 2);
  // Home, approach, view 4, retract, via, view 2, view 7, home.
  const std::vector<Waypoint> path = waypoints(p);
  ASSERT_EQ(path.size(), 8u);
  ASSERT_EQ(ptp.size(), path.size());
  for (std::size_t k = 0; k < ptp.size(); ++k) {
    ASSERT_EQ(ptp[k].size(), 24u);  // A1..A6 and E1..E6, each value after its axis number
    for (int j = 0; j < 6; ++j)
      EXPECT_NEAR(ptp[k][2 * j + 1], degrees(path[k].pose.joints[j]), 1e-4);
    EXPECT_NEAR(ptp[k][13], degrees(path[k].pose.table_angle), 1e-4);
  }
  // Each scanner pose is the scanner in the coupled base, the flange on its mount where the
  // controller puts it; also with the table off the world's origin and its axis tilted.
  expectKrlScannerPosesHoldTheFlange(p);
  RobotProgram moved = p;
  moved.cell.table->origin = Vec3(200, -150, 30);
  moved.cell.table->axis = Vec3(0, 0.1, 1).normalized();
  expectKrlScannerPosesHoldTheFlange(moved);
}

TEST(RobotProgram, RapidFollowsItsGrammarAndHoldsTheTargets) {
  const RobotProgram p = program();
  const std::string text = rapidProgram(p);
  expectGolden(text, "program.mod");
  int modules = 0, procs = 0, ifs = 0, moves = 0;
  std::vector<std::vector<double>> robtargets;
  for (const std::string& line : lines(text)) {
    const std::string code = line.substr(0, line.find('!'));
    if (code.find_first_not_of(' ') == std::string::npos) continue;  // comment or blank
    if (std::regex_match(code, std::regex(R"(MODULE [A-Za-z][A-Za-z0-9_]{0,31})"))) {
      ++modules;
    } else if (code == "ENDMODULE") {
      --modules;
    } else if (std::regex_match(code,
                                std::regex(R"(\s*PROC [A-Za-z][A-Za-z0-9_]*\((num [a-z]+)?\))"))) {
      ++procs;
    } else if (std::regex_match(code, std::regex(R"(\s*ENDPROC)"))) {
      --procs;
    } else if (std::regex_match(code, std::regex(R"(\s*IF [A-Za-z]+ THEN)"))) {
      ++ifs;
    } else if (std::regex_match(code, std::regex(R"(\s*ENDIF)"))) {
      --ifs;
    } else {
      // Every other statement ends with a semicolon (RAPID reference manual, Basic elements).
      EXPECT_EQ(code.back(), ';') << line;
      if (code.find("MoveAbsJ") != std::string::npos) {
        EXPECT_TRUE(
            std::regex_match(
                code,
                std::regex(R"(\s*MoveAbsJ j(View|Approach)\d+, v\d+, (fine|z10), tScanner;)")) ||
            std::regex_match(code,
                             std::regex(R"(\s*MoveAbsJ \[\[([-0-9.]+,){5}[-0-9.]+\],)"
                                        R"(\[[-0-9.E+]+(,9E\+09){5}\]\], v\d+, z\d+, tScanner;)")))
            << line;
        ++moves;
      }
      if (code.find("CONST robtarget") != std::string::npos) {
        // [trans, rot, robconf, extax] (RAPID reference manual, robtarget).
        EXPECT_TRUE(std::regex_match(
            code, std::regex(R"(\s*CONST robtarget pView\d+ := \[\[([-0-9.]+,){2}[-0-9.]+\],)"
                             R"(\[([-0-9.]+,){3}[-0-9.]+\],\[(-?\d,){3}[0-7]\],)"
                             R"(\[[-0-9.E+]+(,9E\+09){5}\]\];)")))
            << line;
        robtargets.push_back(numbersIn(code.substr(code.find(":="))));
      }
      if (code.find("CONST jointtarget") != std::string::npos) {
        EXPECT_TRUE(std::regex_match(
            code,
            std::regex(
                R"(\s*CONST jointtarget j(View|Approach)\d+ := \[\[([-0-9.]+,){5}[-0-9.]+\],\[[-0-9.E+]+(,9E\+09){5}\]\];)")))
            << line;
      }
    }
  }
  EXPECT_EQ(modules, 0);
  EXPECT_EQ(procs, 0);
  EXPECT_EQ(ifs, 0);
  EXPECT_EQ(moves, 8);
  EXPECT_NE(text.find("PERS tooldata tScanner := [TRUE,[[0.000,0.000,150.000],[1.000000,0.000000,"
                      "0.000000,0.000000]],[3.200,[0.000,0.000,90.000],[1,0,0,0],0.02100,0.03400,"
                      "0.01700]];"),
            std::string::npos);
  // The work object moves with the table (coordinated with its mechanical unit): the user
  // frame is the table's, the object frame the part in it, turned 30° about z on the
  // table's axis at the world's origin (cos 15°, sin 15°: the quaternion of 30° about z).
  EXPECT_NE(text.find("PERS wobjdata wPart := [FALSE,FALSE,\"STN_1\",[[0,0,0],[1,0,0,0]],"
                      "[[0.000,0.000,0.000],[0.965926,0.000000,0.000000,0.258819]]];"),
            std::string::npos);
  // Without a table, it stands still in the robot's base frame: the part 1 m ahead of it.
  RobotProgram fixed = p;
  fixed.cell.table.reset();
  EXPECT_NE(rapidProgram(fixed).find(
                "PERS wobjdata wPart := [FALSE,TRUE,\"\",[[1000.000,0.000,0.000],[0.965926,"
                "0.000000,0.000000,0.258819]],[[0,0,0],[1,0,0,0]]];"),
            std::string::npos);
  // The trigger reset at the start; each wait bounded (WaitDI \MaxTime with its \TimeFlag),
  // a timeout dropping the trigger, logged and stopping the program.
  EXPECT_NE(text.find("  PROC main()\n    SetDO DO_3, 0;\n"), std::string::npos);
  EXPECT_NE(
      text.find("SetGO GO_9, view;\n    SetDO DO_3, 1;\n"
                "    WaitDI DI_4, 1 \\MaxTime:=10 \\TimeFlag:=bTimeout;\n"
                "    IF bTimeout THEN\n      SetDO DO_3, 0;\n"
                "      ErrWrite \"scanplan: no acknowledgement\", \"view \" + NumToStr(view, 0);\n"
                "      Stop;\n    ENDIF\n    SetDO DO_3, 0;\n"
                "    WaitDI DI_4, 0 \\MaxTime:=10 \\TimeFlag:=bTimeout;\n"),
      std::string::npos);
  // Each robtarget is the scanner in the work object, the flange on its mount where the
  // controller puts it; also with the table off the world's origin and its axis tilted.
  ASSERT_EQ(robtargets.size(), p.steps.size());
  for (std::size_t k = 0; k < robtargets.size(); ++k)
    EXPECT_EQ(robtargets[k][10], rapidCfx(p.cell.robot, p.steps[k].pose.joints)) << k;  // cfx
  expectRobtargetsHoldTheFlange(p);
  RobotProgram moved = p;
  moved.cell.table->origin = Vec3(200, -150, 30);
  moved.cell.table->axis = Vec3(0, 0.1, 1).normalized();
  expectRobtargetsHoldTheFlange(moved);
}

// ABB's cfx tells apart the configurations of one flange pose: the 8 inverse-kinematics
// solutions (shoulder in front of or behind axis 1, elbow up or down, wrist flipped or
// not) of an IRB 2400 take the 8 values 0 to 7, on 200 random poses that have all 8; and
// the arm leaning forward, elbow up, wrist positive is 0.
TEST(RobotProgram, RapidCfxTellsTheEightSolutionsOfAPoseApart) {
  const RobotModel robot = robotPreset("abb-irb2400-10");
  EXPECT_EQ(rapidCfx(robot, {0, radians(20), radians(-10), 0, radians(30), 0}), 0);
  EXPECT_EQ(rapidCfx(robot, {0, radians(20), radians(-10), 0, radians(-30), 0}), 1);
  RobotModel unlimited = robot;
  unlimited.lower.fill(-2 * M_PI);
  unlimited.upper.fill(2 * M_PI);
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> angle(-M_PI / 2, M_PI / 2);
  int poses = 0;
  while (poses < 200) {
    Joints q;
    for (double& a : q) a = angle(random);
    const std::vector<Joints> solutions = inverseKinematics(unlimited, forwardKinematics(robot, q));
    if (solutions.size() != 8) continue;
    std::set<int> values;
    for (const Joints& s : solutions) values.insert(rapidCfx(robot, s));
    EXPECT_EQ(values.size(), 8u) << "pose " << poses;
    ++poses;
  }
}

// FANUC's LS: the sections in order, every /MN line numbered and one of the instructions
// the writer uses (FANUC's teach-pendant instructions), the positions of /POS read back as
// the path's joints (J3 as FANUC counts it, E1 the table), the handshake bounded by
// $WAITTMOUT and its error exits, FANUC's signals numbered from 1.
TEST(RobotProgram, FanucFollowsItsGrammarAndHoldsTheJoints) {
  const RobotProgram p = withRobot(program(), "fanuc-m20id-25");
  const std::string text = fanucProgram(p);
  expectGolden(text, "program.ls");
  const std::vector<std::string> all = lines(text);
  ASSERT_GE(all.size(), 3u);
  EXPECT_EQ(all.front(), "/PROG  CTC01_PLAN");
  EXPECT_EQ(all.back(), "/END");
  const std::string n = R"(-?\d+)";
  const std::regex numbered(R"(\s*(\d+):(J P\[(\d+):([A-Z0-9]+)\] \d+% FINE|  (.*)) ;)");
  const std::vector<std::regex> instructions = {
      std::regex(R"(!.{1,32})"),
      std::regex(R"((UFRAME_NUM|UTOOL_NUM)=1|PAYLOAD\[1\])"),
      std::regex(R"((DO|GO)\[\d+\]=(ON|OFF|\d+))"),
      std::regex(R"(WAIT \.20\(sec\)|\$WAITTMOUT=\d+)"),
      std::regex(R"(WAIT DI\[\d+\]=(ON|OFF) TIMEOUT,LBL\[\d+\])"),
      std::regex(R"(JMP LBL\[\d+\]|LBL\[\d+\]|MESSAGE\[[A-Z ]+\]|ABORT)")};
  std::size_t at = 0;
  while (at < all.size() && all[at] != "/MN") ++at;
  std::vector<int> moved;  // the position numbers moved to, in order
  int number = 0;
  for (++at; at < all.size() && all[at] != "/POS"; ++at) {
    std::smatch m;
    ASSERT_TRUE(std::regex_match(all[at], m, numbered)) << all[at];
    EXPECT_EQ(std::stoi(m[1]), ++number);
    if (m[3].matched) {
      moved.push_back(std::stoi(m[3]));
      continue;
    }
    const std::string body = m[5];
    bool known = false;
    for (const std::regex& rule : instructions) known = known || std::regex_match(body, rule);
    EXPECT_TRUE(known) << "not an instruction the writer uses: " << all[at];
  }
  EXPECT_NE(text.find("LINE_COUNT\t= " + std::to_string(number) + ";"), std::string::npos);
  // Each position: GP1, its frames, J1 to J6 and E1 in degrees.
  const std::regex position(R"(P\[(\d+):"[A-Z0-9]+"\]\{)");
  std::map<int, std::vector<double>> positions;
  for (++at; at < all.size() && all[at] != "/END"; ++at) {
    std::smatch m;
    ASSERT_TRUE(std::regex_match(all[at], m, position)) << all[at];
    ASSERT_LT(at + 6, all.size());
    EXPECT_EQ(all[at + 1], "   GP1:");
    EXPECT_EQ(all[at + 2], "\tUF : 1, UT : 1,\t");
    const std::string joints = all[at + 3] + all[at + 4] + all[at + 5];
    EXPECT_TRUE(std::regex_match(
        joints, std::regex(R"((\tJ\d= +[-0-9.]+ deg,)+\tJ6= +[-0-9.]+ deg,\tE1= +[-0-9.]+ deg)")))
        << joints;
    std::vector<double> values;
    for (double v : numbersIn(joints)) values.push_back(v);
    positions[std::stoi(m[1])] = values;
    EXPECT_EQ(all[at + 6], "};");
    at += 6;
  }
  const std::vector<Waypoint> path = waypoints(p);
  ASSERT_EQ(moved.size(), path.size());
  for (std::size_t k = 0; k < path.size(); ++k) {
    const std::vector<double>& v = positions.at(moved[k]);
    ASSERT_EQ(v.size(), 14u);  // J1..J6, E1, each after its number
    for (int j = 0; j < 6; ++j) EXPECT_NEAR(v[2 * j + 1], degrees(path[k].pose.joints[j]), 1e-3);
    EXPECT_NEAR(v[13], degrees(path[k].pose.table_angle), 1e-3);
  }
  // The handshake: the trigger dropped at the start, each wait bounded, a timeout dropping
  // the trigger and aborting.
  EXPECT_NE(text.find("  DO[3]=OFF ;\n"), std::string::npos);
  EXPECT_NE(text.find("  GO[9]=4 ;\n"), std::string::npos);
  EXPECT_NE(text.find("  $WAITTMOUT=1000 ;\n"), std::string::npos);
  EXPECT_NE(text.find("  WAIT DI[4]=ON TIMEOUT,LBL[90] ;\n"), std::string::npos);
  EXPECT_NE(text.find("  LBL[90] ;\n"), std::string::npos);
  // FANUC numbers its signals from 1.
  RobotProgram zero = p;
  zero.cell.signals.acknowledge = 0;
  EXPECT_THROW(fanucProgram(zero), UsageError);
}

// A URScript pose from its numbers x, y, z (m) and a rotation vector (radians), in mm.
Pose urPoseOf(const double* n) {
  Pose pose = Pose::Identity();
  pose.translation() = 1000 * Vec3(n[0], n[1], n[2]);
  const Vec3 r(n[3], n[4], n[5]);
  if (r.norm() > 0) pose.linear() = Eigen::AngleAxisd(r.norm(), r.normalized()).toRotationMatrix();
  return pose;
}

// Every view's scanner pose in `p`'s URScript, pose_trans(part_frame, ...) as the controller
// composes it with part_frame as last set (the table's frame, turned about its z, on the
// part on it), is the step's flange on the scanner's mount.
void expectUrScannerPosesHoldTheFlange(const RobotProgram& p) {
  std::map<std::string, Pose> frames;
  std::optional<Pose> part;
  std::size_t k = 0;
  const std::regex given(R"(  (table_frame|part_on_table) = p\[(.*)\])");
  const std::regex turned(
      R"(  part_frame = pose_trans\(table_frame, pose_trans\(p\[0, 0, 0, 0, 0, ([-0-9.]+)\], )"
      R"(part_on_table\)\))");
  for (const std::string& line : lines(urScript(p))) {
    std::smatch m;
    if (std::regex_match(line, m, given)) frames[m[1]] = urPoseOf(numbersIn(m[2]).data());
    if (std::regex_match(line, m, turned)) {
      ASSERT_EQ(frames.size(), 2u) << "part_frame set before its frames";
      part = frames["table_frame"] * Eigen::AngleAxisd(std::stod(m[1]), Vec3::UnitZ()) *
             frames["part_on_table"];
    }
    if (line.find("scanner pose_trans(part_frame, p[") == std::string::npos) continue;
    ASSERT_TRUE(part) << "a scanner pose before part_frame";
    ASSERT_LT(k, p.steps.size());
    const ProgramStep& step = p.steps[k++];
    const Pose scanner = urPoseOf(numbersIn(line.substr(line.find("p["))).data());
    EXPECT_TRUE((*part * scanner * p.cell.mount.inverse()).isApprox(step.flange, 1e-5))
        << step.view;
  }
  EXPECT_EQ(k, p.steps.size());
}

TEST(RobotProgram, UrScriptFollowsItsGrammarAndHoldsTheJoints) {
  const RobotProgram p = urProgram();
  const std::string text = urScript(p);
  expectGolden(text, "program.script");
  const std::vector<Waypoint> path = waypoints(p);  // home, 3 views, approach, retract, home
  int depth = 0, moves = 0, turns = 0;
  for (const std::string& line : lines(text)) {
    const std::string code = line.substr(0, line.find('#'));
    if (code.find_first_not_of(' ') == std::string::npos) continue;
    // Blocks open with a line ending in ':' (def, while) and close with 'end' (URScript
    // manual, The URScript programming language).
    if (code.back() == ':') {
      EXPECT_TRUE(std::regex_match(
          code,
          std::regex(R"(\s*(def [a-z_][a-z0-9_]*\(([a-z_]+(, [a-z_]+)*)?\)|(while|if) .+):)")))
          << line;
      ++depth;
    } else if (std::regex_match(code, std::regex(R"(\s*end)"))) {
      --depth;
      EXPECT_GE(depth, 0) << line;
    } else if (code.find("movej") != std::string::npos) {
      const std::vector<double> v = numbersIn(code);
      ASSERT_EQ(v.size(), 8u) << line;  // the 6 joints (radians), a and v
      ASSERT_LT(static_cast<std::size_t>(moves), path.size());
      for (std::size_t j = 0; j < 6; ++j)
        EXPECT_NEAR(v[j], path[static_cast<std::size_t>(moves)].pose.joints[j], 1e-6);
      ++moves;
    } else {
      turns += code.find("turn_table(") != std::string::npos;
      EXPECT_TRUE(std::regex_match(
          code,
          std::regex(
              R"(\s*(scan\(\d+\)|turn_table\([-0-9.]+\)|sleep\([0-9.]+\)|sync\(\)|)"
              R"(set_standard_digital_out\(\d, (True|False)\)|set_tcp\(p\[([-0-9.]+, ){5}[-0-9.]+\]\)|)"
              R"(set_target_payload\([0-9.]+, \[([-0-9.]+, ){2}[-0-9.]+\], \[([0-9.]+, ){5}[0-9.]+\]\)|)"
              R"((part_frame|table_frame|part_on_table) = p\[([-0-9.]+, ){5}[-0-9.]+\]|)"
              R"(part_frame = pose_trans\(table_frame, pose_trans\(p\[0, 0, 0, 0, 0, [-0-9.]+\], )"
              R"(part_on_table\)\)|)"
              R"(write_output_(integer|float)_register\(\d+, (view|angle)\)|)"
              R"(await_input\(\d+, (True|False), \d, "scanplan: [a-z ]+"\)|)"
              R"(waited = 0\.0|waited = waited \+ 0\.01|halt\(\)|)"
              R"(set_standard_digital_out\(request, False\)|popup\(what, "scanplan", error=True\)))")))
          << line;
    }
  }
  EXPECT_EQ(depth, 0);
  EXPECT_EQ(moves, 7);
  EXPECT_EQ(turns, 3);  // to 0 at home, to 90° to approach the third view, to 0 back home
  EXPECT_NE(text.find("set_tcp(p[0.000000, 0.000000, 0.120000, 0.000000, 0.000000, 0.000000])"),
            std::string::npos);
  // Outputs reset at the start; each wait bounded, ended on a timeout by an error and a halt.
  EXPECT_NE(
      text.find("  set_standard_digital_out(1, False)\n  set_standard_digital_out(5, False)\n"),
      std::string::npos);
  EXPECT_NE(text.find("    while get_standard_digital_in(n) != state:\n      sleep(0.01)\n"
                      "      waited = waited + 0.01\n      if waited > 10:\n"
                      "        set_standard_digital_out(request, False)\n"),
            std::string::npos);
  EXPECT_NE(
      text.find("write_output_float_register(2, angle)\n    set_standard_digital_out(5, True)\n"
                "    await_input(6, True, 5, \"scanplan: no table ready\")\n"),
      std::string::npos);
  // The part's frame turns with the table: each scanner pose in it is the flange on its
  // mount; also with the part placed off the table's axis, the table off the origin and its
  // axis tilted, and the robot's base moved. Without a table, part_frame stands still.
  expectUrScannerPosesHoldTheFlange(p);
  RobotProgram moved = p;
  moved.work_object = Eigen::Translation3d(900, 100, -50) * Eigen::AngleAxisd(0.4, Vec3::UnitZ());
  moved.cell.base.translation() = Vec3(-1000, 0, 0);
  moved.cell.table->origin = Vec3(200, -150, 30);
  moved.cell.table->axis = Vec3(0, 0.1, 1).normalized();
  expectUrScannerPosesHoldTheFlange(moved);
  RobotProgram fixed = p;
  fixed.cell.table.reset();
  fixed.cell.signals.table.reset();
  fixed.work_object.translation() = Vec3(700, 0, 0);
  EXPECT_NE(urScript(fixed).find("  part_frame = p[0.700000, 0.000000, 0.000000, 0.000000, "
                                 "0.000000, 0.000000]\n"),
            std::string::npos);
}

// Each format runs on its robots only, and URScript drives a table only through its
// signals: anything else is refused naming the format.
// Every wait on an input lasts the signals' timeout, 2.5 s here, in each controller's unit:
// KRL's timer in milliseconds, RAPID's \MaxTime in seconds, FANUC's $WAITTMOUT in
// hundredths of a second, URScript's count of seconds waited.
TEST(RobotProgram, EveryControllerWaitsTheSignalsTimeoutForItsInputs) {
  const auto count = [](const std::string& text, const std::string& what) {
    std::size_t n = 0;
    for (std::size_t at = text.find(what); at != std::string::npos; at = text.find(what, at + 1))
      ++n;
    return n;
  };
  RobotProgram p = program();
  p.cell.signals.timeout = 2.5;
  const std::string krl = krlProgram(withRobot(p, "kuka-kr16-r1610-2"));
  EXPECT_EQ(count(krl, "$TIMER[1] = -2500\n"), 2u);  // the acknowledgement, then its end
  EXPECT_EQ(count(krl, "within 2.5 s\n"), 2u);
  EXPECT_EQ(count(krl, "-10000"), 0u);
  const std::string rapid = rapidProgram(p);
  EXPECT_EQ(count(rapid, "\\MaxTime:=2.5 \\TimeFlag:=bTimeout;"), 2u);
  EXPECT_EQ(count(rapid, "MaxTime:=10"), 0u);
  const std::string fanuc = fanucProgram(withRobot(p, "fanuc-m20id-25"));
  EXPECT_EQ(count(fanuc, "$WAITTMOUT=250 ;"), p.steps.size());  // at each view
  EXPECT_EQ(count(fanuc, "$WAITTMOUT=1000"), 0u);
  RobotProgram ur = urProgram();
  ur.cell.signals.timeout = 2.5;
  const std::string script = urScript(ur);
  EXPECT_EQ(count(script, "      if waited > 2.5:\n"), 1u);  // the one wait every input takes
  EXPECT_EQ(count(script, "waited > 10"), 0u);
}

TEST(RobotProgram, AFormatTheCellCannotRunIsRefused) {
  auto refusal = [](const std::function<void()>& write) {
    try {
      write();
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  // Each language for its maker's arms.
  EXPECT_EQ(refusal([] { urScript(program()); }),
            "--format urscript: abb-irb2400-10 is not one of Universal Robots's arms, and urscript "
            "runs on their controllers only: its maker's format is --format rapid");
  EXPECT_EQ(refusal([] { krlProgram(urProgram()); }),
            "--format krl: ur10e is not one of KUKA's arms, and krl runs on their controllers "
            "only: its maker's format is --format urscript");
  EXPECT_EQ(refusal([] { krlProgram(program()); }),
            "--format krl: abb-irb2400-10 is not one of KUKA's arms, and krl runs on their "
            "controllers only: its maker's format is --format rapid");
  EXPECT_EQ(refusal([] { rapidProgram(withRobot(program(), "fanuc-m20id-25")); }),
            "--format rapid: fanuc-m20id-25 is not one of ABB's arms, and rapid runs on their "
            "controllers only: its maker's format is --format fanuc");
  EXPECT_EQ(refusal([] { fanucProgram(withRobot(program(), "kuka-kr16-r1610-2")); }),
            "--format fanuc: kuka-kr16-r1610-2 is not one of FANUC's arms, and fanuc runs on "
            "their controllers only: its maker's format is --format krl");
  // An arm given by its parameters runs any ortho-parallel language.
  RobotProgram custom = program();
  custom.cell.robot.maker.clear();
  EXPECT_EQ(refusal([&] { krlProgram(custom); }), "accepted");
  EXPECT_EQ(refusal([&] { fanucProgram(custom); }), "accepted");
  RobotProgram undriven = urProgram();
  undriven.cell.signals.table.reset();
  EXPECT_EQ(refusal([&] { urScript(undriven); }),
            "--format urscript: URScript cannot drive the rotary table without its signals: give "
            "cell.signals.table {angle, move, ready} in the spec");
}

// A program with a move that collides and could not be cleared is not written unless the
// user allows it; then its header marks every such move.
TEST(RobotProgram, AProgramWithAMoveThatCollidesIsRefusedUnlessAllowed) {
  RobotProgram p = withRobot(program(), "kuka-kr16-r1610-2");
  EXPECT_NO_THROW(checkClearMoves(p, false, "out/cell.src"));
  p.uncleared = {{4, 2}, {7, 0}};
  try {
    checkClearMoves(p, false, "out/cell.src");
    ADD_FAILURE() << "a colliding program was accepted";
  } catch (const UsageError& e) {
    EXPECT_EQ(e.exitCode(), kExitUsage);
    EXPECT_EQ(std::string(e.what()),
              "out/cell.src: the move view 4 -> view 2 and 1 more collide and could not be "
              "cleared: no program written (give --allow-collisions to write it with the moves "
              "marked)");
  }
  EXPECT_NO_THROW(checkClearMoves(p, true, "out/cell.src"));
  const std::string text = krlProgram(p);
  EXPECT_NE(text.find("; WARNING: the move view 4 -> view 2 collides and could not be cleared\n"),
            std::string::npos);
  EXPECT_NE(text.find("; WARNING: the move view 7 -> home collides and could not be cleared\n"),
            std::string::npos);
}

// KRL runs a program only under its file's name: the DEF's name is the file's stem, and a
// stem that is no KRL name (a hyphen, a leading digit, over 24 characters) is refused.
TEST(RobotProgram, KrlIsNamedAsItsFileOrRefused) {
  test::TempDir dir;
  RobotProgram p = withRobot(program(), "kuka-kr16-r1610-2");
  p.name = "bracket_kr6";
  writeRobotProgram(p, "krl", dir.file("bracket_kr6.src"));
  std::ifstream in(dir.file("bracket_kr6.src"));
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  EXPECT_NE(text.find("\nDEF bracket_kr6()\n"), std::string::npos);
  for (const std::string& stem :
       std::vector<std::string>{"bracket-kr6", "6bracket", std::string(25, 'a')}) {
    p.name = robotProgram(p.cell, p.work_object, p.steps, {}, stem, "").name;
    const std::string path = dir.file(stem + ".src");
    try {
      writeRobotProgram(p, "krl", path);
      ADD_FAILURE() << stem << " was accepted";
    } catch (const UsageError& e) {
      EXPECT_EQ(std::string(e.what()).rfind(path + ": KRL runs a program under its file's name", 0),
                0u)
          << e.what();
    }
    EXPECT_FALSE(std::filesystem::exists(path));
  }
}

// A format none of the controllers runs is refused, not written as another: robot-json (the
// command's name for the program as JSON) and a misspelling alike.
TEST(RobotProgram, AFormatNoControllerRunsIsRefusedAndNothingWritten) {
  test::TempDir dir;
  const RobotProgram p = withRobot(program(), "abb-irb4600-60-205");
  for (const std::string format : {"robot-json", "RAPID", "gcode", ""}) {
    const std::string path = dir.file("scan.mod");
    try {
      writeRobotProgram(p, format, path);
      ADD_FAILURE() << "'" << format << "' was accepted";
    } catch (const UsageError& e) {
      EXPECT_EQ(std::string(e.what()),
                "format: '" + format + "': expected krl, rapid, fanuc, urscript or json");
    }
    EXPECT_FALSE(std::filesystem::exists(path)) << format;
  }
  writeRobotProgram(p, "rapid", dir.file("scan.mod"));
  EXPECT_TRUE(std::filesystem::exists(dir.file("scan.mod")));
}

// KRL numbers its inputs and outputs from 1; the view number's 16 outputs from
// cell.signals.view must not hold the trigger. Both refused naming the signal.
TEST(RobotProgram, KrlSignalsStartAtOneAndTheTriggerLiesOutsideTheViewNumber) {
  RobotProgram p = withRobot(program(), "kuka-kr16-r1610-2");
  p.cell.signals = CellSignals{};  // the defaults: view 2 to 17, trigger 1
  EXPECT_NE(krlProgram(p).find("SIGNAL VIEW_NO $OUT[2] TO $OUT[17]"), std::string::npos);
  const auto refusal = [&](int view, int trigger, int acknowledge) {
    p.cell.signals = CellSignals{view, trigger, acknowledge, std::nullopt};
    try {
      krlProgram(p);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  EXPECT_EQ(refusal(1, 1, 1),
            "cell.signals.trigger: output 1 lies within the view number's outputs $OUT[1] to "
            "$OUT[16]: give the trigger an output of its own");
  EXPECT_EQ(refusal(9, 24, 1).substr(0, 29), "cell.signals.trigger: output ");
  EXPECT_EQ(refusal(9, 25, 1), "accepted");
  EXPECT_EQ(refusal(9, 8, 1), "accepted");
  EXPECT_EQ(refusal(0, 20, 1),
            "cell.signals.view: KRL numbers its inputs and outputs from 1, and 0 is none of them");
  EXPECT_EQ(refusal(2, 1, 0),
            "cell.signals.acknowledge: KRL numbers its inputs and outputs from 1, and 0 is none of "
            "them");
}

// URScript's standard digital signals run 0 to 7 and its output registers 0 to 47; the
// table's move output is not the scan's trigger. Each refused naming the signal.
TEST(RobotProgram, UrScriptSignalsLieWithinTheControllersRanges) {
  RobotProgram p = urProgram();
  const auto refusal = [&](const CellSignals& signals) {
    p.cell.signals = signals;
    try {
      urScript(p);
    } catch (const UsageError& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const TableSignals table{47, 7, 0};
  EXPECT_EQ(refusal({47, 0, 7, table}), "accepted");
  EXPECT_EQ(refusal({48, 0, 7, table}),
            "cell.signals.view: URScript numbers its output registers 0 to 47, and 48 is none of "
            "them");
  EXPECT_EQ(refusal({2, 9, 1, table}),
            "cell.signals.trigger: URScript numbers its standard digital inputs and outputs 0 to "
            "7, and 9 is none of them");
  EXPECT_EQ(refusal({2, 1, -1, table}).substr(0, 26), "cell.signals.acknowledge: ");
  EXPECT_EQ(refusal({2, 1, 1, TableSignals{100, 5, 6}}).substr(0, 26),
            "cell.signals.table.angle: ");
  EXPECT_EQ(refusal({2, 5, 1, TableSignals{2, 5, 6}}),
            "cell.signals.table.move: output 5 is the scan's trigger: give the table an output "
            "of its own");
}

// A plan's path and a robot's name come from the user's files: a line break in them would
// end the comment and leave the rest as a statement. Each stays inside its comment line.
TEST(RobotProgram, TextFromTheInputsCannotBecomeAStatement) {
  const std::string evil = "\nDEF EVIL()\r\nMoveAbsJ home;\n\x1b[2J";
  RobotProgram krl = withRobot(program(), "kuka-kr16-r1610-2"), rapid = program(), ur = urProgram();
  for (RobotProgram* p : {&krl, &rapid, &ur}) {
    p->source = "plans/x" + evil + ".json";
    p->cell.robot.name += evil;
  }
  for (const auto& [text, comment] :
       {std::pair{krlProgram(krl), ";"}, {rapidProgram(rapid), "!"}, {urScript(ur), "#"}}) {
    for (const std::string& line : lines(text)) {
      EXPECT_EQ(line.find('\r'), std::string::npos);
      EXPECT_EQ(line.find('\x1b'), std::string::npos);
      if (line.find("EVIL") == std::string::npos && line.find("MoveAbsJ home") == std::string::npos)
        continue;
      const std::size_t start = line.find_first_not_of(' ');
      EXPECT_EQ(line.compare(start, 2, std::string(comment) + " "), 0)
          << "outside a comment: " << line;
    }
    EXPECT_NE(text.find(" from plans/x?DEF EVIL()??MoveAbsJ home;??[2J.json\n"), std::string::npos)
        << text;
  }
}

TEST(RobotProgram, JsonHoldsJointsAndFlangePoses) {
  const RobotProgram p = program();
  const std::string text = programJson(p);
  expectGolden(text, "program.json");
  const nlohmann::json root = nlohmann::json::parse(text);
  EXPECT_EQ(root["format"], "scanplan.robot_program");
  ASSERT_EQ(root["steps"].size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    const nlohmann::json& step = root["steps"][k];
    EXPECT_EQ(step["view"], p.steps[k].view);
    Joints q{};
    for (int j = 0; j < 6; ++j) q[j] = radians(step["joints"][j].get<double>());
    Eigen::Matrix4d flange;
    for (int r = 0; r < 4; ++r)
      for (int c = 0; c < 4; ++c) flange(r, c) = step["flange"][r][c];
    EXPECT_TRUE(forwardKinematics(p.cell.robot, q).matrix().isApprox(flange, 1e-12));
  }
  EXPECT_EQ(root["unreached"], nlohmann::json({9}));
}

}  // namespace
}  // namespace scanplan
