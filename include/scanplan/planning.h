#pragma once
// Planning, all of it: the planner (planning/planner.h), the plan it makes (plan/plan.h),
// the poses it tries (planning/poses.h), the sweeps' tiles (planning/sweep_tiles.h), the
// bridging views (planning/bridging.h), the cell's joints for its views
// (planning/cell_poses.h) and the robot's steps (planning/robot_steps.h), the check of a
// plan on its part (planning/verify.h) and the exact set cover (solve/set_cover.h).

#include <scanplan/plan/plan.h>
#include <scanplan/planning/bridging.h>
#include <scanplan/planning/cell_poses.h>
#include <scanplan/planning/planner.h>
#include <scanplan/planning/poses.h>
#include <scanplan/planning/robot_steps.h>
#include <scanplan/planning/sweep_tiles.h>
#include <scanplan/planning/verify.h>
#include <scanplan/solve/set_cover.h>
