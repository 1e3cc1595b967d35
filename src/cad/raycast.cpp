#include <scanplan/cad/raycast.h>
#include <scanplan/core/errors.h>

#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <atomic>
#include <cmath>
#include <mutex>
#include <string>

namespace scanplan {

// Ownership: the Impl owns one Embree device and one committed scene; both are released
// in its destructor. Embree reports errors through a callback that may run on any
// thread; the first message is kept and rethrown by the call that checks for it.
struct RayCaster::Impl {
  RTCDevice device = nullptr;
  RTCScene scene = nullptr;
  std::vector<int> triangle_faces;
  std::vector<Vec3> normals;  // unit outward normal per triangle
  std::mutex error_mutex;
  std::string error;  // guarded by error_mutex
  std::atomic<bool> failed{false};

  ~Impl() {
    if (scene) rtcReleaseScene(scene);
    if (device) rtcReleaseDevice(device);
  }

  static void onError(void* user, RTCError code, const char* message) {
    auto* self = static_cast<Impl*>(user);
    std::lock_guard lock(self->error_mutex);
    if (self->error.empty())
      self->error = "Embree error " + std::to_string(static_cast<int>(code)) + ": " +
                    (message ? message : "unknown");
    self->failed = true;
  }

  void check() {
    if (!failed) return;
    std::lock_guard lock(error_mutex);
    throw LibraryError("", error);
  }
};

RayCaster::RayCaster(const TriangleMesh& mesh) : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.device = rtcNewDevice(nullptr);
  if (!d.device)
    throw LibraryError("", "cannot create an Embree device (error " +
                               std::to_string(static_cast<int>(rtcGetDeviceError(nullptr))) + ")");
  rtcSetDeviceErrorFunction(d.device, &Impl::onError, &d);
  d.scene = rtcNewScene(d.device);
  d.check();
  rtcSetSceneFlags(d.scene, RTC_SCENE_FLAG_ROBUST);
  rtcSetSceneBuildQuality(d.scene, RTC_BUILD_QUALITY_HIGH);

  RTCGeometry geometry = rtcNewGeometry(d.device, RTC_GEOMETRY_TYPE_TRIANGLE);
  d.check();
  auto* vertices = static_cast<float*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0, RTC_FORMAT_FLOAT3,
                              3 * sizeof(float), std::max<std::size_t>(mesh.vertices.size(), 1)));
  auto* indices = static_cast<unsigned*>(rtcSetNewGeometryBuffer(
      geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3, 3 * sizeof(unsigned),
      std::max<std::size_t>(mesh.triangles.size(), 1)));
  if (!vertices || !indices) {
    rtcReleaseGeometry(geometry);
    d.check();
    throw LibraryError("", "Embree could not allocate the mesh buffers");
  }
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i)
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(mesh.vertices[i][k]);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
  if (mesh.triangles.empty()) {
    // An empty scene: one degenerate triangle that no ray can hit.
    std::fill(vertices, vertices + 3, 0.0f);
    std::fill(indices, indices + 3, 0u);
  }
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(d.scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(d.scene);
  d.check();

  d.triangle_faces = mesh.triangle_faces;
  d.triangle_faces.resize(mesh.triangles.size(), 0);
  d.normals.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) d.normals[t] = mesh.normal(t);
}

RayCaster::~RayCaster() = default;
RayCaster::RayCaster(RayCaster&&) noexcept = default;
RayCaster& RayCaster::operator=(RayCaster&&) noexcept = default;

std::size_t RayCaster::triangleCount() const { return impl_->normals.size(); }

