// FANUC's teach-pendant program in its ASCII form (LS): /PROG, /ATTR, /MN with joint moves
// to positions in the joint representation and the scan handshake, /POS with the
// positions (the rotary table as extended axis E1), /END.

#include "robot/program_text.h"

#include <scanplan/robot/program.h>

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <sstream>

namespace scanplan {
namespace {

// FANUC's joint speed, percent: between views, and on the final approach and the retract.
constexpr int kTravelPercent = 20, kApproachPercent = 5;

// The labels the handshake jumps to when an input does not come in time, and the end.
constexpr int kNoAcknowledge = 90, kAcknowledgeStuck = 91, kEnd = 99;

// A remark, broken between words into lines of at most 32 characters (the pendant's
// remark width), ';' taken out.
void remark(std::vector<std::string>& lines, const std::string& text) {
  std::string safe = detail::commentText(text);
  for (char& c : safe)
    if (c == ';') c = ',';
  std::istringstream words(safe);
  std::string line;
  const auto flush = [&] {
    if (line.empty()) return;
    lines.emplace_back(1, '!');
    lines.back() += line;
    line.clear();
  };
  for (std::string word; words >> word;) {
    if (!line.empty() && line.size() + 1 + word.size() > 32) flush();
    if (!line.empty()) line += ' ';
    line.append(word, 0, 32);
  }
  flush();
}

// Remarks giving frame `name`'s value: X, Y, Z (mm) on one line, W, P, R (degrees) on the
// next.
void frameRemarks(std::vector<std::string>& lines, const std::string& name, const Pose& pose) {
  const Vec3 xyz = pose.translation(), wpr = zyxAngles(pose.linear()).reverse();
  remark(lines, fmt::format("{}: X {:.1f} Y {:.1f} Z {:.1f}", name, xyz.x(), xyz.y(), xyz.z()));
  remark(lines, fmt::format("{}: W {:.2f} P {:.2f} R {:.2f}", name, wpr.x(), wpr.y(), wpr.z()));
}

// The scan handshake at `view`: the view number to the group output, the trigger raised,
// the acknowledgement awaited (at most sig.timeout, else to the error labels), the
// trigger dropped, the acknowledgement's end awaited.
void scanLines(std::vector<std::string>& lines, const CellSignals& sig, int view) {
  lines.insert(
      lines.end(),
      {"WAIT .20(sec)", fmt::format("GO[{}]={}", sig.view, view),
       fmt::format("DO[{}]=ON", sig.trigger),
       fmt::format("$WAITTMOUT={}", std::lround(sig.timeout * 100)),  // hundredths of a second
       fmt::format("WAIT DI[{}]=ON TIMEOUT,LBL[{}]", sig.acknowledge, kNoAcknowledge),
       fmt::format("DO[{}]=OFF", sig.trigger),
       fmt::format("WAIT DI[{}]=OFF TIMEOUT,LBL[{}]", sig.acknowledge, kAcknowledgeStuck)});
}

// The end of the main routine and its error exits: the trigger dropped, a message, the
// program aborted.
void errorLines(std::vector<std::string>& lines, const CellSignals& sig) {
  lines.push_back(fmt::format("JMP LBL[{}]", kEnd));
  for (const auto& [label, what] : {std::pair{kNoAcknowledge, "NO SCAN ACKNOWLEDGE"},
                                    std::pair{kAcknowledgeStuck, "SCAN ACKNOWLEDGE STUCK"}})
    lines.insert(lines.end(),
                 {fmt::format("LBL[{}]", label), fmt::format("DO[{}]=OFF", sig.trigger),
                  fmt::format("MESSAGE[{}]", what), "ABORT"});
  lines.push_back(fmt::format("LBL[{}]", kEnd));
}

// The /MN lines (without their numbers) and, per position number, the waypoint it holds.
struct Routine {
  std::vector<std::string> lines;
  std::map<int, const Waypoint*> positions;
  std::map<int, std::string> names;
};

Routine mainRoutine(const RobotProgram& p, const std::vector<Waypoint>& path) {
  Routine r;
  remark(r.lines, fmt::format("scanplan {}: {} views", p.name, p.steps.size()));
  if (!p.unreached.empty()) remark(r.lines, fmt::format("views left out: {}", p.unreached.size()));
  for (const RobotMove& move : p.uncleared) remark(r.lines, "WARNING collides: " + toString(move));
  frameRemarks(r.lines, "UFRAME 1", p.work_object);
  frameRemarks(r.lines, "UTOOL 1", p.cell.mount);
  remark(r.lines, fmt::format("PAYLOAD 1: {:.2f} kg", p.cell.tool.mass));
  r.lines.insert(r.lines.end(), {"UFRAME_NUM=1", "UTOOL_NUM=1", "PAYLOAD[1]",
                                 fmt::format("DO[{}]=OFF", p.cell.signals.trigger)});
  const std::vector<std::string> names = detail::pointNames(path);
  std::map<std::string, int> numbers;
  int taken = 0;
  for (std::size_t k = 0; k < path.size(); ++k) {
    const Waypoint& w = path[k];
    const auto [at, added] = numbers.emplace(names[k], static_cast<int>(numbers.size()) + 1);
    if (added) {
      r.positions[at->second] = &w;
      r.names[at->second] = names[k];
    }
    const bool slowed = w.step && w.step->approach && (w.what == "view" || w.what == "retract");
    if (w.what == "view")
      remark(r.lines, fmt::format("view {} ({} of {})", w.step->view, ++taken, p.steps.size()));
    r.lines.push_back(fmt::format("J P[{}:{}] {}% FINE", at->second, names[k],
                                  slowed ? kApproachPercent : kTravelPercent));
    if (w.what == "view") scanLines(r.lines, p.cell.signals, w.step->view);
  }
  errorLines(r.lines, p.cell.signals);
  return r;
}

std::string positionText(const RobotProgram& p, int number, const std::string& name,
                         const CellPose& pose) {
  const Joints& j = pose.joints;
  std::string text = fmt::format(
      "P[{}:\"{}\"]{{\n   GP1:\n\tUF : 1, UT : 1,\t\n"
      "\tJ1= {:9.3f} deg,\tJ2= {:9.3f} deg,\tJ3= {:9.3f} deg,\n"
      "\tJ4= {:9.3f} deg,\tJ5= {:9.3f} deg,\tJ6= {:9.3f} deg",
      number, name, degrees(j[0]), degrees(j[1]), degrees(j[2]), degrees(j[3]), degrees(j[4]),
      degrees(j[5]));
  if (p.cell.table) text += fmt::format(",\n\tE1= {:9.3f} deg", degrees(pose.table_angle));
  return text + "\n};\n";
}

}  // namespace

std::string fanucProgram(const RobotProgram& p) {
  checkProgramFormat(p.cell, "fanuc");
  const std::vector<Waypoint> path = waypoints(p);
  const Routine routine = mainRoutine(p, path);
  std::string name = p.name;
  for (char& c : name) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  std::ostringstream out;
  out << "/PROG  " << name << "\n/ATTR\nOWNER\t\t= MNEDITOR;\nCOMMENT\t\t= \"scanplan\";\n"
      << "PROG_SIZE\t= 0;\nCREATE\t\t= DATE 00-01-01  TIME 00:00:00;\n"
      << "MODIFIED\t= DATE 00-01-01  TIME 00:00:00;\nFILE_NAME\t= ;\nVERSION\t\t= 0;\n"
      << "LINE_COUNT\t= " << routine.lines.size() << ";\nMEMORY_SIZE\t= 0;\n"
      << "PROTECT\t\t= READ_WRITE;\nTCD:  STACK_SIZE\t= 0,\n      TASK_PRIORITY\t= 50,\n"
      << "      TIME_SLICE\t= 0,\n      BUSY_LAMP_OFF\t= 0,\n      ABORT_REQUEST\t= 0,\n"
      << "      PAUSE_REQUEST\t= 0;\nDEFAULT_GROUP\t= 1,*,*,*,*;\n"
      << "CONTROL_CODE\t= 00000000 00000000;\n/MN\n";
  for (std::size_t k = 0; k < routine.lines.size(); ++k) {
    const std::string& line = routine.lines[k];
    const bool motion = line.rfind("J ", 0) == 0;
    out << fmt::format("{:4d}:{}{} ;\n", k + 1, motion ? "" : "  ", line);
  }
  out << "/POS\n";
  for (const auto& [number, waypoint] : routine.positions)
    out << positionText(p, number, routine.names.at(number), waypoint->pose);
  out << "/END\n";
  return out.str();
}

}  // namespace scanplan
