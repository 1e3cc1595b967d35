#pragma once
// plan.json (docs/design.md §7): the contract with everything downstream.

#include <scanplan/plan/plan.h>

#include <nlohmann/json.hpp>

#include <string>

namespace scanplan {

// The version of plan.json this scanplan writes. Version 2 adds the cycle time
// (summary.cycle) and the cell's accelerations; version 1 plans read without them.
// Version 3 names a characteristic's error budget too large for its tolerance
// `too_uncertain`, whatever its sources, where versions 1 and 2 said `too_noisy`.
// Version 4 holds the spec the plan was made with (`spec`: its file and text), which the
// commands reading a plan take when given none; earlier plans read without it.
constexpr int kPlanVersion = 4;

// The plan as JSON: every field §7 requires (format, version, units, part, scanner,
// views, sequence, samples with measured_by, summary) plus `not_coverable` reasons and
// stage times; with registration, each view's registration and bridge flag, the
// checked pairs and the markers, and the sequence.
nlohmann::json planJson(const Plan& plan);

// One GD&T characteristic as plan.json gives it: id, kind, dimension, value, limits, datums
// and faces (without its capability).
nlohmann::json characteristicJson(const Characteristic& characteristic);

// Writes planJson(plan) to `path` through a temporary file renamed into place, the part's
// file relative to the plan's folder (its absolute path beside it).
// \throw OutputError when it cannot be written.
void writePlan(const Plan& plan, const std::string& path);

class FileSet;

// Writes `plan` to `path` with the surface task's interpolated patches beside it (each
// sweep's patch as its patch_file names it); an earlier plan's patch files there are
// removed. The files go into `outputs`, for the caller to commit with its other
// files, or else are written here as a set: all of them or none.
// \throw OutputError naming the file that cannot be written.
void writePlanFiles(const Plan& plan, const std::string& path, FileSet* outputs = nullptr);

// Reads a plan.json back: part file (resolved as docs/design.md §7 says) and faces, placement,
// scanner (every §4 parameter the file gives, over the defaults), views with their bridge flags,
// markers, samples with measured_by and not_coverable reasons, and the sequence. Registration
// results and times are not read: they are what `scanplan verify` checks again. \throw InputError
// naming the file and the field that is missing or wrong.
Plan readPlan(const std::string& path);

}  // namespace scanplan
