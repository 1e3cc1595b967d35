// What the robot program writers share (robot/program_text.h).

#include "robot/program_text.h"

#include <scanplan/core/errors.h>

#include <fmt/format.h>

#include <sstream>

namespace scanplan::detail {

std::string commentText(const std::string& text) {
  std::string safe = text;
  for (char& c : safe)
    if (static_cast<unsigned char>(c) < 0x20 || static_cast<unsigned char>(c) > 0x7e) c = '?';
  return safe;
}

std::string header(const RobotProgram& p, std::string_view comment, bool urscript) {
  std::ostringstream out;
  out << comment << " scanplan robot program " << p.name << "\n"
      << comment << " from " << commentText(p.source) << "\n"
      << comment << " robot " << commentText(p.cell.robot.name) << ", " << p.steps.size()
      << (p.steps.size() == 1 ? " view" : " views in sequence order");
  if (p.cell.table)
    out << (urscript ? ", rotary table turned by turn_table" : ", rotary table as external axis 1");
  out << "\n";
  if (!p.unreached.empty()) {
    out << comment << " left out, the cell cannot reach them: views";
    for (int id : p.unreached) out << ' ' << id;
    out << "\n";
  }
  for (const RobotMove& move : p.uncleared)
    out << comment << " WARNING: the move " << toString(move)
        << " collides and could not be cleared\n";
  const CellSignals& s = p.cell.signals;
  out << comment << " joints in " << (urscript ? "radians" : "degrees")
      << " as the controller counts them; the tool is the scanner frame on its mount\n"
      << comment << " scanner poses in the part's frame"
      << (p.cell.table ? ", which turns with the table" : "")
      << (urscript ? ", m and rotation vectors\n" : ", mm\n") << comment
      << fmt::format(
             " scan handshake: view number to output {}, trigger output {}, "
             "acknowledge input {}\n",
             s.view, s.trigger, s.acknowledge);
  return out.str();
}

Vec3 loadCentre(const Cell& cell) { return cell.tool.centre.value_or(cell.mount.translation()); }

void checkSignalsFromOne(const CellSignals& s, std::string_view numbers) {
  for (const auto& [key, number] : {std::pair{"cell.signals.view", s.view},
                                    {"cell.signals.trigger", s.trigger},
                                    {"cell.signals.acknowledge", s.acknowledge}})
    if (number < 1)
      throw UsageError(key, fmt::format("{} from 1, and {} is none of them", numbers, number));
}

std::vector<std::string> pointNames(const std::vector<Waypoint>& path) {
  std::vector<std::string> names;
  int vias = 0;
  for (const Waypoint& w : path) {
    if (w.what == "home")
      names.push_back("HOME");
    else if (w.what == "via")
      names.push_back("VIA" + std::to_string(++vias));
    else
      names.push_back(fmt::format("{}{}", w.what == "view" ? "VIEW" : "APPROACH", w.step->view));
  }
  return names;
}

}  // namespace scanplan::detail
