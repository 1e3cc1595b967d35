#pragma once
// Safe motion of a robot program (docs/cell.md): the robot leaves and returns to its home
// joints, reaches each view from an approach pose back along the view's axis and leaves
// it the same way, and every move between is joint-interpolated and checked for
// collisions; a move that collides is lifted over the part through via points, or goes by
// a path searched for in joint space, or is named as one that could not be cleared.

#include <scanplan/robot/cell.h>
#include <scanplan/robot/program.h>
#include <scanplan/scanner/sensor.h>

#include <cmath>
#include <optional>
#include <vector>

namespace scanplan {

// The joint-interpolated move from `from` to `to` (the table turning with it), sampled
// so that no point of the robot or the scanner moves more than
// collisions.sampleSpacing() / `finer` against the part between samples (by
// collisions.travelBound); both ends included.
std::vector<CellPose> sampledMove(const CellCollisions& collisions, const CellPose& from,
                                  const CellPose& to, int finer = 1);

// True when no sample of the move collides.
bool moveIsClear(const CellCollisions& collisions, const CellPose& from, const CellPose& to);

// Adds to `program` its home (cell.home, or one computed clear above the part), each view's
// approach (cell.approach mm back along the view's axis, clear of everything, the move to
// the view clear too) and the via points of the moves between: the table turns with the
// arm standing still where the whole turn is clear, and where a direct move collides, the
// arm goes straight up to `lift` mm above the highest point of the scene and across, else
// the view is taken by another of its solutions, else a path is searched for in joint space
// (docs/cell.md). Moves still colliding are listed in program.uncleared.
void planMotion(RobotProgram& program, const CellCollisions& collisions, double lift);

// How far above the scene's highest point via points go: the mount, the scanner's body
// and its margin, and the cell's clearance, mm.
double viaLift(const Cell& cell, const Scanner& scanner);

// The program's travel time, seconds, by moveTime: home, vias, approaches, views and back
// home.
double programSeconds(const RobotProgram& program);

// The robot program's motion with a cell: the joint travel of the whole program, seconds
// (home, approaches, views, retracts, via points, back home), and the moves that collide
// and could not be lifted clear.
struct CellMotion {
  double seconds = 0;
  std::vector<RobotMove> uncleared;
};

// Seconds from one cell pose to the next: the slowest joint, or the table, each by its
// speed and acceleration (robot/cycle.h, moveSeconds).
double moveTime(const Cell& cell, const CellPose& a, const CellPose& b);

// The joint motion of a sequence of cell poses: the largest change of any joint between
// consecutive reached views (radians), the travel time (seconds, by moveTime) and how
// often the table turns.
struct JointMotion {
  double max_step = 0;
  int max_step_joint = 0;  // 1-based
  double seconds = 0;
  std::size_t table_moves = 0;
  std::size_t unreached = 0;  // views the cell cannot reach
};
JointMotion jointMotion(const Cell& cell, const std::vector<std::optional<CellPose>>& poses,
                        const std::vector<View>& views, const std::vector<int>& order);

}  // namespace scanplan
