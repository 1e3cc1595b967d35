#pragma once
// Can the plan verify each characteristic? (docs/capability.md) What its views measure of
// the characteristic's faces: the covered share of their area, the points and their
// density, the largest gap, and the expanded uncertainty U of the characteristic's value
// from the scanner's noise at each point's distance and incidence (Monte Carlo), against
// the tolerance's width.

#include <scanplan/cad/gdt.h>
#include <scanplan/cad/part.h>
#include <scanplan/plan/plan.h>
#include <scanplan/spec/spec.h>

#include <vector>

namespace scanplan {

// The share of its faces' area a capable characteristic has measured, and of its datum
// features' area (to fit its datum reference frame).
constexpr double kCoveredEnough = 0.9;
constexpr double kDatumsCoveredEnough = 0.5;

// The spacing at the standoff of the points a characteristic is read from, mm: each the
// mean of the scanner's points around it, as an inspection's software filters a scan. The
// noise left on them widens a zone read from points (docs/capability.md, "Error budget"),
// and the virtual inspection lays its points so far apart unless told otherwise.
// `planner.evaluation_spacing`, or a hundredth of the field's height; at most the field's.
double evaluationSpacing(const Scanner& scanner, const CapabilityOptions& options);

// The capability of each of `characteristics` under the views of `plan` (each in its own
// orientation's placement), with the simulation, the capability options
// (planner.capable_ratio) and the seed `spec` sets.
std::vector<Capability> capabilities(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                                     const std::vector<Characteristic>& characteristics);

// The capability of each characteristic, and how many of them the plan's first views make
// capable: the trade-off of capability against views and cycle time, at `points` counts of
// views spread up to all of them (0: none). The last count is the plan's own, judged as
// `capabilities`; the others with a quarter of the Monte Carlo draws, a view whose
// registration runs through a later view registering to nothing. No counts for a plan of
// several rest orientations.
struct CapabilityJudgement {
  std::vector<Capability> capabilities;
  std::vector<CapableCount> by_views;
};
CapabilityJudgement judgeCapability(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                                    const std::vector<Characteristic>& characteristics,
                                    std::size_t points = 8);

}  // namespace scanplan
