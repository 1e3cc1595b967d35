#pragma once
// The inspection spec as YAML (docs/spec.md), in millimetres and degrees.

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

}  // namespace scanplan
