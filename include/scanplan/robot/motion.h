#pragma once
// Safe motion of a robot program (docs/cell.md): the robot leaves and returns to its home
// joints, reaches each view from an approach pose back along the view's axis and leaves
// it the same way, and every move between is joint-interpolated and checked for
// collisions; a move that collides is lifted over the part through via points, or named
// as one that could not be cleared.

#include <scanplan/robot/cell.h>
#include <scanplan/robot/program.h>

#include <vector>

namespace scanplan {

// The joint-interpolated move from `from` to `to` (the table turning with it), sampled
// so that no joint (nor the table) turns more than `step` radians between samples; both
// ends included.
std::vector<CellPose> sampledMove(const CellPose& from, const CellPose& to, double step);

// True when no sample of the move collides.
bool moveIsClear(const CellCollisions& collisions, const CellPose& from, const CellPose& to,
                 double step);

// Adds to `program` its home, each view's approach (cell.approach mm back along the view's
// axis, clear of everything, the move to the view clear too) and the via points of the
// moves between: where a direct move collides, the arm goes up to `lift` mm above the
// highest point of the scene and across. Moves still colliding are listed in
// program.uncleared.
void planMotion(RobotProgram& program, const CellCollisions& collisions, double lift);

// How far above the scene's highest point via points go: the mount, the scanner's body
// and its margin, and the cell's clearance, mm.
double viaLift(const Cell& cell, const Scanner& scanner);

// The program of `plan` in `cell` (robotProgram, the cell poses `poses`) with its safe
// motion (planMotion, lifted by viaLift).
RobotProgram safeProgram(const Plan& plan, const Cell& cell, const CellCollisions& collisions,
                         const std::vector<std::optional<CellPose>>& poses, const std::string& name,
                         const std::string& source);

// The program's joint travel time, seconds: home, vias, approaches, views and back home.
double programSeconds(const RobotProgram& program);

}  // namespace scanplan
