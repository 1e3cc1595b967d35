#pragma once
// Acquisition simulation: what a view of the scanner really measures (docs/design.md §4).
// The same measurement test serves surface points (samples), mesh facets and the
// simulated point cloud, so that plans and reports agree.

#include <scanplan/cad/part.h>
#include <scanplan/cad/raycast.h>
#include <scanplan/core/view.h>
#include <scanplan/scanner/sensor.h>

#include <array>
#include <cstdint>
#include <memory>
#include <span>
#include <string_view>
#include <vector>

namespace scanplan {

// Why a surface point is not measured from a view; the first test that fails, in this
// order. Kept small: one byte per point and view.
enum class Loss : std::uint8_t {
  Measured = 0,
  OutsideVolume,      // not within the measuring volume (depth or field of view)
  CameraAngle,        // angle between normal and camera direction above the limit
  ProjectorAngle,     // the same for the projector
  Reflection,         // specular face, mirror reflection of the projector near the camera
  UnderMarker,        // a marker stuck on the surface covers it
  CameraOccluded,     // something (part, fixture, working plane) hides it from the camera
  ProjectorOccluded,  // ... from the projector
};
inline constexpr int kLossKinds = 8;
std::string_view toString(Loss loss);

// Projector centre of `view` in the world.
inline Vec3 projectorPosition(const View& view, const Scanner& scanner) {
  return view.camera_to_world * scanner.projectorInScanner();
}

// A point on the part's surface, world frame.
struct SurfacePoint {
  Vec3 position = Vec3::Zero();  // mm
  Vec3 normal = Vec3::UnitZ();   // unit, outward
  int face = 0;                  // 1-based face id (0: unknown, never specular)
};

// A spot of the part's surface that something stuck on it covers (a marker), world frame.
struct CoveredSpot {
  Vec3 centre = Vec3::Zero();   // mm
  Vec3 normal = Vec3::UnitZ();  // unit
  double radius = 0;            // mm
};

// Whether `spot` covers `point` (face >= 1): within its radius of its centre, near its plane
// (within half the radius) and facing its way.
bool spotCovers(const CoveredSpot& spot, const SurfacePoint& point);

// Per point, whether the spot nearest it covers it, as the simulation judges (Loss::
// UnderMarker) whatever the view.
std::vector<char> underSpots(const std::vector<CoveredSpot>& spots,
                             std::span<const SurfacePoint> points);

struct SimulationOptions {
  Pose part_to_world = Pose::Identity();  // where the part stands in the cell
  bool working_plane = true;              // the plane z = 0 occludes (world frame)
  std::vector<int> specular_faces;        // face ids that reflect like mirrors
  std::vector<TriangleMesh> fixtures;     // extra occluders, world frame, mm
  double surface_offset = 1e-5;           // ray origin offset along the normal, as a
                                          // fraction of the part's bounding-box diagonal
                                          // (at least 1.1 x the mesh's chordal tolerance)
  // Points of the part's faces (face >= 1) within a spot's radius of its centre, on its
  // side and near its plane (within half the radius), are not measured.
  std::vector<CoveredSpot> covered;
};

// The measurement of one view over the part's mesh facets (triangles).
struct Acquisition {
  int view_id = 0;
  std::vector<Loss> facets;                      // per triangle of Part::mesh
  std::vector<double> face_area;                 // measured area per face id - 1, mm²
  double measured_area = 0;                      // mm²
  std::array<std::size_t, kLossKinds> counts{};  // facets per Loss value
  std::size_t rays = 0;                          // occlusion rays cast
};

// A simulated point cloud of one view, world frame.
struct PointCloud {
  std::vector<Vec3> points;      // mm, with noise
  std::vector<Vec3> normals;     // unit, outward
  std::vector<int> faces;        // face id per point
  std::vector<float> incidence;  // angle between normal and camera ray, degrees
  std::vector<Vec3> hits;        // mm, where each point's ray met the mesh, before the noise
                                 // (a simulated cloud's; empty for one read from a file)
};

// A simulated cloud before its noise (Simulator::rays): each point where its pixel's ray
// meets the part, the ray's direction and the noise's standard deviation there; the
// points lie in rows of the pixel grids, each row drawing its noise from a random stream
// of its own, point after point.
struct CloudRays {
  PointCloud cloud;                        // points and hits alike, without noise
  std::vector<Vec3> along;                 // unit, the camera ray's direction
  std::vector<double> sigma;               // mm
  std::vector<std::uint64_t> row_streams;  // per row, its stream (with the seed)
  std::vector<std::size_t> row_ends;       // per row, one past its last point
};

// The noise of each point of `rays` drawn from `seed`, along its ray: sigma times a
// standard normal of its row's stream.
std::vector<Vec3> noiseOf(const CloudRays& rays, std::uint64_t seed);

// What a view's camera records on the surface at a point it measures (docs/simulation.md):
// the depth noise of its points (along the camera's ray), its part along the surface normal,
// and their density, points per mm², from the pixel grid (point_spacing at the standoff) at
// the point's depth and incidence.
struct PointQuality {
  double sigma = 0, along_normal = 0, density = 0;
};
PointQuality pointQuality(const Scanner& scanner, const View& view, const Vec3& position,
                          const Vec3& normal);

// Owns the ray-casting scene of the part (in the world) and its fixtures, built once.
// All queries are const and thread-safe.
class Simulator {
 public:
  // \throw InputError when a specular face id is unknown; LibraryError from Embree.
  Simulator(const Part& part, const Scanner& scanner, SimulationOptions options = {});
  ~Simulator();
  Simulator(Simulator&&) noexcept;
  Simulator& operator=(Simulator&&) noexcept;

