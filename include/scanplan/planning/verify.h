#pragma once
// Checking a plan again on its part: coverage, registration and sequence (scanplan verify).

#include <scanplan/cad/part.h>
#include <scanplan/core/progress.h>
#include <scanplan/planning/planner.h>
#include <scanplan/spec/spec.h>

#include <cstddef>

namespace scanplan {

// What `scanplan verify` finds when it checks a plan again on its part.
struct PlanCheck {
  Plan plan;  // the plan with measured_by, registration and path length recomputed
  std::size_t coverage_differences = 0;  // samples whose measured_by differs from the file's
  // Views whose registration state differs, or whose claimed link (registered to a view by
  // markers or ICP) is no pair the check finds registrable.
  std::size_t registration_differences = 0;
  std::size_t sequence_missing = 0;  // views not in the sequence, or in it more than once
  std::size_t sequence_breaks = 0;   // registered views that follow no view they register to
  std::size_t unregistered = 0;      // views that register to nothing, as checked again
  // The plan requires its views to register (it was planned with registration and
  // `registration.required`); then an unregistered view fails it.
  bool registration_required = false;
  bool holds() const {
    return coverage_differences == 0 && registration_differences == 0 && sequence_missing == 0 &&
           (!registration_required || unregistered == 0);
  }
};

// Simulates every view of `plan` on its samples again, checks the registration of its
// views (no bridging) and walks its sequence, with the part placed as the plan says and
// the spec's specular faces, markers (else the plan's) and registration thresholds (its
// method, else the plan's). A plan made without registration has none checked.
// \throw InputError when the part does not match the plan (face count).
PlanCheck verifyPlan(const Plan& plan, const Part& part, const Spec& spec,
                     const PlanningOptions& options = {}, const Progress& progress = {});

}  // namespace scanplan
