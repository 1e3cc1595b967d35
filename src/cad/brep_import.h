#pragma once
// Private entry points of the importers, dispatched by importPart() on the extension.

#include <scanplan/cad/import.h>

namespace scanplan::detail {

// STEP, IGES ("STEP", "IGES") through XDE, or OCCT BREP ("BREP").
Part importBRep(const std::string& path, const std::string& format, const ImportOptions& options,
                const Progress& progress);

// STL, OBJ, PLY, OFF triangle meshes ("STL", "OBJ", "PLY", "OFF").
Part importMesh(const std::string& path, const std::string& format, const ImportOptions& options,
                const Progress& progress);

}  // namespace scanplan::detail
