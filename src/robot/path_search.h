#pragma once
// A clear joint path searched for where the via points over the scene fail (robot/motion.h):
// OMPL's RRT-Connect in the arm's joint space within its working range, the table held at
// one angle, each configuration checked with the cell's collision model and each move
// between two sampled as moveIsClear samples it. The path found is shortened: from each
// corner, straight on to the farthest later one the move to which is clear.

#include <scanplan/robot/cell.h>

#include <optional>
#include <vector>

namespace scanplan::detail {

// Steps of the search before it gives up: a count, so that a search finds the same path on
// every machine and under any load. Each step reaches at most kSearchStepLength (radians, over
// the six joints together) towards a sampled configuration, then as far as it can towards
// the other tree.
inline constexpr unsigned kMostSearchSteps = 1000;
inline constexpr double kSearchStepLength = 0.5;

// The via points (both ends left out) of a clear joint path from `from` to `to`, at
// `from`'s table angle; none when the ends collide or the search finds no path within
// kMostSearchSteps steps. The same path for the same ends on every run.
std::optional<std::vector<CellPose>> searchedPath(const Cell& cell,
                                                  const CellCollisions& collisions,
                                                  const CellPose& from, const CellPose& to);

}  // namespace scanplan::detail
