#pragma once
// The plan summary table that `scanplan plan` and `scanplan verify` print.

#include <scanplan/planning.h>

namespace scanplan::cli {

// Model and fixture faces, target and measured samples, views, views registered,
// bridging views added and path length, one per line.
void printPlanSummary(const Plan& plan, const Part& part);

// The plan as the method's authors table their results (their Table 2): model and
// fixture faces, control points (or targets) and those acquired, views, alignable views.
void printResultsRow(const Plan& plan);

}  // namespace scanplan::cli
