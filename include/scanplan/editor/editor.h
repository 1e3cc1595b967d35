#pragma once
// The inspection-spec editor (docs/spec-editor.md).

#include <scanplan/cad/part.h>

#include <string>

namespace scanplan {

// Writes the inspection-spec editor of `part`: a self-contained page, in the report's
// style, where faces are picked for tasks and roles, control points are clicked onto the
// exact faces, and spec.yaml and points.csv are downloaded. It starts from `spec_file`
// when given ("" for a new spec).
// \throw InputError for a spec that does not read or names what the part lacks;
//        OutputError when the page cannot be written.
void writeSpecEditor(const Part& part, const std::string& spec_file, const std::string& path);

}  // namespace scanplan
