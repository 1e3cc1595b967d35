// Robot programs from a list of steps. Each moves in joint space to every view (the joints the plan
// chose, so the robot takes the configuration the plan checked), waits there and triggers
// the scanner, in sequence order. The scanner poses are given too, in the part's frame (the
// work object), for the integrator.

#include "robot/program_text.h"

#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/robot/program.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <array>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <map>
#include <set>
#include <sstream>
#include <tuple>
#include <vector>

namespace scanplan {
namespace {

using detail::commentText;
using detail::header;
using detail::loadCentre;

std::string identifier(const std::string& name, std::size_t length) {
  std::string id;
  for (char c : name) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (id.empty() || !std::isalpha(static_cast<unsigned char>(id.front()))) id = "p_" + id;
  return id.substr(0, length);
}

// A KRL FRAME: {X, Y, Z, A, B, C}, mm and degrees.
std::string krlFrame(const Pose& pose) {
  const Vec3 xyz = pose.translation(), abc = zyxAngles(pose.linear());
  return fmt::format("{{X {:.3f}, Y {:.3f}, Z {:.3f}, A {:.4f}, B {:.4f}, C {:.4f}}}", xyz.x(),
                     xyz.y(), xyz.z(), abc.x(), abc.y(), abc.z());
}

// The quaternion with a non-negative scalar part (the same rotation), as ABB writes them.
Eigen::Quaterniond positive(Eigen::Quaterniond q) {
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return q;
}

// ABB's position and orientation "[x, y, z],[q1, q2, q3, q4]": mm and a quaternion.
std::string rapidPose(const Pose& pose) {
  const Vec3 xyz = pose.translation();
  const Eigen::Quaterniond q = positive(Eigen::Quaterniond(pose.linear()));
  return fmt::format("[{:.3f},{:.3f},{:.3f}],[{:.6f},{:.6f},{:.6f},{:.6f}]", xyz.x(), xyz.y(),
                     xyz.z(), q.w(), q.x(), q.y(), q.z());
}

// ABB's configuration quadrants cf1, cf4, cf6: floor(angle / 90°).
int quadrant(double angle) { return static_cast<int>(std::floor(degrees(angle) / 90)); }

// The speed of RAPID's moves between views and of its final approach to a view, mm/s (the
// predefined speeddata v500 and v100): the approach and the retract run slowed.
constexpr int kTravelSpeed = 500, kApproachSpeed = 100;

// KRL numbers its inputs and outputs from 1, and the view number's group of 16 outputs
// ($OUT[view] to $OUT[view+15]) must leave the trigger output alone. \throw UsageError
// naming the signal.
void checkKrlSignals(const CellSignals& s) {
  detail::checkSignalsFromOne(s, "KRL numbers its inputs and outputs");
  if (s.trigger >= s.view && s.trigger <= s.view + 15)
    throw UsageError("cell.signals.trigger",
                     fmt::format("output {} lies within the view number's outputs $OUT[{}] to "
                                 "$OUT[{}]: give the trigger an output of its own",
                                 s.trigger, s.view, s.view + 15));
}

// URScript's standard digital inputs and outputs are numbered 0 to 7, its integer and float
// output registers 0 to 47 (URScript manual, e-Series: set_standard_digital_out,
// get_standard_digital_in, write_output_integer_register, write_output_float_register); the
// table's move output must not be the scan's trigger. \throw UsageError naming the signal.
void checkUrSignals(const CellSignals& s) {
  std::vector<std::tuple<std::string, int, int>> checks = {
      {"cell.signals.view", s.view, 47},
      {"cell.signals.trigger", s.trigger, 7},
      {"cell.signals.acknowledge", s.acknowledge, 7}};
  if (s.table)
    checks.insert(checks.end(), {{"cell.signals.table.angle", s.table->angle, 47},
                                 {"cell.signals.table.move", s.table->move, 7},
                                 {"cell.signals.table.ready", s.table->ready, 7}});
  for (const auto& [key, number, most] : checks)
    if (number < 0 || number > most)
      throw UsageError(
          key, fmt::format("URScript numbers its {} 0 to {}, and {} is none of them",
                           most == 7 ? "standard digital inputs and outputs" : "output registers",
                           most, number));
  if (s.table && s.table->move == s.trigger)
    throw UsageError("cell.signals.table.move",
                     fmt::format("output {} is the scan's trigger: give the table an output of "
                                 "its own",
                                 s.trigger));
}

}  // namespace

RobotProgram robotProgram(const Cell& cell, const Pose& work_object, std::vector<ProgramStep> steps,
                          std::vector<int> unreached, const std::string& name,
                          const std::string& source) {
  RobotProgram program;
  program.name = identifier(name, 24);
  program.source = source;
  program.cell = cell;
  program.work_object = work_object;
  program.steps = std::move(steps);
  program.unreached = std::move(unreached);
  return program;
}

std::string toString(const RobotMove& move) {
  auto name = [](int id) { return id > 0 ? "view " + std::to_string(id) : std::string("home"); };
  return name(move.from) + " -> " + name(move.to);
}

Pose partOnTable(const RobotProgram& p) {
  return tableFrame(*p.cell.table).inverse() * p.cell.base * p.work_object;
}

Pose scannerInPart(const RobotProgram& p, const ProgramStep& step) {
  const Cell& cell = p.cell;
  // The part's frame in the base frame with the table at the step's angle.
  const Pose part =
      cell.base.inverse() * tableTurn(cell, step.pose.table_angle) * cell.base * p.work_object;
  return part.inverse() * step.flange * cell.mount;
}

int rapidCfx(const RobotModel& robot, const Joints& joints) {
  const std::array<Vec3, 4> c = jointCentres(robot, joints);
  const Vec3 &shoulder = c[0], &elbow = c[1], &wrist = c[2];
  // The arm's forward direction: the base's x axis turned by axis 1's model angle.
  const double turn = joints[0] * robot.signs[0] - robot.offsets[0];
  const Vec3 forward(std::cos(turn), std::sin(turn), 0);
  const bool behind_axis1 = forward.dot(wrist) < 0;
  // In the arm's plane (forward, up): the side of the lower arm (axis 2 to axis 3) that is
  // forward when the lower arm stands upright.
  const Vec3 arm = elbow - shoulder, to_wrist = wrist - shoulder;
  const double front = arm.z() * forward.dot(to_wrist) - forward.dot(arm) * to_wrist.z();
  const bool behind_lower_arm = front < 0;
  return 4 * behind_axis1 + 2 * behind_lower_arm + (joints[4] < 0);
}

std::vector<Waypoint> waypoints(const RobotProgram& p) {
  std::vector<Waypoint> path;
  if (p.home) path.push_back({*p.home, "home", nullptr});
  for (const ProgramStep& s : p.steps) {
    for (const CellPose& v : s.via) path.push_back({v, "via", &s});
    const CellPose back{s.pose.table_angle, s.approach.value_or(Joints{})};
    if (s.approach) path.push_back({back, "approach", &s});
    path.push_back({s.pose, "view", &s});
    if (s.approach) path.push_back({back, "retract", &s});
  }
  for (const CellPose& v : p.via_home) path.push_back({v, "via", nullptr});
  if (p.home) path.push_back({*p.home, "home", nullptr});
  return path;
}

void checkProgramFormat(const Cell& cell, std::string_view format) {
  const std::string option = "--format " + std::string(format);
  const RobotModel& robot = cell.robot;
  struct Language {
    std::string_view format, maker, name;
  };
  static constexpr std::array<Language, 4> languages = {
      {{"krl", "kuka", "KUKA"},
       {"rapid", "abb", "ABB"},
       {"fanuc", "fanuc", "FANUC"},
       {"urscript", "universal-robots", "Universal Robots"}}};
  const auto find = [&](auto Language::*key, std::string_view value) {
    return std::find_if(languages.begin(), languages.end(),
                        [&](const Language& l) { return l.*key == value; });
  };
  // An arm given by its parameters runs any ortho-parallel language; a preset its maker's.
  const auto language = find(&Language::format, format);
  const bool custom = robot.maker.empty() && !robot.offset_wrist;
  if (language != languages.end() && !custom && robot.maker != language->maker) {
    const auto own = find(&Language::maker, robot.maker);
    throw UsageError(option, fmt::format("{} is not one of {}'s arms, and {} runs on their "
                                         "controllers only: its maker's format is --format {}",
                                         commentText(robot.name), language->name, format,
                                         own != languages.end() ? own->format : "robot-json"));
  }
  if (format == "krl") checkKrlSignals(cell.signals);
  if (format == "fanuc")
    detail::checkSignalsFromOne(cell.signals, "FANUC numbers its GO, DO and DI signals");
  if (format == "urscript") checkUrSignals(cell.signals);
  if (format == "urscript" && cell.table && !cell.signals.table)
    throw UsageError(option,
                     "URScript cannot drive the rotary table without its signals: give "
                     "cell.signals.table {angle, move, ready} in the spec");
}

void checkClearMoves(const RobotProgram& program, bool allow, const std::string& path) {
  if (allow || program.uncleared.empty()) return;
  const std::size_t n = program.uncleared.size();
  throw UsageError(
      path, "the move " + toString(program.uncleared.front()) +
                (n > 1 ? fmt::format(" and {} more collide", n - 1) : std::string(" collides")) +
                " and could not be cleared: no program written (give "
                "--allow-collisions to write it with the moves marked)");
}

// KRL's scan handshake: the view number, the trigger, and each wait on the acknowledgement
// bounded (sig.timeout) by timer 1 ($TIMER_FLAG[1] rises when $TIMER[1], set below 0, reaches 0):
// on a timeout the trigger drops and the program halts.
std::string krlScan(const CellSignals& sig) {
  const auto wait = [&](bool state, std::string_view what) {
    return fmt::format(
        "  $TIMER_STOP[1] = TRUE\n  $TIMER[1] = -{ms}\n  $TIMER_STOP[1] = FALSE\n"
        "  WAIT FOR {is}$IN[{in}] OR $TIMER_FLAG[1]\n  $TIMER_STOP[1] = TRUE\n"
        "  IF {isnt}$IN[{in}] THEN\n    $OUT[{out}] = FALSE\n    HALT ; no {what} within {s} s\n"
        "  ENDIF\n",
        fmt::arg("ms", std::lround(sig.timeout * 1000)), fmt::arg("is", state ? "" : "NOT "),
        fmt::arg("isnt", state ? "NOT " : ""), fmt::arg("in", sig.acknowledge),
        fmt::arg("out", sig.trigger), fmt::arg("what", what), fmt::arg("s", sig.timeout));
  };
  return fmt::format(
             "DEF SCAN(VIEW:IN)\n  INT VIEW\n  SIGNAL VIEW_NO $OUT[{0}] TO $OUT[{1}]\n"
             "  WAIT SEC 0.2\n  VIEW_NO = VIEW\n  $OUT[{2}] = TRUE\n",
             sig.view, sig.view + 15, sig.trigger) +
         wait(true, "acknowledgement") + fmt::format("  $OUT[{}] = FALSE\n", sig.trigger) +
         wait(false, "end of the acknowledgement") + "END\n";
}

namespace {

// KRL's names of the points: X and the point's name (detail::pointNames).
std::vector<std::string> krlNames(const std::vector<Waypoint>& path) {
  std::vector<std::string> names = detail::pointNames(path);
  for (std::string& name : names) name = "X" + name;
  return names;
}

// KRL's PTP speed, percent of each axis's top speed: between views, and on the final
// approach to a view and its retract.
constexpr int kKrlTravelPercent = 20, kKrlApproachPercent = 5;

// KRL's $BASE, the part's frame. Fixed without a table: the part in the robot's base
// frame, the controller's world by default. With one, coupled to the table, the external
// kinematic MACHINE_DEF[2] (the first after the robot's MACHINE_DEF[1]), by EK(root, kind,
// offset): the base then turns with E1, and the offset is the part in the table's flange
// frame, whose root the controller's machine data calibrate.
std::string krlBase(const RobotProgram& p) {
  if (!p.cell.table) return "  $BASE = " + krlFrame(p.work_object) + "\n";
  return "  ; $BASE turns with the table (E1): the part in the table's frame (origin on its\n"
         "  ; axis, z along it, x along the world's x at E1 = 0)\n"
         "  $BASE = EK(MACHINE_DEF[2].ROOT, MACHINE_DEF[2].MECH_TYPE, " +
         krlFrame(partOnTable(p)) + ")\n";
}

}  // namespace

std::string krlProgram(const RobotProgram& p) {
  checkProgramFormat(p.cell, "krl");
  std::ostringstream out;
  const Vec3 centre = loadCentre(p.cell);
  const Vec3 inertia = p.load_inertia;
  out << "&ACCESS RVP\n&REL 1\n"
      << header(p, ";") << "DEF " << p.name << "()\n"
      << fmt::format("  BAS(#INITMOV, 0)\n  BAS(#VEL_PTP, {})\n  BAS(#ACC_PTP, 20)\n",
                     kKrlTravelPercent)
      << "  $TOOL = " << krlFrame(p.cell.mount) << "\n"
      << fmt::format("  $LOAD.M = {:.3f}\n", p.cell.tool.mass)
      << fmt::format("  $LOAD.CM = {{X {:.3f}, Y {:.3f}, Z {:.3f}, A 0, B 0, C 0}}\n", centre.x(),
                     centre.y(), centre.z())
      << fmt::format("  $LOAD.J = {{X {:.5f}, Y {:.5f}, Z {:.5f}}}\n", inertia.x(), inertia.y(),
                     inertia.z())
      << krlBase(p) << fmt::format("  $OUT[{}] = FALSE\n", p.cell.signals.trigger);
  int taken = 0;
  const std::vector<Waypoint> path = waypoints(p);
  const std::vector<std::string> names = krlNames(path);
  for (std::size_t k = 0; k < path.size(); ++k) {
    const Waypoint& w = path[k];
    const bool slowed = w.step && w.step->approach;
    if (w.what == "view") {
      const ProgramStep& s = *w.step;
      const Pose scanner = scannerInPart(p, s);
      const Vec3 xyz = scanner.translation(), abc = zyxAngles(scanner.linear());
      out << fmt::format("  ; view {} ({} of {}), task {}\n", s.view, ++taken, p.steps.size(),
                         s.task.empty() ? "-" : s.task)
          << fmt::format(
                 "  ; scanner {{E6POS: X {:.3f}, Y {:.3f}, Z {:.3f}, A {:.3f}, B {:.3f}, "
                 "C {:.3f}, E1 {:.3f}}}\n",
                 xyz.x(), xyz.y(), xyz.z(), abc.x(), abc.y(), abc.z(), degrees(s.pose.table_angle));
      if (slowed) out << fmt::format("  BAS(#VEL_PTP, {})\n", kKrlApproachPercent);
    } else {
      out << "  ; " << w.what << (w.step ? " view " + std::to_string(w.step->view) : "") << "\n";
    }
    out << "  PTP " << names[k] << "\n";
    if (w.what == "view") out << fmt::format("  SCAN({})\n", w.step->view);
    if (w.what == "retract") out << fmt::format("  BAS(#VEL_PTP, {})\n", kKrlTravelPercent);
  }
  out << "END\n\n" << krlScan(p.cell.signals);
  return out.str();
}

std::string krlData(const RobotProgram& p) {
  checkProgramFormat(p.cell, "krl");
  std::ostringstream out;
  out << "&ACCESS RVP\n&REL 1\nDEFDAT " << p.name << "\n"
      << "  ; the points of " << p.name << ".src: joints in degrees, E1 the rotary table\n";
  const std::vector<Waypoint> path = waypoints(p);
  const std::vector<std::string> names = krlNames(path);
  std::set<std::string> declared;
  for (std::size_t k = 0; k < path.size(); ++k) {
    if (!declared.insert(names[k]).second) continue;
    out << "  DECL E6AXIS " << names[k] << "={";
    for (int j = 0; j < 6; ++j)
      out << fmt::format("A{} {:.4f}, ", j + 1, degrees(path[k].pose.joints[j]));
    out << fmt::format("E1 {:.4f}, E2 0.0, E3 0.0, E4 0.0, E5 0.0, E6 0.0}}\n",
                       degrees(path[k].pose.table_angle));
  }
  out << "ENDDAT\n";
  return out.str();
}

// RAPID's scan handshake: the view number, the trigger, and each wait on the
// acknowledgement bounded (sig.timeout) by \MaxTime with its \TimeFlag: on a timeout the trigger
// drops, the error goes to the event log and the program stops.
std::string rapidScan(const CellSignals& sig) {
  const auto wait = [&](int state, std::string_view what) {
    return fmt::format(
        "    WaitDI DI_{in}, {state} \\MaxTime:={s} \\TimeFlag:=bTimeout;\n"
        "    IF bTimeout THEN\n      SetDO DO_{out}, 0;\n"
        "      ErrWrite \"scanplan: no {what}\", \"view \" + NumToStr(view, 0);\n"
        "      Stop;\n    ENDIF\n",
        fmt::arg("in", sig.acknowledge), fmt::arg("state", state), fmt::arg("s", sig.timeout),
        fmt::arg("out", sig.trigger), fmt::arg("what", what));
  };
  return "  PROC Scan(num view)\n    WaitTime 0.2;\n" +
         fmt::format("    SetGO GO_{}, view;\n    SetDO DO_{}, 1;\n", sig.view, sig.trigger) +
         wait(1, "acknowledgement") + fmt::format("    SetDO DO_{}, 0;\n", sig.trigger) +
         wait(0, "end of acknowledgement") + "  ENDPROC\n";
}

// RAPID's jointtarget value of `pose`: axes 1 to 6 and the table as external axis a
// (9E+09: no table), degrees.
std::string rapidJoints(const Cell& cell, const CellPose& pose) {
  const Joints& j = pose.joints;
  const std::string table =
      cell.table ? fmt::format("{:.4f}", degrees(pose.table_angle)) : std::string("9E+09");
  return fmt::format(
      "[[{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}],[{},9E+09,9E+09,9E+09,9E+09,9E+09]]",
      degrees(j[0]), degrees(j[1]), degrees(j[2]), degrees(j[3]), degrees(j[4]), degrees(j[5]),
      table);
}

// The named targets of each view: its joints (jView), its approach (jApproach) and the
// scanner's pose in the work object with the configuration (pView).
std::string rapidTargets(const RobotProgram& p) {
  std::string out;
  for (const ProgramStep& s : p.steps) {
    const Joints& j = s.pose.joints;
    const std::string table =
        p.cell.table ? fmt::format("{:.4f}", degrees(s.pose.table_angle)) : std::string("9E+09");
    out += fmt::format("  CONST jointtarget jView{} := {};\n", s.view, rapidJoints(p.cell, s.pose));
    if (s.approach)
      out += fmt::format("  CONST jointtarget jApproach{} := {};\n", s.view,
                         rapidJoints(p.cell, {s.pose.table_angle, *s.approach}));
    out += fmt::format(
        "  CONST robtarget pView{} := [{},[{},{},{},{}],[{},9E+09,9E+09,9E+09,9E+09,9E+09]];\n",
        s.view, rapidPose(scannerInPart(p, s)), quadrant(j[0]), quadrant(j[3]), quadrant(j[5]),
        rapidCfx(p.cell.robot, j), table);
  }
  return out;
}

// One move of RAPID's main routine: to the named targets at a view (the approach and the
// view itself slowed when there is an approach), elsewhere to the joints given inline.
std::string rapidMove(const RobotProgram& p, const Waypoint& w) {
  if (!w.step)
    return fmt::format("    ! {}\n    MoveAbsJ {}, v{}, z10, tScanner;\n", w.what,
                       rapidJoints(p.cell, w.pose), kTravelSpeed);
  const int view = w.step->view;
  const bool slowed = w.step->approach.has_value();
  if (w.what == "view")
    return fmt::format("    MoveAbsJ jView{}, v{}, fine, tScanner;\n    Scan {};\n", view,
                       slowed ? kApproachSpeed : kTravelSpeed, view);
  if (w.what == "approach")
    return fmt::format("    ! approach view {}\n    MoveAbsJ jApproach{}, v{}, z10, tScanner;\n",
                       view, view, kTravelSpeed);
  if (w.what == "retract")
    return fmt::format("    ! retract view {}\n    MoveAbsJ jApproach{}, v{}, z10, tScanner;\n",
                       view, view, kApproachSpeed);
  return fmt::format("    ! {} view {}\n    MoveAbsJ {}, v{}, z10, tScanner;\n", w.what, view,
                     rapidJoints(p.cell, w.pose), kTravelSpeed);
}

// RAPID's work object of the part. Fixed without a table: the part in the robot's base
// frame, the controller's world by default. With one, coordinated with the table's
// mechanical unit (ufprog FALSE, ufmec): the user frame is then the table's, as the
// controller's system parameters calibrate it, and the object frame the part in it (ABB,
// MultiMove application manual, "Coordinated work objects").
std::string rapidWorkObject(const RobotProgram& p) {
  if (!p.cell.table)
    return fmt::format("  PERS wobjdata wPart := [FALSE,TRUE,\"\",[{}],[[0,0,0],[1,0,0,0]]];\n",
                       rapidPose(p.work_object));
  return fmt::format(
      "  ! wPart moves with the table, mechanical unit {0}: the part in the table's frame\n"
      "  ! (origin on its axis, z along it, x along the world's x at angle 0)\n"
      "  PERS wobjdata wPart := [FALSE,FALSE,\"{0}\",[[0,0,0],[1,0,0,0]],[{1}]];\n",
      p.cell.table->unit, rapidPose(partOnTable(p)));
}

std::string rapidProgram(const RobotProgram& p) {
  checkProgramFormat(p.cell, "rapid");
  std::ostringstream out;
  const Vec3 centre = loadCentre(p.cell);
  out << "MODULE " << p.name << "\n"
      << header(p, "  !")
      << fmt::format(
             "  PERS tooldata tScanner := [TRUE,[{}],[{:.3f},[{:.3f},{:.3f},{:.3f}],"
             "[1,0,0,0],{:.5f},{:.5f},{:.5f}]];\n",
             rapidPose(p.cell.mount), p.cell.tool.mass, centre.x(), centre.y(), centre.z(),
             p.load_inertia.x(), p.load_inertia.y(), p.load_inertia.z())
      << rapidWorkObject(p) << rapidTargets(p) << "  VAR bool bTimeout;\n\n  PROC main()\n"
      << fmt::format("    SetDO DO_{}, 0;\n", p.cell.signals.trigger);
  for (const Waypoint& w : waypoints(p)) out << rapidMove(p, w);
  out << "  ENDPROC\n\n" << rapidScan(p.cell.signals) << "ENDMODULE\n";
  return out.str();
}

// URScript's pose p[x, y, z, rx, ry, rz]: metres and a rotation vector.
std::string urPose(const Pose& pose) {
  const Vec3 xyz = pose.translation() / 1000;
  const Eigen::AngleAxisd turn(pose.linear());
  const Vec3 r = turn.angle() * turn.axis();
  return fmt::format("p[{:.6f}, {:.6f}, {:.6f}, {:.6f}, {:.6f}, {:.6f}]", xyz.x(), xyz.y(), xyz.z(),
                     r.x(), r.y(), r.z());
}

// Raises output `request`, waits for input `done`, drops the output, waits for the input
// to drop.
// URScript's handshake: raise `request`, wait for `done`, drop `request`, wait for `done` to
// drop; each wait bounded (await_input) and ended, on a timeout, by an error and a halt.
std::string urHandshake(int request, int done, std::string_view what) {
  return fmt::format(
      "    set_standard_digital_out({0}, True)\n"
      "    await_input({1}, True, {0}, \"scanplan: no {2}\")\n"
      "    set_standard_digital_out({0}, False)\n"
      "    await_input({1}, False, {0}, \"scanplan: {2} did not end\")\n",
      request, done, what);
}

// The wait on an input of every URScript handshake: at most `timeout` seconds, then the
// request dropped, an error shown and the program halted.
std::string urAwaitInput(double timeout) {
  return fmt::format(
      "  def await_input(n, state, request, what):\n    waited = 0.0\n"
      "    while get_standard_digital_in(n) != state:\n      sleep(0.01)\n"
      "      waited = waited + 0.01\n      if waited > {}:\n"
      "        set_standard_digital_out(request, False)\n"
      "        popup(what, \"scanplan\", error=True)\n        halt()\n      end\n    end\n"
      "  end\n",
      timeout);
}

// URScript's part_frame, the part's frame in the robot's base frame. With a table it turns
// with it: the table's frame at 0 and the part on it are given, and part_frame is set again
// after each turn.
std::string urPartFrame(const RobotProgram& p) {
  if (!p.cell.table) return "  part_frame = " + urPose(p.work_object) + "\n";
  return "  # part_frame turns with the table: table_frame is the table's at 0 (origin on its\n"
         "  # axis, z along it, x along the world's x), part_on_table the part in it\n"
         "  table_frame = " +
         urPose(p.cell.base.inverse() * tableFrame(*p.cell.table)) +
         "\n  part_on_table = " + urPose(partOnTable(p)) + "\n";
}

std::string urScript(const RobotProgram& p) {
  checkProgramFormat(p.cell, "urscript");
  const CellSignals& sig = p.cell.signals;
  const Vec3 centre = loadCentre(p.cell) / 1000;
  std::ostringstream out;
  out << header(p, "#", true) << "def " << p.name << "():\n"
      << "  set_tcp(" << urPose(p.cell.mount) << ")\n"
      << urPartFrame(p)
      << fmt::format(
             "  set_target_payload({:.3f}, [{:.6f}, {:.6f}, {:.6f}], [{:.5f}, {:.5f}, {:.5f}, 0, "
             "0, "
             "0])\n",
             p.cell.tool.mass, centre.x(), centre.y(), centre.z(), p.load_inertia.x(),
             p.load_inertia.y(), p.load_inertia.z())
      << fmt::format("  set_standard_digital_out({}, False)\n", sig.trigger)
      << (sig.table ? fmt::format("  set_standard_digital_out({}, False)\n", sig.table->move) : "")
      << urAwaitInput(sig.timeout) << "  def scan(view):\n    sleep(0.2)\n"
      << fmt::format("    write_output_integer_register({}, view)\n", sig.view)
      << urHandshake(sig.trigger, sig.acknowledge, "acknowledgement of the scan") << "  end\n";
  if (sig.table)
    out << "  def turn_table(angle):\n"
        << fmt::format("    write_output_float_register({}, angle)\n", sig.table->angle)
        << urHandshake(sig.table->move, sig.table->ready, "table ready") << "  end\n";
  std::optional<double> table;
  int taken = 0;
  for (const Waypoint& w : waypoints(p)) {
    if (w.what == "view")
      out << fmt::format("  # view {} ({} of {}), scanner pose_trans(part_frame, {})\n",
                         w.step->view, ++taken, p.steps.size(), urPose(scannerInPart(p, *w.step)));
    else
      out << "  # " << w.what << (w.step ? " view " + std::to_string(w.step->view) : "") << "\n";
    if (p.cell.table && (!table || *table != w.pose.table_angle))
      out << fmt::format("  turn_table({:.4f})\n", degrees(w.pose.table_angle))
          << fmt::format(
                 "  part_frame = pose_trans(table_frame, pose_trans(p[0, 0, 0, 0, 0, {:.6f}], "
                 "part_on_table))\n",
                 w.pose.table_angle);
    table = w.pose.table_angle;
    const Joints& q = w.pose.joints;
    out << fmt::format("  movej([{:.6f}, {:.6f}, {:.6f}, {:.6f}, {:.6f}, {:.6f}], a=1.2, v=0.5)\n",
                       q[0], q[1], q[2], q[3], q[4], q[5]);
    if (w.what == "view") out << fmt::format("  scan({})\n", w.step->view);
  }
  out << "end\n";
  return out.str();
}

std::string programJson(const RobotProgram& p) {
  using nlohmann::json;
  auto matrix = [](const Pose& pose) {
    json rows = json::array();
    for (int r = 0; r < 4; ++r) rows.push_back({pose(r, 0), pose(r, 1), pose(r, 2), pose(r, 3)});
    return rows;
  };
  auto poseJson = [](const CellPose& pose) {
    json joints = json::array();
    for (double q : pose.joints) joints.push_back(degrees(q));
    return json{{"joints", joints}, {"table", degrees(pose.table_angle)}};
  };
  json steps = json::array();
  for (const ProgramStep& s : p.steps) {
    json joints = json::array();
    for (double q : s.pose.joints) joints.push_back(degrees(q));
    json via = json::array();
    for (const CellPose& v : s.via) via.push_back(poseJson(v));
    steps.push_back(
        {{"view", s.view},
         {"task", s.task},
         {"joints", joints},
         {"table", degrees(s.pose.table_angle)},
         {"flange", matrix(s.flange)},
         {"scanner", matrix(scannerInPart(p, s))},
         {"via", via},
         {"approach", s.approach ? poseJson({s.pose.table_angle, *s.approach}) : json(nullptr)}});
  }
  json via_home = json::array();
  for (const CellPose& v : p.via_home) via_home.push_back(poseJson(v));
  json uncleared = json::array();
  for (const RobotMove& move : p.uncleared) uncleared.push_back(toString(move));
  const json root = {{"format", "scanplan.robot_program"},
                     {"version", 1},
                     {"units", {{"length", "mm"}, {"angle", "deg"}}},
                     {"name", p.name},
                     {"source", p.source},
                     {"robot", p.cell.robot.name},
                     {"base", matrix(p.cell.base)},
                     {"mount", matrix(p.cell.mount)},
                     {"work_object", matrix(p.work_object)},
                     {"home", p.home ? poseJson(*p.home) : json(nullptr)},
                     {"steps", steps},
                     {"via_home", via_home},
                     {"uncleared", uncleared},
                     {"unreached", p.unreached}};
  return root.dump(1) + "\n";
}

void checkProgramLanguage(std::string_view format) {
  if (format != "krl" && format != "rapid" && format != "fanuc" && format != "urscript" &&
      format != "json")
    throw UsageError("format", "'" + commentText(std::string(format)) +
                                   "': expected krl, rapid, fanuc, urscript or json");
}

void writeRobotProgram(const RobotProgram& program, std::string_view format,
                       const std::string& path) {
  checkProgramLanguage(format);
  const std::string stem = std::filesystem::path(path).stem().string();
  // KRL and FANUC run a program under its file's name.
  if ((format == "krl" || format == "fanuc") && stem != program.name) {
    const bool krl = format == "krl";
    throw UsageError(path, fmt::format("{} runs a program under its file's name, and '{}' is "
                                       "not a {} name (a letter, then letters, digits or _, 24 "
                                       "at most): name the file {}.{}",
                                       krl ? "KRL" : "FANUC", commentText(stem),
                                       krl ? "KRL" : "program", program.name, krl ? "src" : "ls"));
  }
  if (format == "krl" && std::filesystem::path(path).extension() != ".src")
    throw UsageError(path,
                     "a KRL program is written as NAME.src, its points as NAME.dat "
                     "beside it: give the file the extension .src");
  const std::string text = format == "krl"        ? krlProgram(program)
                           : format == "rapid"    ? rapidProgram(program)
                           : format == "fanuc"    ? fanucProgram(program)
                           : format == "urscript" ? urScript(program)
                                                  : programJson(program);
  if (format == "krl") {
    const std::string data = krlData(program);
    writeFileAtomically(std::filesystem::path(path).replace_extension(".dat").string(),
                        [&](std::ostream& out) { out << data; });
  }
  writeFileAtomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace scanplan
