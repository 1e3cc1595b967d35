// Robot programs from a plan. Each moves in joint space to every view (the joints the plan
// chose, so the robot takes the configuration the plan checked), waits there and triggers
// the scanner, in sequence order. Poses of the flange are given too, for the integrator.

#include <scanplan/io/atomic_file.h>
#include <scanplan/robot/program.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cctype>
#include <cmath>
#include <map>
#include <sstream>

namespace scanplan {
namespace {

std::string identifier(const std::string& name, std::size_t length) {
  std::string id;
  for (char c : name) id += std::isalnum(static_cast<unsigned char>(c)) ? c : '_';
  if (id.empty() || !std::isalpha(static_cast<unsigned char>(id.front()))) id = "p_" + id;
  return id.substr(0, length);
}

// KUKA's A, B, C: rotation about Z, then the new Y, then the new X, degrees.
Vec3 kukaAbc(const Eigen::Matrix3d& r) {
  return Vec3(degrees(std::atan2(r(1, 0), r(0, 0))),
              degrees(std::atan2(-r(2, 0), std::hypot(r(0, 0), r(1, 0)))),
              degrees(std::atan2(r(2, 1), r(2, 2))));
}

// ABB's configuration quadrants cf1, cf4, cf6: floor(angle / 90°).
int quadrant(double angle) { return static_cast<int>(std::floor(degrees(angle) / 90)); }

std::string header(const RobotProgram& p, std::string_view comment) {
  std::ostringstream out;
  out << comment << " scanplan robot program " << p.name << "\n"
      << comment << " from " << p.source << "\n"
      << comment << " robot " << p.cell.robot.name << ", " << p.steps.size()
      << " views in sequence order";
  if (p.cell.table) out << ", rotary table as external axis 1";
  out << "\n";
  if (!p.unreached.empty()) {
    out << comment << " left out, the cell cannot reach them: views";
    for (int id : p.unreached) out << ' ' << id;
    out << "\n";
  }
  out << comment
      << " joints in degrees as the controller counts them; flange poses in the robot's\n"
      << comment << " base frame, mm; the scan is triggered on the first digital output and\n"
      << comment << " done when the first digital input is set\n";
  return out.str();
}

}  // namespace

RobotProgram robotProgram(const Plan& plan, const Cell& cell, const std::string& name,
                          const std::string& source, const CellCollisions* collisions) {
  RobotProgram program;
  program.name = identifier(name, 24);
  program.source = source;
  program.cell = cell;
  const std::vector<int> order = visitingOrder(plan);
  const std::vector<std::optional<CellPose>> poses = cellPoses(cell, plan.views, order, collisions);
  std::map<int, std::size_t> index;
  for (std::size_t i = 0; i < plan.views.size(); ++i) index[plan.views[i].id] = i;
  for (int id : order) {
    const std::size_t i = index.at(id);
    if (!poses[i]) {
      program.unreached.push_back(id);
      continue;
    }
    program.steps.push_back(
        {id, plan.views[i].task, *poses[i], forwardKinematics(cell.robot, poses[i]->joints)});
  }
  return program;
}

std::string krlProgram(const RobotProgram& p) {
  std::ostringstream out;
  out << "&ACCESS RVP\n&REL 1\n"
      << header(p, ";") << "DEF " << p.name << "()\n"
      << "  BAS(#INITMOV, 0)\n  BAS(#VEL_PTP, 20)\n  BAS(#ACC_PTP, 20)\n";
  for (std::size_t k = 0; k < p.steps.size(); ++k) {
    const ProgramStep& s = p.steps[k];
    const Vec3 xyz = s.flange.translation(), abc = kukaAbc(s.flange.linear());
    const double e1 = degrees(s.pose.table_angle);
    out << fmt::format("  ; view {} ({} of {}), task {}\n", s.view, k + 1, p.steps.size(),
                       s.task.empty() ? "-" : s.task)
        << fmt::format(
               "  ; flange {{E6POS: X {:.3f}, Y {:.3f}, Z {:.3f}, A {:.3f}, B {:.3f}, C {:.3f}, E1 "
               "{:.3f}}}\n",
               xyz.x(), xyz.y(), xyz.z(), abc.x(), abc.y(), abc.z(), e1);
    out << "  PTP {E6AXIS:";
    for (int j = 0; j < 6; ++j)
      out << fmt::format(" A{} {:.4f},", j + 1, degrees(s.pose.joints[j]));
    out << fmt::format(" E1 {:.4f}}}\n", e1) << fmt::format("  SCAN({})\n", s.view);
  }
  out << "END\n\n"
      << "DEF SCAN(VIEW:IN)\n  INT VIEW\n  WAIT SEC 0.2\n  $OUT[1] = TRUE\n"
      << "  WAIT FOR $IN[1]\n  $OUT[1] = FALSE\nEND\n";
  return out.str();
}

std::string rapidProgram(const RobotProgram& p) {
  std::ostringstream out;
  out << "MODULE " << p.name << "\n" << header(p, "  !");
  auto external = [&](double angle) {
    return p.cell.table ? fmt::format("{:.4f}", degrees(angle)) : std::string("9E+09");
  };
  for (const ProgramStep& s : p.steps) {
    const Vec3 xyz = s.flange.translation();
    Eigen::Quaterniond q(s.flange.linear());
    if (q.w() < 0) q.coeffs() = -q.coeffs();
    const Joints& j = s.pose.joints;
    out << fmt::format(
        "  CONST jointtarget jView{} := [[{:.4f},{:.4f},{:.4f},{:.4f},{:.4f},{:.4f}],"
        "[{},9E+09,9E+09,9E+09,9E+09,9E+09]];\n",
        s.view, degrees(j[0]), degrees(j[1]), degrees(j[2]), degrees(j[3]), degrees(j[4]),
        degrees(j[5]), external(s.pose.table_angle));
    out << fmt::format(
        "  CONST robtarget pView{} := [[{:.3f},{:.3f},{:.3f}],[{:.6f},{:.6f},{:.6f},{:.6f}],"
        "[{},{},{},0],[{},9E+09,9E+09,9E+09,9E+09,9E+09]];\n",
        s.view, xyz.x(), xyz.y(), xyz.z(), q.w(), q.x(), q.y(), q.z(), quadrant(j[0]),
        quadrant(j[3]), quadrant(j[5]), external(s.pose.table_angle));
  }
  out << "\n  PROC main()\n";
  for (const ProgramStep& s : p.steps)
    out << fmt::format("    MoveAbsJ jView{}, v500, fine, tool0;\n    Scan {};\n", s.view, s.view);
  out << "  ENDPROC\n\n"
      << "  PROC Scan(num view)\n    WaitTime 0.2;\n    SetDO DO_1, 1;\n"
      << "    WaitDI DI_1, 1;\n    SetDO DO_1, 0;\n  ENDPROC\nENDMODULE\n";
  return out.str();
}

std::string urScript(const RobotProgram& p) {
  // A UR arm has no spherical wrist: its controller solves the inverse kinematics of the
  // flange poses (metres, rotation vectors) itself.
  std::ostringstream out;
  out << header(p, "#") << "def " << p.name << "():\n"
      << "  def scan(view):\n    sleep(0.2)\n    set_standard_digital_out(0, True)\n"
      << "    while not get_standard_digital_in(0):\n      sync()\n    end\n"
      << "    set_standard_digital_out(0, False)\n  end\n";
  for (std::size_t k = 0; k < p.steps.size(); ++k) {
    const ProgramStep& s = p.steps[k];
    const Vec3 xyz = s.flange.translation() / 1000;
    const Eigen::AngleAxisd turn(s.flange.linear());
    const Vec3 r = turn.angle() * turn.axis();
    out << fmt::format("  # view {} ({} of {})\n", s.view, k + 1, p.steps.size())
        << fmt::format("  movej(p[{:.6f}, {:.6f}, {:.6f}, {:.6f}, {:.6f}, {:.6f}], a=1.2, v=0.5)\n",
                       xyz.x(), xyz.y(), xyz.z(), r.x(), r.y(), r.z())
        << fmt::format("  scan({})\n", s.view);
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
  json steps = json::array();
  for (const ProgramStep& s : p.steps) {
    json joints = json::array();
    for (double q : s.pose.joints) joints.push_back(degrees(q));
    steps.push_back({{"view", s.view},
                     {"task", s.task},
                     {"joints", joints},
                     {"table", degrees(s.pose.table_angle)},
                     {"flange", matrix(s.flange)}});
  }
  const json root = {{"format", "scanplan.robot_program"},
                     {"version", 1},
                     {"units", {{"length", "mm"}, {"angle", "deg"}}},
                     {"name", p.name},
                     {"source", p.source},
                     {"robot", p.cell.robot.name},
                     {"base", matrix(p.cell.base)},
                     {"mount", matrix(p.cell.mount)},
                     {"steps", steps},
                     {"unreached", p.unreached}};
  return root.dump(1) + "\n";
}

void writeRobotProgram(const RobotProgram& program, std::string_view format,
                       const std::string& path) {
  const std::string text = format == "krl"        ? krlProgram(program)
                           : format == "rapid"    ? rapidProgram(program)
                           : format == "urscript" ? urScript(program)
                                                  : programJson(program);
  writeFileAtomically(path, [&](std::ostream& out) { out << text; });
}

}  // namespace scanplan
