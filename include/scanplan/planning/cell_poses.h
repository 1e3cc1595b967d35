#pragma once
// The cell's joints for the views of a plan (docs/cell.md): every inverse-kinematics
// solution of each view, and the joints chosen along the visiting order for the least
// joint travel.

#include <scanplan/plan/plan.h>
#include <scanplan/robot/cell.h>

#include <Eigen/Core>
#include <optional>
#include <vector>

namespace scanplan {

// Per view, every way the cell takes it: the inverse-kinematics solutions at the table
// angle nearest 0 that reaches it (with `collisions`, those whose arm stays clear), and
// the other turns of wide axes; empty where the cell cannot take the view.
using CellSolutions = std::vector<std::vector<CellPose>>;
CellSolutions cellSolutions(const Cell& cell, const std::vector<View>& views,
                            const CellCollisions* collisions = nullptr);

// The time to wind `pose`'s joints from their turns nearest 0 (within the working range)
// to where `pose` has them, seconds: 0 for joints within ±180°.
double unwindingTime(const Cell& cell, const CellPose& pose);

// How the cell takes each of `views` when they are visited in `order` (ids): of each
// view's `solutions`, the ones whose joints travel least from view to view over the whole
// order (dynamic programming), the first view's winding from the joints' turns nearest 0
// and the last one's unwinding back counted too, so that a program does not leave the
// wrist (and the scanner's cable) wound. Per view, in the order of `views`; none where the
// cell cannot take the view.
std::vector<std::optional<CellPose>> cellPoses(const Cell& cell, const std::vector<View>& views,
                                               const std::vector<int>& order,
                                               const CellSolutions& solutions);
// The same with the views' solutions computed.
std::vector<std::optional<CellPose>> cellPoses(const Cell& cell, const std::vector<View>& views,
                                               const std::vector<int>& order,
                                               const CellCollisions* collisions = nullptr);

// The cell's motion cost between every two views: the least joint travel time over their
// `solutions` (seconds; the cell's joint speeds, the table at a quarter turn per second),
// 1000 s to or from a view the cell cannot take.
Eigen::MatrixXd jointTravelTimes(const Cell& cell, const CellSolutions& solutions);

}  // namespace scanplan
