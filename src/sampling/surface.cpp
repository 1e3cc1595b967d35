// Surface sampling: B-Rep faces at the Greville abscissae of their NURBS form, by portions
// that fit the field of view (cad/face_sampling.h); mesh faces at their triangles' centroids.

#include <scanplan/cad/face_sampling.h>
#include <scanplan/sampling/sampling.h>

#include <algorithm>
#include <cmath>

namespace scanplan {

std::vector<Sample> sampleSurface(const Part& part, const std::vector<int>& faces, Role role,
                                  TaskType task, const SamplingOptions& options) {
  std::vector<Sample> samples;
  if (!part.brep) {
    // A mesh part: triangle centroids, thinned to about min_per_direction per portion.
    for (int id : faces) {
      const Face& face = part.face(id);
      std::vector<Sample> centroids;
      for (int t = face.first_triangle; t < face.first_triangle + face.triangle_count; ++t) {
        const Vec3i& tri = part.mesh.triangles[t];
        Sample s;
        s.position =
            (part.mesh.vertices[tri[0]] + part.mesh.vertices[tri[1]] + part.mesh.vertices[tri[2]]) /
            3;
        s.normal = part.mesh.normal(t);
        s.face = id;
        s.role = role;
        s.task = task;
        s.weight = part.mesh.area(t);
        if (!s.normal.isZero()) centroids.push_back(s);
      }
      std::vector<Sample> kept =
          decimate(centroids, options.portion_size / (2.0 * options.min_per_direction), 10);
      const double weight = face.area / static_cast<double>(std::max<std::size_t>(kept.size(), 1));
      for (Sample& s : kept) s.weight = weight;
      samples.insert(samples.end(), kept.begin(), kept.end());
    }
    return samples;
  }
  const FaceSampling sampling{options.portion_size, options.max_normal_spread, options.overlap,
                              options.min_per_direction, options.max_per_direction};
  for (int id : faces) {
    const Face& face = part.face(id);
    const std::vector<FacePoint> points = brepSurfacePoints(part, id, sampling);
    const double weight = face.area / static_cast<double>(std::max<std::size_t>(points.size(), 1));
    for (const FacePoint& point : points) {
      Sample sample;
      sample.position = point.position;
      sample.normal = point.normal;
      sample.uv = point.uv;
      sample.face = id;
      sample.role = role;
      sample.task = task;
      sample.weight = weight;
      samples.push_back(sample);
    }
  }
  return samples;
}

}  // namespace scanplan
