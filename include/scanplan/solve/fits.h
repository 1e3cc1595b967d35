#pragma once
// Fits of ideal geometry to measured points, as inspection software evaluates features
// (docs/capability.md, "Virtual inspection"): least-squares (Gaussian) planes and
// cylinders, and the minimum-zone (Chebyshev) flatness and straightness of ISO 1101.

#include <scanplan/core/geometry.h>

#include <span>

namespace scanplan {

struct PlaneFit {
  Vec3 point = Vec3::Zero();    // the points' centroid
  Vec3 normal = Vec3::UnitZ();  // unit
  double rms = 0;               // of the points' distances to the plane, mm
  bool determined = false;      // at least 3 points, not all on one line
};

// The least-squares plane of `points`, its normal turned to the side of `towards`.
PlaneFit fitPlane(std::span<const Vec3> points, const Vec3& towards);

// The width of the narrowest pair of parallel planes holding every point (minimum zone),
// found as a linear programme over the planes near `normal`. 0 for fewer than 3 points.
double minimumZoneFlatness(std::span<const Vec3> points, const Vec3& normal);

// The straightness of a line element (ISO 1101, minimum zone): the width of the narrowest
// pair of parallel lines, in the plane of `along` and `across` (unit, at right angles), that
// holds the points, as they lie in that plane. 0 for fewer than 3 points.
double minimumZoneStraightness(std::span<const Vec3> points, const Vec3& along, const Vec3& across);

// The diameter of the smallest circle holding `points` (of a plane): the straightness zone
// of an axis whose section centres lie at these offsets from a line. 0 when empty.
double enclosingCircleDiameter(std::span<const Eigen::Vector2d> points);

// A cylinder's fit is taken as determined by points spread over this much of its circle,
// degrees: a band measured all round fixes it, a strip along one side does not.
constexpr double kLeastArc = 90;

struct CylinderFit {
  Vec3 point = Vec3::Zero();  // on the axis, nearest the points' centroid
  Vec3 axis = Vec3::UnitZ();  // unit
  double radius = 0;          // mm
  double rms = 0;             // of the points' radial residuals, mm
  bool determined = false;    // the fit converged on points that fix it
};

// The least-squares cylinder of `points` (the sum of squared radial residuals), by
// Gauss-Newton from `start`: a cylinder near the points, the nominal one, say. With
// `hold_axis`, the axis keeps the start's direction and only its place and the radius are
// fitted: the least-squares circle of a band too short to turn the axis.
CylinderFit fitCylinder(std::span<const Vec3> points, const CylinderFit& start,
                        bool hold_axis = false);

// The cylinder surface `points` with their outward `normals` lie on, without noise: the
// axis along which the normals do not turn, its point and radius by least squares. For a
// start to fitCylinder; `determined` false when the normals do not fix an axis.
CylinderFit cylinderFromNormals(std::span<const Vec3> points, std::span<const Vec3> normals);

// How much of the circle about the cylinder's axis `points` cover, in degrees (by 10° bins).
double arcAbout(const CylinderFit& cylinder, std::span<const Vec3> points);

// The distance from `p` to the axis of `cylinder`, mm.
double axisDistance(const CylinderFit& cylinder, const Vec3& p);

// A sphere's points fix it when their directions from its centre span a cap 90° across:
// the smallest eigenvalue of the mean of their outer products, 0.13 on such a cap (1/3 all
// round, 0 along a band about a circle, which leaves the centre free along its axis).
constexpr double kLeastCap = 0.12;

struct SphereFit {
  Vec3 centre = Vec3::Zero();
  double radius = 0;        // mm
  double rms = 0;           // of the points' radial residuals, mm
  bool determined = false;  // the fit converged on points that span kLeastCap
};

// The least-squares sphere of `points` (the sum of squared radial residuals), by
// Gauss-Newton from the algebraic fit (|p|² linear in the centre).
SphereFit fitSphere(std::span<const Vec3> points);

}  // namespace scanplan
