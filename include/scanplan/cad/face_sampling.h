#pragma once
// Points on the faces of a B-Rep part from their exact geometry (OCCT): the kernels the
// tasks' sampling uses (sampling/sampling.h, docs/sampling.md). Part frame, mm.

#include <scanplan/cad/part.h>

#include <Eigen/Core>

#include <optional>
#include <vector>

namespace scanplan {

// A point on a face with its outward normal and the face's (u, v); a border point with the
// unit tangent of its edge, its edge parameter as u, and the length of edge to the next.
struct FacePoint {
  Vec3 position = Vec3::Zero();
  Vec3 normal = Vec3::UnitZ();
  Vec3 tangent = Vec3::Zero();
  Eigen::Vector2d uv = Eigen::Vector2d::Zero();
  double length = 0;  // mm, border points
};

// How a face is cut into portions and sampled; SamplingOptions (sampling/sampling.h) sets
// every field.
struct FaceSampling {
  double portion_size;       // largest extent of a portion, mm
  double max_normal_spread;  // largest angle between normals in a portion, degrees
  double overlap;            // portions overlap their neighbours by this fraction
  int min_per_direction;     // points per parameter direction of a portion, at least
  int max_per_direction;     // and at most
};

// Face `face` split along isoparametric lines into portions no larger than portion_size
// whose normals spread at most max_normal_spread, overlapping; each portion sampled at the
// Greville abscissae of the face's NURBS form (OCCT's conversion for analytic faces), at
// least min_per_direction per direction, keeping the points inside the trimmed face.
std::vector<FacePoint> brepSurfacePoints(const Part& part, int face, const FaceSampling& sampling);

// Points along the edges of face `face`'s outer and inner wires under the chordal tolerance
// `deflection`, at most `step` mm apart, each with the face's normal and the edge's tangent.
// Seam and degenerate edges are skipped.
std::vector<FacePoint> brepBorderPoints(const Part& part, int face, double deflection, double step);

// The point of face `face` nearest `p`, and how far it lies from `p`; where it lies inside
// the face, its (u, v) and the outward normal there (where defined). None when OCCT finds
// no nearest point.
struct NearestOnFace {
  Vec3 position = Vec3::Zero();
  double distance = 0;
  std::optional<Eigen::Vector2d> uv;
  std::optional<Vec3> normal;
};
std::optional<NearestOnFace> nearestOnBrepFace(const Part& part, int face, const Vec3& p);

}  // namespace scanplan
