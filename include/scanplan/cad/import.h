#pragma once
// Reading a part from a CAD or mesh file.

#include <scanplan/cad/part.h>
#include <scanplan/core/progress.h>

#include <string>

namespace scanplan {

struct ImportOptions {
  double linear_deflection = 0;       // chordal tolerance of the mesh, mm; 0: chosen from size
  double relative_deflection = 5e-4;  // automatic chordal tolerance / bounding-box diagonal
  double angular_deflection = 20;     // largest angle between adjacent mesh normals, degrees
  double sharp_angle = 30;            // meshes without groups split into faces at edges whose
                                      // dihedral angle exceeds this, degrees
  double mesh_unit = 1;               // millimetres per unit of a mesh file (meshes carry none)
  bool read_gdt = true;               // read AP242 semantic PMI from STEP files
};

// Reads a part from `path`: STEP (.step/.stp, AP203/214/242), IGES (.iges/.igs), OCCT
// BREP (.brep), or a triangle mesh (.stl ASCII or binary, .obj, .ply, .off).
// The result is in millimetres whatever unit the file declares. Several solids make one
// part. B-Rep faces get outward orientation (repaired where a shell is inconsistent) and
// a triangulation whose chordal tolerance follows the part size unless given. OCCT's
// messages are silenced (its default messenger loses its printers on the first call).
// \throw InputError for a missing or unreadable file, an unsupported extension, a
//        truncated or corrupt file, or a file without geometry or triangles.
Part importPart(const std::string& path, const ImportOptions& options = {},
                const Progress& progress = {});

}  // namespace scanplan
