#pragma once
// A characteristic's value from measured points, by its definition (docs/capability.md,
// "Virtual inspection"): its features fitted (least-squares planes and cylinders, the
// minimum zone for flatness), located in a datum reference frame fitted to its datum
// features.

#include "planning/registration_error.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/cad/gdt.h>
#include <scanplan/cad/part.h>
#include <scanplan/scanner/simulation.h>
#include <scanplan/solve/fits.h>

#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

namespace scanplan::detail {

// In a datum reference frame, each datum weighs this many times the next (primary,
// secondary, tertiary), each datum's points alike.
constexpr double kDatumPrecedence = 100;

// A cylinder measured over a band shorter than this share of its radius is fitted as a
// circle about its designed axis' direction, as inspection software fits a short one: so
// short a band does not turn the axis. Not for an orientation, which is that direction.
constexpr double kShortBand = 0.5;

// Whether `kind` tolerances an orientation: perpendicularity, parallelism, angularity.
bool orientationKind(const std::string& kind);

// Points by the face they lie on (part frame).
using FacePoints = std::map<int, std::vector<Vec3>>;

// A face as designed, sampled densely (part frame).
struct NominalFace {
  SurfaceType type = SurfaceType::Other;
  std::vector<Vec3> points, normals;
  Vec3 centroid = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();              // a plane's
  CylinderFit cylinder;                     // a cylinder's
  std::optional<ElementarySurface> sphere;  // a sphere's, as the B-Rep gives it
  double rim = 0;  // the farthest its points lie from the centroid, across it
};

// The part's faces as designed, from points sampled densely on them (part frame). Where a
// face is a cylinder, cone, sphere or torus in the B-Rep, its points are moved onto that
// surface: a mesh's facets cut inside the curve, by up to its chordal tolerance.
class Nominal {
 public:
  Nominal(const Part& part, std::span<const SurfacePoint> points);
  ~Nominal();
  const NominalFace* face(int id) const;
  const std::map<int, NominalFace>& faces() const { return faces_; }
  // The normal of face `id` at its point nearest `p` (its exact surface; else its triangles;
  // without them, its nearest sample), and the signed distance from `p` to it along that
  // normal: a point carried past the face's edge is as far from the face as it lies along
  // its normal, as a surface comparison measures deviations normal to the nominal.
  std::pair<Vec3, double> nearest(int id, const Vec3& p) const;
  // That point of face `id` nearest `p`, with the normal there.
  SurfacePoint closest(int id, const Vec3& p) const;
  // The point of face `id`'s exact surface nearest `p`, with the face's outward normal
  // there; none for a face without one.
  std::optional<SurfacePoint> onExact(int id, const Vec3& p) const;
  // Face `id`'s exact surface (none for a plane or a face without one), and which way its
  // outward normal points from it: 1 away from its axis, centre or tube, -1 towards it.
  std::optional<std::pair<ElementarySurface, double>> exactSurface(int id) const;
  // The sum of face `id`'s principal curvatures at its point nearest `p` (1/mm): positive
  // where the face bends away from its outward normal (a boss), negative where towards it
  // (a bore); 0 for a face without an exact surface.
  double curvature(int id, const Vec3& p) const;
  // The point of face `id`'s triangles nearest `p`, with its triangle's normal: within the
  // face's bounds, where an exact surface runs on past them; none without triangles.
  std::optional<SurfacePoint> onTriangles(int id, const Vec3& p) const;
  // Whether `p` lies within `distance` of face `id`'s triangles, its bounds; true for a face
  // without triangles, which has none to bound it.
  bool withinBounds(int id, const Vec3& p, double distance) const;
  // A point `p` of face `id`'s triangles (normal `n`) where it lies on the face as designed:
  // the nearest point of the face's exact surface, with its outward normal there; as it is
  // on faces without one.
  SurfacePoint onDesigned(int id, const Vec3& p, const Vec3& n) const;

 private:
  struct Trees;

  // A curved face's exact surface, and which way the face's outward normal points from
  // it: 1 away from its axis or centre (a boss), -1 towards it (a bore).
  struct Exact {
    ElementarySurface surface;
    double side = 1;
  };

  std::map<int, NominalFace> faces_;
  std::map<int, Exact> exact_;
  std::unique_ptr<Trees> trees_;
};

// Whether two faces' surfaces are one feature's: one plane, cylinder or sphere, to within
// the mesh's chords. The evaluation groups faces so by the surfaces fitted to their designed
// points (a sphere's by its B-Rep surface); the capability model by their B-Rep surfaces.
bool oneFeature(const ElementarySurface& a, const ElementarySurface& b);

// The value of `c` from `points`, or why it cannot be found: its features not measured or
// not fitted, or a kind the evaluation does not know.
struct Evaluation {
  std::optional<double> value;
  std::string why_not;
};
Evaluation evaluate(const Characteristic& c, const Gdt& gdt, const Nominal& nominal,
                    const FacePoints& points);

// The small rigid motion that puts the measured datum features `datums` (in precedence)
// where the nominal ones lie: least squares, each datum a hundred times the next, the
// directions none fixes left at 0. Planes by their points' distances, cylinders by their
// fitted axes. None, and why, when a datum is not measured enough to fit.
struct Alignment {
  std::optional<Twist> motion;
  std::string why_not;
};
Alignment datumAlignment(const std::vector<std::string>& datums, const Gdt& gdt,
                         const Nominal& nominal, const FacePoints& points);

}  // namespace scanplan::detail
