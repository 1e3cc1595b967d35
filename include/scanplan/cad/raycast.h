#pragma once
// Ray casting against the part's triangle mesh with Embree: the one primitive that
// visibility, simulation and rendering are built on.

#include <scanplan/cad/mesh.h>
#include <scanplan/core/geometry.h>

#include <limits>
#include <memory>
#include <optional>
#include <span>
#include <vector>

namespace scanplan {

// A ray segment origin + t * direction for t in [t_near, t_far]; `direction` need not be
// unit length (t is then in units of its length).
struct Ray {
  Vec3 origin = Vec3::Zero();
  Vec3 direction = Vec3::UnitZ();
  double t_near = 0;
  double t_far = std::numeric_limits<double>::infinity();
};

struct RayHit {
  double t = 0;  // ray parameter of the hit
  Vec3 point = Vec3::Zero();
  Vec3 normal = Vec3::Zero();  // unit outward normal of the triangle hit
  int triangle = -1;           // index into the mesh's triangles
  int face = 0;                // 1-based face id of that triangle
};

// Owns an Embree device and a scene built once from a mesh (or several: the part plus
// fixtures); queries are thread-safe. Errors raised by Embree, on any thread, are turned
// into LibraryError thrown from the call that caused them.
class RayCaster {
 public:
  // \throw LibraryError when Embree cannot create the device or build the scene.
  explicit RayCaster(const TriangleMesh& mesh);
  ~RayCaster();
  RayCaster(RayCaster&&) noexcept;
  RayCaster& operator=(RayCaster&&) noexcept;
  RayCaster(const RayCaster&) = delete;
  RayCaster& operator=(const RayCaster&) = delete;

  // The closest hit along the ray, if any.
  std::optional<RayHit> intersect(const Ray& ray) const;
  // True when anything lies on the ray within [t_near, t_far].
  bool occluded(const Ray& ray) const;

  // Batched queries, run in parallel (oneTBB) over packets of rays. A batch's hits are the
  // same whatever the threads; on an edge two triangles share, the triangle reported may
  // differ from the single query's (the point and, inside a face, the face do not).
  std::vector<std::optional<RayHit>> intersect(std::span<const Ray> rays) const;
  std::vector<bool> occluded(std::span<const Ray> rays) const;

  std::size_t triangleCount() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// One-off closest-hit query for tools and tests; builds a scene for the call.
std::vector<std::optional<RayHit>> castRays(const TriangleMesh& mesh, std::span<const Ray> rays);

}  // namespace scanplan
