#pragma once
// An interpolated patch as a file (docs/sweep.md): STEP or BREP.

#include <scanplan/cad/patch.h>

#include <string>

namespace scanplan {

// Writes the patch's faces, in the part frame, as STEP (.step, .stp) or BREP (.brep).
// \throw OutputError when the file cannot be written or its extension is neither.
void writePatch(const PatchShape& patch, const std::string& path);

}  // namespace scanplan
