#pragma once
// What the robot program writers (robot/program.h) share: the header comment, the safe
// comment text, the load's centre, the handshake's timeout and the names of the points.

#include <scanplan/robot/program.h>

#include <string>
#include <string_view>
#include <vector>

namespace scanplan::detail {

// `text` from the user's files (a path, a robot's name) for a one-line comment: every byte
// outside printable ASCII, a line break above all, becomes '?', so that nothing of it can
// end the comment and stand as a statement, nor trouble a controller's 8-bit editor.
std::string commentText(const std::string& text);

// The header comment, each line opened by `comment`; URScript counts joints in radians and
// drives the table by signals.
std::string header(const RobotProgram& p, std::string_view comment, bool urscript = false);

// The scanner's load: its centre of gravity in the flange frame, mm.
Vec3 loadCentre(const Cell& cell);

// Signals numbered from 1, as `numbers` says the language counts them ("KRL numbers its
// inputs and outputs"). \throw UsageError naming the first signal below 1.
void checkSignalsFromOne(const CellSignals& signals, std::string_view numbers);

// The name of each waypoint's point, in order: HOME, VIA1, VIA2, ..., APPROACH<view> (its
// retract too), VIEW<view>.
std::vector<std::string> pointNames(const std::vector<Waypoint>& path);

}  // namespace scanplan::detail
