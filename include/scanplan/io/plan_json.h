#pragma once
// plan.json (DESIGN.md §7): the contract with everything downstream.

#include <scanplan/planning.h>

#include <nlohmann/json.hpp>

#include <string>

namespace scanplan {

// The plan as JSON: every field §7 requires (format, version, units, part, scanner,
// views, sequence, samples with measured_by, summary) plus `not_coverable` reasons and
// stage times. Views carry `registration: null` until registration is checked.
nlohmann::json planJson(const Plan& plan);

// Writes planJson(plan) to `path` through a temporary file renamed into place.
// \throw OutputError when it cannot be written.
void writePlan(const Plan& plan, const std::string& path);

}  // namespace scanplan
