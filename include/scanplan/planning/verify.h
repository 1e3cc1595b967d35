#pragma once
// Checking a plan again on its part: coverage, registration and sequence (scanplan verify).

#include <scanplan/cad/part.h>
#include <scanplan/core/progress.h>
#include <scanplan/planning/planner.h>
#include <scanplan/spec/spec.h>

#include <cstddef>

namespace scanplan {

// How the samples of a plan lie on a part, placed as the plan says: how far the farthest
// lies from its face's surface where that is elementary (a plane, cylinder, cone, sphere or
// torus) and from its face's triangles, and how many lie farther than allowed from either,
// or on a face the part does not have.
struct PartFit {
  std::size_t samples = 0, off = 0;
  double exact_farthest = 0, mesh_farthest = 0;  // mm
  double exact_tolerance = 0;                    // mm
  double mesh_tolerance = 0;  // mm: a few times the chordal tolerance of the part's mesh
};
PartFit partFit(const Plan& plan, const Part& part);

// What `scanplan verify` finds when it checks a plan again on its part.
struct PlanCheck {
  Plan plan;  // the plan with measured_by, registration and path length recomputed
  PartFit part;
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

// How the plan's samples lie on `part`, which is the part the plan was made for.
// \throw InputError naming the part's file when it is not: it has another count of faces,
// or samples of the plan lie off their faces on it (a part changed since the plan was
// made, or another one with as many faces).
PartFit checkPlanPart(const Plan& plan, const Part& part);

// Simulates every view of `plan` on its samples again, checks the registration of its
// views (no bridging) and walks its sequence, with the part placed as the plan says and
// the spec's specular faces, markers (else the plan's) and registration thresholds (its
// method, else the plan's). A plan made without registration has none checked.
// \throw InputError when the part is not the plan's (checkPlanPart).
PlanCheck verifyPlan(const Plan& plan, const Part& part, const Spec& spec,
                     const PlanningOptions& options = {}, const Progress& progress = {});

}  // namespace scanplan
