#pragma once
// What one run of a plan takes on the cell (docs/cycle.md): the scanner's acquisition at
// every view, the settling before each trigger and the handshake after it, and the moves
// between views, by each joint's (and the table's) speed and acceleration; without a cell,
// by a generic Cartesian positioning of the scanner.

#include <scanplan/robot/program.h>
#include <scanplan/scanner/sensor.h>

#include <span>
#include <string>
#include <vector>

namespace scanplan {

// The spec's `cycle:` section: the times spent at each view besides the acquisition, and
// the generic positioning of plans without a cell.
struct CycleSettings {
  double settle = 0.3;        // s the robot stands still before the trigger
  double handshake = 0.2;     // s from the end of the acquisition to the next move
  double speed = 250;         // generic positioning: the scanner's top speed, mm/s
  double acceleration = 500;  // and its acceleration, mm/s²
  double turn_over = 0;       // s to turn the part over by hand between two setups
};

// \throw InputError naming `source` and the key when a value is out of range: settle and
// handshake within [0, 60] s, speed within [1, 10000] mm/s, acceleration within
// [1, 100000] mm/s², turn_over within [0, 3600] s.
void validate(const CycleSettings& settings, const std::string& source);

// A run of the plan, seconds, split by what the cell does.
struct CycleTime {
  std::string model;       // "cell": the robot's joints and table; "generic": Cartesian
  std::size_t views = 0;   // the views taken
  double acquisition = 0;  // the scanner capturing, over all views
  double motion = 0;       // moving between views (home, approaches, vias included)
  double table = 0;        // the moves the table's turn makes longer than the arm's
  double other = 0;        // settling and handshakes, over all views
  std::size_t turns = 0;   // turns of the part by hand between setups (rest orientations)
  double turning = 0;      // and their seconds (cycle.turn_over each)
  // The estimated cycle of the plan's first k views (in its numbering, by marginal
  // coverage), k = 1..views: their time at the views and the moves of a path through
  // them (cheapest insertion). Empty when not estimated.
  std::vector<double> by_views;
  double total() const { return acquisition + motion + table + other + turning; }
  // Another run after this one (a later rest orientation): the parts add up, and its
  // curve continues this one's. The turn of the part between them is added apart.
  CycleTime& operator+=(const CycleTime& more);
};

// The seconds one view takes standing: the scanner's acquisition, the settling before it
// and the handshake after it.
double viewSeconds(const Scanner& scanner, const CycleSettings& settings);

// CycleTime::by_views from the motion of a path through the first k views (k = 1..n,
// seconds): k views' viewSeconds plus path[k - 1].
std::vector<double> cycleByViews(std::span<const double> path, const Scanner& scanner,
                                 const CycleSettings& settings);

// One move of the cell from `a` to `b`, every joint and the table synchronised to the
// slowest: the arm's seconds (the slowest joint's trapezoid) and the table's.
struct MoveSeconds {
  double arm = 0, table = 0;
  double total() const { return std::max(arm, table); }
};
MoveSeconds moveSeconds(const Cell& cell, const CellPose& a, const CellPose& b);

// The cycle of `program`: each of its moves (waypoints) by moveSeconds, counted as table
// time where the table's turn is the longer; at each view the scanner's acquisition, the
// settling and the handshake.
CycleTime programCycle(const RobotProgram& program, const Scanner& scanner,
                       const CycleSettings& settings);

// The generic cycle of `views` views reached one after another by the scanner's moves of
// `distances` mm (trapezoids at the settings' speed and acceleration).
CycleTime genericCycle(std::span<const double> distances, std::size_t views, const Scanner& scanner,
                       const CycleSettings& settings);

}  // namespace scanplan
