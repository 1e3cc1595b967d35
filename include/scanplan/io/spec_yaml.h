#pragma once
// The inspection spec as YAML (docs/spec.md), in millimetres and degrees.

#include <scanplan/plan/plan.h>
#include <scanplan/spec/spec.h>

#include <string>

namespace scanplan {

// Reads and validates a spec (not yet against a part: see resolveSpec), with
// the control points of its points tasks.
// \throw InputError naming the file and the key that is wrong.
Spec loadSpec(const std::string& path);

// The same for a spec's text (YAML, or JSON, which is YAML too); errors name `source`, and
// the files it names are relative to the folder of `source` (else the current one).
Spec specFromText(const std::string& text, const std::string& source);

// The spec `plan` was made with, as it was read then (Plan::spec), else the default one:
// what the commands reading a plan take when given no spec. \throw InputError naming
// `plan_file` when the spec's text no longer reads (its files are checked where used).
Spec planSpec(const Plan& plan, const std::string& plan_file);

}  // namespace scanplan
