#pragma once
// A face's surface where it is elementary, as numbers: what a click on the face snaps to.

#include <scanplan/cad/part.h>

#include <optional>
#include <utility>

namespace scanplan {

// Part frame, mm and radians. A plane's axis is the face's outward normal; a cone's radius
// is RefRadius at its origin, R + h tan(semi_angle) at height h along the axis.
struct ElementarySurface {
  SurfaceType type = SurfaceType::Plane;  // Plane, Cylinder, Cone, Sphere or Torus
  Vec3 origin = Vec3::Zero();
  Vec3 axis = Vec3::UnitZ();  // unit; none for a sphere
  double radius = 0;          // cylinder, cone (at the origin), sphere; torus: the major one
  double minor_radius = 0;    // torus
  double semi_angle = 0;      // cone
};

// Face `face`'s surface where it is a plane, cylinder, cone, sphere or torus; none for other
// surfaces and for mesh parts.
std::optional<ElementarySurface> elementarySurface(const Part& part, int face);

// The point of `surface` nearest `p` and the surface's unit normal there, pointing away
// from its axis, centre or (a plane's) along its axis: the cone taken whole, both nappes.
// A point on the axis (or at the centre) takes an arbitrary direction about it.
std::pair<Vec3, Vec3> nearestOn(const ElementarySurface& surface, const Vec3& p);

// The sum of `surface`'s principal curvatures (1/mm) at its point nearest `p`: positive
// where the surface bends away from the normal nearestOn gives there (a cylinder 1/radius,
// a sphere 2/radius), 0 for a plane and near a cone's apex.
double curvatureSum(const ElementarySurface& surface, const Vec3& p);

}  // namespace scanplan
