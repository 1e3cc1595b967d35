#pragma once
// scanplan inspect: a virtual inspection of a plan (docs/capability.md, "Virtual
// inspection"). Per Monte Carlo run, every registered view's cloud is simulated with the
// scanner's noise and acceptance errors, moved by a draw of its registration error, and
// merged in its setup's frame; each characteristic is then evaluated from the points by
// its definition, against a datum reference frame fitted to its datum features.

#include <scanplan/cad/part.h>
#include <scanplan/core/progress.h>
#include <scanplan/plan/inspection.h>
#include <scanplan/plan/plan.h>
#include <scanplan/spec/spec.h>

#include <cstdint>
#include <span>
#include <vector>

namespace scanplan {

struct InspectionOptions {
  int runs = 20;  // with `precision`, the most runs
  // The simulated points' spacing at the standoff, mm; each stands for the mean of the
  // scanner's points around it, its noise so much less. 0: evaluationSpacing()
  // (`planner.evaluation_spacing`, or a hundredth of the field's height).
  double spacing = 0;
  std::uint64_t seed = 1;
  std::vector<Deviation> deviations;
  // How each run places the views registered by ICP: Drawn, by a draw of the capability
  // model's covariance of that link; Registered, by ICP of the run's simulated cloud onto
  // the surface the view it registers to measured (slower; independent of the model's ICP
  // covariance, and shows ICP's false minima: docs/capability.md, "Virtual inspection").
  enum class IcpLinks { Drawn, Registered };
  IcpLinks icp = IcpLinks::Drawn;
  // 0: `runs` runs. Else runs until every characteristic evaluated has its U + |bias| known
  // within this share of itself at 95 % (spreadPrecision), checked every kPrecisionBatch
  // runs from kLeastRuns on, at most `runs`.
  double precision = 0;
};

// Runs between the checks of InspectionOptions::precision, and the fewest it checks.
inline constexpr int kPrecisionBatch = 10;
inline constexpr int kLeastRuns = 20;
// The most runs of an inspection run until precise, where the caller names no other.
inline constexpr int kMostPreciseRuns = 1000;

// U + |bias| of `values`, measured on a part of value `true_value`: twice their standard
// deviation (k = 2) and their mean's distance from it.
double spreadOf(std::span<const double> values, double true_value);

// The half-width of the 95 % interval the runs' finite number leaves on spreadOf (the
// numerical tolerance of a Monte Carlo result, GUM Supplement 1, 7.9): twice its standard
// deviation over kResamples bootstrap resamples of `values`, drawn from `seed`.
inline constexpr int kResamples = 400;
double spreadPrecision(std::span<const double> values, double true_value, std::uint64_t seed);

// \throw InputError when a deviation names a face the part does not have, or a diameter
// change a face that is not a cylinder; or the options are out of range.
Inspection inspectPlan(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                       const InspectionOptions& options, const Progress& progress = {});

}  // namespace scanplan
