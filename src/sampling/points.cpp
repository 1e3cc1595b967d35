// User control points (points task): projected onto the nearest face, exactly onto a B-Rep's.

#include "cad/brep_model.h"

#include <scanplan/core/errors.h>
#include <scanplan/sampling/sampling.h>

#include <BRepAdaptor_Surface.hxx>
#include <BRepBuilderAPI_MakeVertex.hxx>
#include <BRepExtrema_DistShapeShape.hxx>
#include <BRepLProp_SLProps.hxx>

#include <limits>

namespace scanplan {

namespace {

// The point of the mesh nearest `p`, as a sample on the nearest triangle's face with that
// triangle's normal; `distance` is how far it lies from `p`.
Sample onMesh(const TriangleMesh& mesh, const Vec3& p, double& distance) {
  double best = std::numeric_limits<double>::infinity();
  std::size_t best_triangle = 0;
  Vec3 best_point = p;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const Vec3i& tri = mesh.triangles[t];
    const Vec3 q = closestPointOnTriangle(p, mesh.vertices[tri[0]], mesh.vertices[tri[1]],
                                          mesh.vertices[tri[2]]);
    const double d = (q - p).squaredNorm();
    if (d < best) {
      best = d;
      best_triangle = t;
      best_point = q;
    }
  }
  distance = std::sqrt(best);
  Sample sample;
  sample.face = mesh.triangle_faces[best_triangle];
  sample.position = best_point;
  sample.normal = mesh.normal(best_triangle);
  return sample;
}

// Moves `sample` onto its exact face, nearest `p`: the point, its parameters and the
// outward normal there; `distance` becomes how far that point lies from `p`.
void ontoExactFace(const detail::BRepModel& brep, const Vec3& p, Sample& sample, double& distance) {
  const TopoDS_Face face = brep.outwardFace(sample.face);
  BRepExtrema_DistShapeShape extrema(
      BRepBuilderAPI_MakeVertex(gp_Pnt(p.x(), p.y(), p.z())).Vertex(), face);
  if (!extrema.IsDone() || extrema.NbSolution() == 0) return;
  distance = extrema.Value();
  const gp_Pnt on = extrema.PointOnShape2(1);
  sample.position = Vec3(on.X(), on.Y(), on.Z());
  if (extrema.SupportTypeShape2(1) != BRepExtrema_IsInFace) return;
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

}  // namespace

std::vector<Sample> samplePoints(const Part& part, const std::vector<ControlPoint>& points,
                                 const std::string& source, const SamplingOptions& options) {
  std::vector<Sample> samples;
  for (const ControlPoint& point : points) {
    double distance = 0;
    Sample sample = onMesh(part.mesh, point.position, distance);
    if (part.brep) ontoExactFace(*part.brep, point.position, sample, distance);
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
