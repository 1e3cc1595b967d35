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
      const Vec3 q = closestPointOnTriangle(point.position, part.mesh.vertices[tri[0]],
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
