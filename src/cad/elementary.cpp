// Elementary surfaces of B-Rep faces, read from OCCT's adaptor.

#include "cad/brep_model.h"

#include <scanplan/cad/elementary.h>

#include <BRepAdaptor_Surface.hxx>

namespace scanplan {
namespace {

Vec3 point(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }
Vec3 direction(const gp_Dir& d) { return {d.X(), d.Y(), d.Z()}; }

}  // namespace

std::optional<ElementarySurface> elementarySurface(const Part& part, int id) {
  if (!part.brep) return std::nullopt;
  const TopoDS_Face face = part.brep->outwardFace(id);
  const BRepAdaptor_Surface s(face);
  ElementarySurface e;
  switch (s.GetType()) {
    case GeomAbs_Plane: {
      gp_Dir normal = s.Plane().Axis().Direction();
      if (face.Orientation() == TopAbs_REVERSED) normal.Reverse();
      e.type = SurfaceType::Plane;
      e.origin = point(s.Plane().Location());
      e.axis = direction(normal);
      return e;
    }
    case GeomAbs_Cylinder:
      e.type = SurfaceType::Cylinder;
      e.origin = point(s.Cylinder().Location());
      e.axis = direction(s.Cylinder().Axis().Direction());
      e.radius = s.Cylinder().Radius();
      return e;
    case GeomAbs_Cone:
      e.type = SurfaceType::Cone;
      e.origin = point(s.Cone().Location());
      e.axis = direction(s.Cone().Axis().Direction());
      e.radius = s.Cone().RefRadius();
      e.semi_angle = s.Cone().SemiAngle();
      return e;
    case GeomAbs_Sphere:
      e.type = SurfaceType::Sphere;
      e.origin = point(s.Sphere().Location());
      e.radius = s.Sphere().Radius();
      return e;
    case GeomAbs_Torus:
      e.type = SurfaceType::Torus;
      e.origin = point(s.Torus().Location());
      e.axis = direction(s.Torus().Axis().Direction());
      e.radius = s.Torus().MajorRadius();
      e.minor_radius = s.Torus().MinorRadius();
      return e;
    default: return std::nullopt;
  }
}

}  // namespace scanplan
