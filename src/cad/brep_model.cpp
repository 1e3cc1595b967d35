#include "cad/brep_model.h"

#include <scanplan/core/errors.h>

#include <tbb/parallel_for.h>
#include <BRepAdaptor_Surface.hxx>
#include <BRepGProp.hxx>
#include <BRepMesh_IncrementalMesh.hxx>
#include <BRep_Tool.hxx>
#include <GProp_GProps.hxx>
#include <IMeshTools_Parameters.hxx>
#include <Poly_Triangulation.hxx>
#include <ShapeFix_Shell.hxx>
#include <TopExp.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>
#include <TopoDS_Shell.hxx>

#include <cmath>

namespace scanplan::detail {

TopoDS_Face BRepModel::outwardFace(int id) const {
  TopoDS_Face face = TopoDS::Face(faces(id));
  return reversed[id - 1] ? TopoDS::Face(face.Reversed()) : face;
}

namespace {

SurfaceType surfaceType(const TopoDS_Face& face) {
  switch (BRepAdaptor_Surface(face, false).GetType()) {
    case GeomAbs_Plane: return SurfaceType::Plane;
    case GeomAbs_Cylinder: return SurfaceType::Cylinder;
    case GeomAbs_Cone: return SurfaceType::Cone;
    case GeomAbs_Sphere: return SurfaceType::Sphere;
    case GeomAbs_Torus: return SurfaceType::Torus;
    case GeomAbs_BezierSurface: return SurfaceType::Bezier;
    case GeomAbs_BSplineSurface: return SurfaceType::BSpline;
    case GeomAbs_SurfaceOfRevolution: return SurfaceType::Revolution;
    case GeomAbs_SurfaceOfExtrusion: return SurfaceType::Extrusion;
    case GeomAbs_OffsetSurface: return SurfaceType::Offset;
    default: return SurfaceType::Other;
  }
}

// A shell and the solid it bounds (-1 for a free shell).
struct ShellRef {
  TopoDS_Shape shell;
  int solid;
};

std::vector<ShellRef> collectShells(const TopoDS_Shape& shape,
                                    const TopTools_IndexedMapOfShape& solids) {
  std::vector<ShellRef> shells;
  for (int s = 1; s <= solids.Extent(); ++s)
    for (TopExp_Explorer it(solids(s), TopAbs_SHELL); it.More(); it.Next())
      shells.push_back({it.Current(), s - 1});
  for (TopExp_Explorer it(shape, TopAbs_SHELL, TopAbs_SOLID); it.More(); it.Next())
    shells.push_back({it.Current(), -1});
  return shells;
}

// Makes the faces of each shell consistently oriented (ShapeFix_Shell), recording in
// `reversed` the faces whose orientation had to change.
void fixShellOrientation(const std::vector<ShellRef>& shells,
                         const TopTools_IndexedMapOfShape& faces, std::vector<bool>& reversed) {
  for (const ShellRef& ref : shells) {
    ShapeFix_Shell fix;
    if (!fix.FixFaceOrientation(TopoDS::Shell(ref.shell), true, false)) continue;
    for (TopExp_Explorer it(fix.Shape(), TopAbs_FACE); it.More(); it.Next()) {
      int id = faces.FindIndex(it.Current());
      if (id > 0) reversed[id - 1] = it.Current().Orientation() != faces(id).Orientation();
    }
  }
}

// Appends the triangulation of face `id` to the mesh, wound outward.
void appendFaceTriangles(const BRepModel& model, int id, Face& face, TriangleMesh& mesh) {
  TopoDS_Face f = model.outwardFace(id);
  TopLoc_Location location;
  Handle(Poly_Triangulation) tri = BRep_Tool::Triangulation(f, location);
  face.first_triangle = static_cast<int>(mesh.triangles.size());
  face.triangle_count = 0;
  if (tri.IsNull()) return;
  const gp_Trsf& trsf = location.Transformation();
  const int base = static_cast<int>(mesh.vertices.size());
  for (int i = 1; i <= tri->NbNodes(); ++i) {
    gp_Pnt p = tri->Node(i).Transformed(trsf);
    mesh.vertices.emplace_back(p.X(), p.Y(), p.Z());
    face.bounds.add(mesh.vertices.back());
  }
  const bool flip = f.Orientation() == TopAbs_REVERSED;
  for (int i = 1; i <= tri->NbTriangles(); ++i) {
    int a, b, c;
    tri->Triangle(i).Get(a, b, c);
    if (flip) std::swap(b, c);
    mesh.triangles.emplace_back(base + a - 1, base + b - 1, base + c - 1);
    mesh.triangle_faces.push_back(id);
  }
  face.triangle_count = tri->NbTriangles();
}

void flipFace(Face& face, TriangleMesh& mesh) {
  for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t)
    std::swap(mesh.triangles[t][1], mesh.triangles[t][2]);
}

// Closed shells of a solid must enclose positive volume (the outer one, the largest) or
// negative volume (voids); flips whole shells whose mesh says otherwise.
void fixSolidOrientation(const std::vector<ShellRef>& shells, BRepModel& model, Part& part) {
  std::vector<std::vector<int>> shell_faces(shells.size());
  std::vector<double> volume(shells.size(), 0.0);
  for (std::size_t k = 0; k < shells.size(); ++k) {
    TopTools_IndexedMapOfShape shell_map;
    TopExp::MapShapes(shells[k].shell, TopAbs_FACE, shell_map);
    for (int i = 1; i <= shell_map.Extent(); ++i) {
      int id = model.faces.FindIndex(shell_map(i));
      if (id <= 0) continue;
      shell_faces[k].push_back(id);
      const Face& face = part.faces[id - 1];
      for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
        const Vec3i& tri = part.mesh.triangles[t];
        const auto& v = part.mesh.vertices;
        volume[k] += v[tri[0]].dot(v[tri[1]].cross(v[tri[2]])) / 6.0;
      }
    }
  }
  for (int s = 0; s < static_cast<int>(part.solids.size()); ++s) {
    int outer = -1;
    for (std::size_t k = 0; k < shells.size(); ++k)
      if (shells[k].solid == s && (outer < 0 || std::abs(volume[k]) > std::abs(volume[outer])))
        outer = static_cast<int>(k);
    for (std::size_t k = 0; k < shells.size(); ++k) {
      if (shells[k].solid != s) continue;
      bool want_positive = static_cast<int>(k) == outer;
      if ((volume[k] > 0) == want_positive || volume[k] == 0) continue;
      for (int id : shell_faces[k]) {
        model.reversed[id - 1] = !model.reversed[id - 1];
        flipFace(part.faces[id - 1], part.mesh);
      }
    }
  }
}

}  // namespace

