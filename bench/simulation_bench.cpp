// Acquisition simulation speed: 100 views of NIST CTC 02 (about 100k triangles), in rays
// per second, next to a bare Embree occlusion loop over the same rays.
//
//   build/release/bench/scanplan_bench --benchmark_filter=Simulat

#include <scanplan/cad/import.h>
#include <scanplan/cad/raycast.h>
#include <scanplan/planning/poses.h>
#include <scanplan/scanner/simulation.h>

#include <benchmark/benchmark.h>
#include <embree3/rtcore.h>
#include <tbb/parallel_for.h>

#include <filesystem>
#include <optional>

namespace {

using namespace scanplan;

struct Scene {
  Part part;
  SimulationOptions options;
  std::optional<Simulator> simulator;
  std::vector<View> views;
  std::vector<Ray> rays;  // the occlusion rays the simulation casts for all views
};

// 100 views on a hemisphere around targets spread over the part, looking at them from
// the standoff.
std::vector<View> hemisphereViews(const Box& box, double standoff, int count) {
  std::vector<View> views;
  const double golden = M_PI * (3 - std::sqrt(5.0));
  for (int i = 0; i < count; ++i) {
    const double z = 0.15 + 0.85 * (i + 0.5) / count;  // elevation above ~9 degrees
    const double r = std::sqrt(1 - z * z);
    const Vec3 direction(r * std::cos(golden * i), r * std::sin(golden * i), z);
    const Vec3 target(box.min.x() + box.size().x() * ((i * 7 % count) + 0.5) / count,
                      box.min.y() + box.size().y() * ((i * 13 % count) + 0.5) / count, box.max.z());
    View view;
    view.id = i + 1;
    view.target = target;
    view.camera_to_world = lookAt(target + standoff * direction, target);
    views.push_back(view);
  }
  return views;
}

Scene* scene() {
  static Scene* cached = [] {
    const std::string path =
        std::string(SCANPLAN_SHARED_DATA) + "/nist/nist_ctc_02_asme1_ap242-e2.stp";
    if (!std::filesystem::exists(path)) return static_cast<Scene*>(nullptr);
    auto* s = new Scene;
    ImportOptions import;
    import.linear_deflection = 0.05;  // mm: about 100k triangles
    s->part = importPart(path, import);
    const Box box = s->part.bounds();
    s->options.part_to_world.translation() = Vec3(0, 0, -box.min.z());  // on the working plane
    Scanner scanner;
    s->simulator.emplace(s->part, scanner, s->options);
    Box world = box;
    world.min.z() = 0;
    world.max.z() = box.size().z();
    s->views = hemisphereViews(world, scanner.standoff, 100);
    // The rays the simulation casts: two per facet that passes the geometric tests.
    const std::vector<SurfacePoint> facets = s->simulator->facetPoints();
    const double offset = std::max(s->options.surface_offset * box.diagonal(), 1e-4);
    const auto losses = s->simulator->measure(s->views, facets);
    for (std::size_t v = 0; v < s->views.size(); ++v) {
      const Vec3 eyes[2] = {s->views[v].camera(), projectorPosition(s->views[v], scanner)};
      for (std::size_t f = 0; f < facets.size(); ++f) {
        const Loss loss = losses[v][f];
        if (loss != Loss::Measured && loss != Loss::CameraOccluded &&
            loss != Loss::ProjectorOccluded)
          continue;
        for (const Vec3& eye : eyes) {
          Ray ray;
          ray.origin = facets[f].position + offset * facets[f].normal;
          ray.direction = eye - ray.origin;
          ray.t_far = 1;
          s->rays.push_back(ray);
        }
      }
    }
    return s;
  }();
  return cached;
}

void BM_SimulateHundredViews(benchmark::State& state) {
  Scene* s = scene();
  if (!s) return state.SkipWithError("shared data not found");
  std::size_t rays = 0;
  for (auto _ : state) {
    auto acquisitions = s->simulator->acquire(s->views);
    rays = 0;
    for (const Acquisition& a : acquisitions) rays += a.rays;
    benchmark::DoNotOptimize(acquisitions);
  }
  state.counters["triangles"] = static_cast<double>(s->part.mesh.triangles.size());
  state.counters["rays"] = static_cast<double>(rays);
  state.counters["rays_per_second"] =
      benchmark::Counter(static_cast<double>(rays), benchmark::Counter::kIsIterationInvariantRate);
}
BENCHMARK(BM_SimulateHundredViews)->Unit(benchmark::kMillisecond)->UseRealTime();

// The same occlusion rays through rtcOccluded1, one ray at a time, in a plain parallel loop.
void BM_BareEmbreeOcclusion(benchmark::State& state) {
  Scene* s = scene();
  if (!s) return state.SkipWithError("shared data not found");
  RTCDevice device = rtcNewDevice(nullptr);
  RTCScene rtc_scene = rtcNewScene(device);
  RTCGeometry geometry = rtcNewGeometry(device, RTC_GEOMETRY_TYPE_TRIANGLE);
  const TriangleMesh& mesh = s->part.mesh;
  auto* vertices = static_cast<float*>(rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_VERTEX, 0,
                                                               RTC_FORMAT_FLOAT3, 3 * sizeof(float),
                                                               mesh.vertices.size()));
  auto* indices = static_cast<unsigned*>(
      rtcSetNewGeometryBuffer(geometry, RTC_BUFFER_TYPE_INDEX, 0, RTC_FORMAT_UINT3,
                              3 * sizeof(unsigned), mesh.triangles.size()));
  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    const Vec3 p = s->options.part_to_world * mesh.vertices[i];
    for (int k = 0; k < 3; ++k) vertices[3 * i + k] = static_cast<float>(p[k]);
  }
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) indices[3 * t + k] = static_cast<unsigned>(mesh.triangles[t][k]);
  rtcCommitGeometry(geometry);
  rtcAttachGeometry(rtc_scene, geometry);
  rtcReleaseGeometry(geometry);
  rtcCommitScene(rtc_scene);

  std::vector<char> blocked(s->rays.size());
  for (auto _ : state) {
    tbb::parallel_for(std::size_t{0}, s->rays.size(), [&](std::size_t i) {
      const Ray& r = s->rays[i];
      RTCRay ray{};
      ray.org_x = static_cast<float>(r.origin.x());
      ray.org_y = static_cast<float>(r.origin.y());
      ray.org_z = static_cast<float>(r.origin.z());
      ray.dir_x = static_cast<float>(r.direction.x());
      ray.dir_y = static_cast<float>(r.direction.y());
      ray.dir_z = static_cast<float>(r.direction.z());
      ray.tnear = 0;
      ray.tfar = 1;
      ray.mask = 0xFFFFFFFFu;
      RTCIntersectContext context;
      rtcInitIntersectContext(&context);
      rtcOccluded1(rtc_scene, &context, &ray);
      blocked[i] = ray.tfar < 0;
    });
    benchmark::DoNotOptimize(blocked.data());
  }
  state.counters["rays"] = static_cast<double>(s->rays.size());
  state.counters["rays_per_second"] = benchmark::Counter(
      static_cast<double>(s->rays.size()), benchmark::Counter::kIsIterationInvariantRate);
  rtcReleaseScene(rtc_scene);
  rtcReleaseDevice(device);
}
BENCHMARK(BM_BareEmbreeOcclusion)->Unit(benchmark::kMillisecond)->UseRealTime();

}  // namespace
