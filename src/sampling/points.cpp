// User control points (points task): projected onto the nearest face, exactly onto a B-Rep's.

#include <scanplan/cad/face_sampling.h>
#include <scanplan/core/errors.h>
#include <scanplan/sampling/sampling.h>

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

}  // namespace

std::vector<Sample> samplePoints(const Part& part, const std::vector<ControlPoint>& points,
                                 const std::string& source, const SamplingOptions& options) {
  std::vector<Sample> samples;
  for (const ControlPoint& point : points) {
    double distance = 0;
    Sample sample = onMesh(part.mesh, point.position, distance);
    if (part.brep)
      if (const auto exact = nearestOnBrepFace(part, sample.face, point.position)) {
        // Onto its exact face: the point, and its parameters and normal where inside it.
        distance = exact->distance;
        sample.position = exact->position;
        if (exact->uv) sample.uv = *exact->uv;
        if (exact->normal) sample.normal = *exact->normal;
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
