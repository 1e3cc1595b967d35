#pragma once
// The self-contained HTML report of a plan (docs/report.md): its scene (report/scene.h) and
// the evidence the planning stages make for it (planning/evidence.h), inlined in one page;
// report/exports.h writes the other files seen beside it.

#include <scanplan/cad/part.h>
#include <scanplan/core/progress.h>
#include <scanplan/plan/plan.h>
#include <scanplan/planning/evidence.h>
#include <scanplan/report/exports.h>
#include <scanplan/report/scene.h>
#include <scanplan/spec/spec.h>

#include <string>

namespace scanplan {

// What the report shows beside the plan (planning/evidence.h).
using ReportOptions = EvidenceOptions;

// Writes the self-contained HTML report of `plan` on `part` (three.js inlined, opens from
// disk without network), with the evidence planning makes as `options` asks
// (reportEvidence). \throw OutputError when it cannot be written.
void writeReport(const Plan& plan, const Part& part, const Spec& spec, const std::string& path,
                 const ReportOptions& options = {}, const Progress& progress = {});
// The same with the spec already resolved against `part` (its fixture models read).
void writeReport(const Plan& plan, const Part& part, const ResolvedSpec& spec,
                 const std::string& path, const ReportOptions& options = {},
                 const Progress& progress = {});

// The page itself: the plan's scene and `evidence`, drawn as they are.
void writeReport(const Plan& plan, const Part& part, const ResolvedSpec& spec,
                 const ReportEvidence& evidence, const std::string& path);

}  // namespace scanplan
