#pragma once
// The imported part: faces with stable ids, their triangle mesh, and the GD&T read from
// the file. Produced by importPart() (cad/import.h); every later stage reads it.

#include <scanplan/cad/gdt.h>
#include <scanplan/cad/mesh.h>
#include <scanplan/core/geometry.h>

#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace scanplan {

enum class SurfaceType {
  Plane,
  Cylinder,
  Cone,
  Sphere,
  Torus,
  BSpline,
  Bezier,
  Revolution,
  Extrusion,
  Offset,
  Other,
  Mesh  // Mesh: a face of a triangle-mesh input
};
std::string_view toString(SurfaceType type);

struct Color {
  float r = 0, g = 0, b = 0;  // linear RGB in [0, 1]
};

// One face of the part. Faces of a B-Rep are numbered in TopExp::MapShapes order over
// the imported shape (docs/design.md §3); faces of a mesh by group or sharp-edge region.
struct Face {
  int id = 0;  // 1-based
  SurfaceType type = SurfaceType::Other;
  double area = 0;             // mm², of the exact surface (B-Rep) or the triangles
  Box bounds;                  // mm, part frame
  int solid = -1;              // index into Part::solids; -1 when in no solid
  bool reoriented = false;     // its orientation was flipped to point outward on import
  std::string name;            // from the file (STEP/IGES name or mesh group), may be empty
  std::optional<Color> color;  // surface colour from the file
  int first_triangle = 0;      // its triangles in Part::mesh: [first, first + count)
  int triangle_count = 0;
};

// A solid (or, for shells and free faces, a body) of the part.
struct Solid {
  std::string name;        // product or instance name from the file, may be empty
  double volume = 0;       // mm³ (exact for B-Rep solids, 0 for open bodies)
  std::vector<int> faces;  // 1-based face ids
};

namespace detail {
struct BRepModel;  // OCCT shape and face map, defined in src/cad/brep_model.h
}

struct Part {
  std::string file;       // the file it was read from
  std::string format;     // "STEP", "IGES", "BREP", "STL", "OBJ", "PLY", "OFF"
  std::string file_unit;  // length unit the file declares ("mm", "inch", "m"), or ""
  double unit_scale = 1;  // millimetres per file unit, applied on import
  std::vector<Solid> solids;
  std::vector<Face> faces;  // faces[i].id == i + 1
  TriangleMesh mesh;        // all faces, outward, mm
  Gdt gdt;
  double linear_deflection = 0;       // chordal tolerance used for the mesh, mm
  double angular_deflection = 0;      // angular tolerance used for the mesh, radians
  std::vector<std::string> warnings;  // things the user should know about the import

  // The B-Rep behind the faces (NURBS surfaces, trims); null for mesh input.
  std::shared_ptr<const detail::BRepModel> brep;

  Box bounds() const;
  double area() const;
  double volume() const;  // sum of solid volumes, mm³

  // The face with this id. \throw InputError naming the part when the id is unknown.
  const Face& face(int id) const;

  // The triangles of the given faces (all vertices kept). \throw InputError for an
  // unknown face id.
  TriangleMesh meshOf(const std::vector<int>& face_ids) const;
};

}  // namespace scanplan