void buildFromShape(Part& part, const TopoDS_Shape& shape, double linear_deflection,
                    double angular_deflection_rad, const Progress& progress) {
  auto model = std::make_shared<BRepModel>();
  model->shape = shape;
  TopExp::MapShapes(shape, TopAbs_FACE, model->faces);
  const int face_count = model->faces.Extent();
  if (face_count == 0) throw InputError(part.file, "no faces: the file holds no surface geometry");
  model->reversed.assign(face_count, false);

  TopTools_IndexedMapOfShape solids;
  TopExp::MapShapes(shape, TopAbs_SOLID, solids);
  std::vector<ShellRef> shells = collectShells(shape, solids);
  report(progress, "orienting faces", 0);
  fixShellOrientation(shells, model->faces, model->reversed);

  report(progress, "meshing", 0);
  IMeshTools_Parameters params;
  params.Deflection = linear_deflection;
  params.Angle = angular_deflection_rad;
  params.InParallel = true;
  BRepMesh_IncrementalMesh mesher(shape, params);
  part.linear_deflection = linear_deflection;
  part.angular_deflection = angular_deflection_rad;
  report(progress, "meshing", 1);

  report(progress, "measuring faces", 0);
  part.faces.assign(face_count, Face{});
  tbb::parallel_for(1, face_count + 1, [&](int id) {
    const TopoDS_Face& f = TopoDS::Face(model->faces(id));
    Face& face = part.faces[id - 1];
    face.id = id;
    face.type = surfaceType(f);
    GProp_GProps props;
    BRepGProp::SurfaceProperties(f, props, false, face.type == SurfaceType::BSpline);
    face.area = props.Mass();
  });
  for (int id = 1; id <= face_count; ++id)
    appendFaceTriangles(*model, id, part.faces[id - 1], part.mesh);

  part.solids.resize(solids.Extent());
  tbb::parallel_for(1, solids.Extent() + 1, [&](int s) {
    GProp_GProps props;
    BRepGProp::VolumeProperties(solids(s), props);
    part.solids[s - 1].volume = std::abs(props.Mass());
  });
  for (int s = 1; s <= solids.Extent(); ++s) {
    Solid& solid = part.solids[s - 1];
    TopTools_IndexedMapOfShape solid_faces;
    TopExp::MapShapes(solids(s), TopAbs_FACE, solid_faces);
    for (int i = 1; i <= solid_faces.Extent(); ++i) {
      int id = model->faces.FindIndex(solid_faces(i));
      solid.faces.push_back(id);
      if (part.faces[id - 1].solid < 0) part.faces[id - 1].solid = s - 1;
    }
  }
  fixSolidOrientation(shells, *model, part);
  for (int id = 1; id <= face_count; ++id) part.faces[id - 1].reoriented = model->reversed[id - 1];
  report(progress, "measuring faces", 1);

  int untriangulated = 0;
  for (const Face& face : part.faces) untriangulated += face.triangle_count == 0;
  if (untriangulated > 0)
    part.warnings.push_back(std::to_string(untriangulated) +
                            " face(s) could not be triangulated and are invisible to ray casting");
  part.brep = std::move(model);
}

}  // namespace scanplan::detail
