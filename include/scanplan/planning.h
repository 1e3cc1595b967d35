#pragma once
// Planning, all of it: the planner (planning/planner.h), the plan it makes
// (planning/plan.h), the poses it tries (planning/poses.h), the cell's joints for its
// views (planning/cell_poses.h), the check of a plan on its part (planning/verify.h) and
// the exact set cover (planning/set_cover.h).

#include <scanplan/planning/cell_poses.h>
#include <scanplan/planning/plan.h>
#include <scanplan/planning/planner.h>
#include <scanplan/planning/poses.h>
#include <scanplan/planning/set_cover.h>
#include <scanplan/planning/verify.h>