namespace {

void setRay(RTCRay& r, const Ray& ray) {
  r.org_x = static_cast<float>(ray.origin.x());
  r.org_y = static_cast<float>(ray.origin.y());
  r.org_z = static_cast<float>(ray.origin.z());
  r.dir_x = static_cast<float>(ray.direction.x());
  r.dir_y = static_cast<float>(ray.direction.y());
  r.dir_z = static_cast<float>(ray.direction.z());
  r.tnear = static_cast<float>(ray.t_near);
  r.tfar = std::isinf(ray.t_far) ? std::numeric_limits<float>::infinity()
                                 : static_cast<float>(ray.t_far);
  r.time = 0;
  r.mask = 0xFFFFFFFFu;
  r.id = 0;
  r.flags = 0;
}

constexpr std::size_t kPacket = 256;  // rays per stream call

// Calls body(first, count) for consecutive packets of at most kPacket rays, in parallel.
template <typename Body>
void forEachPacket(std::size_t rays, const Body& body) {
  const std::size_t packets = (rays + kPacket - 1) / kPacket;
  tbb::parallel_for(std::size_t{0}, packets, [&](std::size_t p) {
    const std::size_t first = p * kPacket;
    body(first, std::min(kPacket, rays - first));
  });
}

}  // namespace

std::optional<RayHit> RayCaster::intersect(const Ray& ray) const {
  auto hits = intersect(std::span<const Ray>(&ray, 1));
  return hits.front();
}

bool RayCaster::occluded(const Ray& ray) const {
  return occluded(std::span<const Ray>(&ray, 1)).front();
}

std::vector<std::optional<RayHit>> RayCaster::intersect(std::span<const Ray> rays) const {
  Impl& d = *impl_;
  std::vector<std::optional<RayHit>> hits(rays.size());
  forEachPacket(rays.size(), [&](std::size_t first, std::size_t count) {
    RTCRayHit batch[kPacket];
    for (std::size_t i = 0; i < count; ++i) {
      setRay(batch[i].ray, rays[first + i]);
      batch[i].hit.geomID = RTC_INVALID_GEOMETRY_ID;
      batch[i].hit.instID[0] = RTC_INVALID_GEOMETRY_ID;
    }
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    // The rays of a batch are mostly a camera's pixels, side by side: traced as coherent
    // packets, a cloud is made in about two thirds of the time. On an edge two triangles
    // share, either may be the hit.
    context.flags = RTC_INTERSECT_CONTEXT_FLAG_COHERENT;
    rtcIntersect1M(d.scene, &context, batch, static_cast<unsigned>(count), sizeof(RTCRayHit));
    for (std::size_t i = 0; i < count; ++i) {
      if (batch[i].hit.geomID == RTC_INVALID_GEOMETRY_ID) continue;
      const Ray& ray = rays[first + i];
      RayHit hit;
      hit.t = batch[i].ray.tfar;
      hit.point = ray.origin + hit.t * ray.direction;
      hit.triangle = static_cast<int>(batch[i].hit.primID);
      hit.normal = d.normals[hit.triangle];
      hit.face = d.triangle_faces[hit.triangle];
      hits[first + i] = hit;
    }
  });
  d.check();
  return hits;
}

std::vector<bool> RayCaster::occluded(std::span<const Ray> rays) const {
  Impl& d = *impl_;
  std::vector<char> blocked(rays.size(), 0);
  forEachPacket(rays.size(), [&](std::size_t first, std::size_t count) {
    RTCRay batch[kPacket];
    for (std::size_t i = 0; i < count; ++i) setRay(batch[i], rays[first + i]);
    RTCIntersectContext context;
    rtcInitIntersectContext(&context);
    rtcOccluded1M(d.scene, &context, batch, static_cast<unsigned>(count), sizeof(RTCRay));
    // Embree marks an occluded ray by setting tfar to -inf.
    for (std::size_t i = 0; i < count; ++i) blocked[first + i] = batch[i].tfar < 0;
  });
  d.check();
  return {blocked.begin(), blocked.end()};
}

std::vector<std::optional<RayHit>> castRays(const TriangleMesh& mesh, std::span<const Ray> rays) {
  return RayCaster(mesh).intersect(rays);
}

}  // namespace scanplan
