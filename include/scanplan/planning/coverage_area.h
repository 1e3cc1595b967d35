#pragma once
// Coverage as area (docs/planning.md, "Coverage by area"): how much of each face's surface
// the plan's views measure, rather than how many of its samples.

#include <scanplan/cad/part.h>
#include <scanplan/plan/plan.h>
#include <scanplan/spec/spec.h>

#include <cstddef>
#include <vector>

namespace scanplan {

// Points spread over the part's mesh (part frame): each triangle cut into n² equal
// triangles, n the least for which their sides are at most `spacing`, a point at the
// centroid of each, standing for its area, with the triangle's normal and face.
struct AreaPoints {
  std::vector<SurfacePoint> points;
  std::vector<double> area;  // mm² each stands for
};
AreaPoints areaPoints(const TriangleMesh& mesh, double spacing);

// Per face of `part` (in face order): its mesh area and the area of it that some view of
// `plan` measures, each view simulated in its rest orientation's placement, over about
// `points` area points (areaPoints at the spacing that gives that many).
std::vector<FaceArea> measuredArea(const Part& part, const ResolvedSpec& spec, const Plan& plan,
                                   std::size_t points = 100'000);

}  // namespace scanplan
