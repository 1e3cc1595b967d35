// Border sampling (trim task): the edges of the target faces.

#include <scanplan/cad/face_sampling.h>
#include <scanplan/sampling/sampling.h>

#include <cmath>
#include <map>

namespace scanplan {
namespace {

// A mesh face's border: its triangle edges not shared with another triangle of the face.
void sampleMeshBorders(const Part& part, int id, Role role, TaskType task,
                       const SamplingOptions& options, std::vector<Sample>& out) {
  const Face& face = part.face(id);
  std::map<std::pair<int, int>, std::pair<int, int>> edges;  // (a, b) → (uses, triangle)
  for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t)
    for (int k = 0; k < 3; ++k) {
      int a = part.mesh.triangles[t][k], b = part.mesh.triangles[t][(k + 1) % 3];
      auto& entry = edges[{std::min(a, b), std::max(a, b)}];
      ++entry.first;
      entry.second = t;
    }
  for (const auto& [key, use] : edges) {
    if (use.first != 1) continue;
    const Vec3& a = part.mesh.vertices[key.first];
    const Vec3& b = part.mesh.vertices[key.second];
    const double length = (b - a).norm();
    const int pieces = std::max(1, static_cast<int>(std::ceil(length / options.border_step)));
    for (int k = 0; k < pieces; ++k) {
      Sample s;
      s.position = a + (b - a) * (k + 0.5) / pieces;
      s.normal = part.mesh.normal(use.second);
      s.tangent = (b - a).normalized();
      s.face = id;
      s.role = role;
      s.task = task;
      s.weight = length / pieces;
      out.push_back(s);
    }
  }
}

}  // namespace

std::vector<Sample> sampleBorders(const Part& part, const std::vector<int>& faces, Role role,
                                  TaskType task, const SamplingOptions& options) {
  std::vector<Sample> samples;
  for (int id : faces) {
    part.face(id);  // throws for an unknown id
    if (part.brep)
      for (const FacePoint& point :
           brepBorderPoints(part, id, options.border_deflection, options.border_step)) {
        Sample s;
        s.position = point.position;
        s.normal = point.normal;
        s.tangent = point.tangent;
        s.face = id;
        s.uv = point.uv;
        s.role = role;
        s.task = task;
        s.weight = point.length;
        samples.push_back(s);
      }
    else
      sampleMeshBorders(part, id, role, task, options, samples);
  }
  return samples;
}

}  // namespace scanplan
