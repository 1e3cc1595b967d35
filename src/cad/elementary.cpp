// Elementary surfaces of B-Rep faces, read from OCCT's adaptor.

#include "cad/brep_model.h"

#include <scanplan/cad/elementary.h>

#include <BRepAdaptor_Surface.hxx>

#include <cmath>
#include <limits>

namespace scanplan {
namespace {

Vec3 point(const gp_Pnt& p) { return {p.X(), p.Y(), p.Z()}; }
Vec3 direction(const gp_Dir& d) { return {d.X(), d.Y(), d.Z()}; }

// The unit part of `v` across `axis`: any direction across it when `v` runs along it.
Vec3 across(const Vec3& v, const Vec3& axis) {
  const Vec3 r = v - v.dot(axis) * axis;
  if (r.norm() > 1e-12) return r.normalized();
  return axis.unitOrthogonal();
}

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

std::pair<Vec3, Vec3> nearestOn(const ElementarySurface& s, const Vec3& p) {
  const Vec3 from = p - s.origin;
  const double h = from.dot(s.axis);
  switch (s.type) {
    case SurfaceType::Cylinder: {
      const Vec3 out = across(from, s.axis);
      return {s.origin + h * s.axis + s.radius * out, out};
    }
    case SurfaceType::Cone: {
      // In the plane of the axis and `p`, a generator on each side of the axis, each through
      // (0, radius) on its side at the semi-angle (and on through the apex): the point of
      // the nearer nearest (h, r).
      const Vec3 out = across(from, s.axis);
      const double r = (from - h * s.axis).norm(), c = std::cos(s.semi_angle),
                   sn = std::sin(s.semi_angle);
      std::pair<Vec3, Vec3> best;
      double least = std::numeric_limits<double>::infinity();
      for (const double side : {1.0, -1.0}) {
        const double t = h * c + (side * r - s.radius) * sn;
        const Vec3 q = s.origin + t * c * s.axis + side * (s.radius + t * sn) * out;
        if ((p - q).norm() < least) {
          least = (p - q).norm();
          best = {q, side * c * out - sn * s.axis};
        }
      }
      return best;
    }
    case SurfaceType::Sphere: {
      const Vec3 out = from.norm() > 1e-12 ? Vec3(from.normalized()) : Vec3::UnitZ();
      return {s.origin + s.radius * out, out};
    }
    case SurfaceType::Torus: {
      // In the plane of the axis and `p`, the tube's circle about the ring's point on each
      // side of the axis: the nearer of the two nearest. The far side's is the nearer only
      // where the tube crosses the axis (a spindle torus, minor radius past the major).
      std::pair<Vec3, Vec3> best;
      double least = std::numeric_limits<double>::infinity();
      for (const double side : {1.0, -1.0}) {
        const Vec3 ring = s.origin + side * s.radius * across(from, s.axis);
        const Vec3 to = p - ring;
        const Vec3 out = to.norm() > 1e-12 ? Vec3(to.normalized()) : across(from, s.axis);
        const double distance = std::abs(to.norm() - s.minor_radius);
        if (distance < least) {
          least = distance;
          best = {ring + s.minor_radius * out, out};
        }
      }
      return best;
    }
    default: return {p - h * s.axis, s.axis};
  }
}

double curvatureSum(const ElementarySurface& s, const Vec3& p) {
  switch (s.type) {
    case SurfaceType::Sphere: return 2 / s.radius;
    case SurfaceType::Cylinder:
    case SurfaceType::Cone:
    case SurfaceType::Torus: {
      // About the axis, a surface of revolution bends by the normal's share across the
      // axis over the distance from it; along its meridian only a torus bends.
      const auto [q, normal] = nearestOn(s, p);
      const Vec3 from = q - s.origin;
      const Vec3 radial = from - from.dot(s.axis) * s.axis;
      const double distance = radial.norm();
      const double about = distance > 1e-9 ? normal.dot(radial) / (distance * distance) : 0;
      return about + (s.type == SurfaceType::Torus ? 1 / s.minor_radius : 0);
    }
    default: return 0;
  }
}

}  // namespace scanplan
