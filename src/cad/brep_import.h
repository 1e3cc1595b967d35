#pragma once
// Private entry points of the importers, dispatched by importPart() on the extension.

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>

#include <Standard_Failure.hxx>

namespace scanplan::detail {

// STEP, IGES ("STEP", "IGES") through XDE, or OCCT BREP ("BREP").
Part importBRep(const std::string& path, const std::string& format, const ImportOptions& options,
                const Progress& progress);

// The error naming `path` for a failure inside the CAD kernel.
InputError kernelError(const std::string& path, const Standard_Failure& failure);

// STL, OBJ, PLY, OFF triangle meshes ("STL", "OBJ", "PLY", "OFF").
Part importMesh(const std::string& path, const std::string& format, const ImportOptions& options,
                const Progress& progress);

}  // namespace scanplan::detail