  // The measurement test of each point from `view`.
  std::vector<Loss> measure(const View& view, std::span<const SurfacePoint> points) const;
  // The same for many views, in parallel: result[v][i] for views[v] and points[i].
  std::vector<std::vector<Loss>> measure(std::span<const View> views,
                                         std::span<const SurfacePoint> points) const;

  // The test of points[i] from views[i], for every i (equal lengths), in parallel.
  std::vector<Loss> measurePairs(std::span<const View> views,
                                 std::span<const SurfacePoint> points) const;

  // The measurement of every facet of the part's mesh (its centroid and normal).
  Acquisition acquire(const View& view) const;
  std::vector<Acquisition> acquire(std::span<const View> views) const;

  // The cloud the camera records: one ray per pixel of a grid of `point_spacing` at the
  // standoff; a hit is kept when it passes the measurement test. Depth noise along the
  // camera ray, Gaussian with sigma = noise_sigma * (z / standoff)^2 / cos(incidence)
  // (docs/simulation.md), seeded by `seed`. A `spacing` > 0 replaces the scanner's.
  PointCloud cloud(const View& view, std::uint64_t seed = 1, double spacing = 0) const;
  // The same cloud before its noise (its points its hits), with what the noise is drawn
  // from: cloud(view, seed, spacing) is rays(view, spacing) plus noiseOf(them, seed).
  CloudRays rays(const View& view, double spacing = 0) const;

  const Scanner& scanner() const;
  const SimulationOptions& options() const;
  // Ray origin offset along the normal used by every occlusion test, mm.
  double surfaceOffset() const;
  // Occlusion queries against the same scene (part and fixtures, not the working plane).
  std::vector<bool> occluded(std::span<const Ray> rays) const;
  // True when `point` (world) lies inside the part's material: the part is a closed solid,
  // and a ray from the point first meets its surface from the inside. Always false for an
  // open mesh.
  bool insideSolid(const Vec3& point) const;
  // The part's surface points in the world: facet centroids with their normals.
  std::vector<SurfacePoint> facetPoints() const;
  // Points spread uniformly over the part's surface in the world, one per `spacing`² of
  // area on average (each stands for that area), seeded by `seed`.
  std::vector<SurfacePoint> surfacePoints(double spacing, std::uint64_t seed = 1) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

// Per view, the indices of the `points` it measures, ascending: the same test as
// Simulator::measure, applied only to the points of cells that reach each view's
// measuring volume, and in them to the groups of points whose normals may face the view
// within the scanner's angles; views in parallel.
std::vector<std::vector<int>> measuredPoints(const Simulator& simulator,
                                             std::span<const View> views,
                                             std::span<const SurfacePoint> points);

// measuredPoints over points indexed once, for views that come a few at a time.
class IndexedPoints {
 public:
  explicit IndexedPoints(std::vector<SurfacePoint> points);
  ~IndexedPoints();
  IndexedPoints(IndexedPoints&&) noexcept;

  std::vector<std::vector<int>> measured(const Simulator& simulator,
                                         std::span<const View> views) const;
  const std::vector<SurfacePoint>& points() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace scanplan
