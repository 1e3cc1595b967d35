// User control points (points task): projected onto the nearest face.

#include "cad/brep_model.h"

#include <scanplan/errors.h>
#include <scanplan/sampling.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepLProp_SLProps.hxx>

#include <limits>

namespace scanplan {
namespace {

// Closest point to p on triangle (a, b, c) (Ericson, Real-Time Collision Detection, 5.1.5).
Vec3 closestOnTriangle(const Vec3& p, const Vec3& a, const Vec3& b, const Vec3& c) {
  const Vec3 ab = b - a, ac = c - a, ap = p - a;
  const double d1 = ab.dot(ap), d2 = ac.dot(ap);
  if (d1 <= 0 && d2 <= 0) return a;
  const Vec3 bp = p - b;
  const double d3 = ab.dot(bp), d4 = ac.dot(bp);
  if (d3 >= 0 && d4 <= d3) return b;
  const double vc = d1 * d4 - d3 * d2;
  if (vc <= 0 && d1 >= 0 && d3 <= 0) return a + d1 / (d1 - d3) * ab;
  const Vec3 cp = p - c;
  const double d5 = ab.dot(cp), d6 = ac.dot(cp);
  if (d6 >= 0 && d5 <= d6) return c;
  const double vb = d5 * d2 - d1 * d6;
  if (vb <= 0 && d2 >= 0 && d6 <= 0) return a + d2 / (d2 - d6) * ac;
  const double va = d3 * d6 - d5 * d4;
  if (va <= 0 && (d4 - d3) >= 0 && (d5 - d6) >= 0)
    return b + (d4 - d3) / ((d4 - d3) + (d5 - d6)) * (c - b);
  const double denom = 1 / (va + vb + vc);
  return a + ab * (vb * denom) + ac * (vc * denom);
}

}  // namespace

std::vector<Sample> samplePoints(const Part& part, const std::vector<ControlPoint>& points,
                                 const std::string& source, const SamplingOptions& options) {
  std::vector<Sample> samples;
  for (const ControlPoint& point : points) {
    // Nearest triangle of the mesh: its face, and a first projection.
    double best = std::numeric_limits<double>::infinity();
    std::size_t best_triangle = 0;
    Vec3 best_point = Vec3::Zero();
    for (std::size_t t = 0; t < part.mesh.triangles.size(); ++t) {
      const Vec3i& tri = part.mesh.triangles[t];
      const Vec3 q = closestOnTriangle(point.position, part.mesh.vertices[tri[0]],
                                       part.mesh.vertices[tri[1]], part.mesh.vertices[tri[2]]);
      const double d = (q - point.position).squaredNorm();
      if (d < best) {
        best = d;
        best_triangle = t;
        best_point = q;
      }
    }
    Sample sample;
    sample.face = part.mesh.triangle_faces[best_triangle];
    sample.position = point.position;
    sample.normal = part.mesh.normal(best_triangle);
    double distance = std::sqrt(best);
    if (part.brep) {
      // The exact face: distance, parameters and normal.
      const TopoDS_Face face = part.brep->outwardFace(sample.face);
      const gp_Pnt p(point.position.x(), point.position.y(), point.position.z());
      BRepExtrema_DistShapeShape extrema(BRepBuilderAPI_MakeVertex(p).Vertex(), face);
      if (extrema.IsDone() && extrema.NbSolution() > 0) {
        distance = extrema.Value();
        if (extrema.SupportTypeShape2(1) == BRepExtrema_IsInFace) {
          double u = 0, v = 0;
          extrema.ParOnFaceS2(1, u, v);
          sample.uv = Eigen::Vector2d(u, v);
          BRepLProp_SLProps props(BRepAdaptor_Surface(face), u, v, 1, 1e-9);
          if (props.IsNormalDefined()) {
            gp_Dir n = props.Normal();
            if (face.Orientation() == TopAbs_REVERSED) n.Reverse();
            sample.normal = Vec3(n.X(), n.Y(), n.Z());
          }
        }
      }
    }
    if (distance > options.point_tolerance)
      throw InputError(source, "line " + std::to_string(point.line) + ": the point (" +
                                   std::to_string(point.position.x()) + ", " +
                                   std::to_string(point.position.y()) + ", " +
                                   std::to_string(point.position.z()) + ") is " +
                                   std::to_string(distance) + " mm from the part (tolerance " +
                                   std::to_string(options.point_tolerance) + " mm)");
    if (point.normal) sample.normal = *point.normal;
    sample.role = Role::Priority;
    sample.task = TaskType::Points;
    sample.weight = 0;
    samples.push_back(sample);
  }
  return samples;
}

}  // namespace scanplan
