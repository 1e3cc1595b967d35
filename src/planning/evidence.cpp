// The report's evidence: simulated clouds and visibility maps of a plan.

#include <scanplan/planning/evidence.h>
#include <scanplan/planning/planner.h>
#include <scanplan/planning/poses.h>

#include <algorithm>
#include <cmath>
#include <map>

namespace scanplan {

void forEachViewCloud(const Plan& plan, const Part& part, const ResolvedSpec& resolved,
                      double spacing, const Progress& progress,
                      const std::function<void(std::size_t, PointCloud&&)>& take) {
  const std::vector<std::size_t> orientation_of = viewOrientations(plan);
  std::size_t done = 0;
  for (std::size_t k = 0; k < std::max<std::size_t>(1, plan.orientations.size()); ++k) {
    const Pose placement = orientationPlacement(plan, k);
    const Simulator simulator(part, plan.scanner, simulationOptionsFor(resolved, part, placement));
    const Pose to_scene = plan.part_to_world * placement.inverse();
    for (std::size_t i = 0; i < plan.views.size(); ++i) {
      if (orientation_of[i] != k) continue;
      report(progress, "simulated clouds",
             static_cast<double>(done++) / static_cast<double>(plan.views.size()));
      PointCloud cloud = simulator.cloud(plan.views[i], static_cast<std::uint64_t>(i + 1), spacing);
      for (Vec3& p : cloud.points) p = to_scene * p;
      for (Vec3& v : cloud.normals) v = to_scene.linear() * v;
      take(i, std::move(cloud));
    }
  }
  report(progress, "simulated clouds", 1);
}

std::vector<std::vector<int>> measuredByViews(const Plan& plan, const Part& part,
                                              const ResolvedSpec& spec,
                                              std::span<const SurfacePoint> points) {
  std::vector<std::vector<int>> measured(plan.views.size());
  const std::vector<std::size_t> orientation_of = viewOrientations(plan);
  for (std::size_t k = 0; k < std::max<std::size_t>(1, plan.orientations.size()); ++k) {
    std::vector<View> views;
    std::vector<std::size_t> indices;  // into plan.views
    for (std::size_t v = 0; v < plan.views.size(); ++v)
      if (orientation_of[v] == k) {
        views.push_back(plan.views[v]);
        indices.push_back(v);
      }
    if (views.empty()) continue;
    const Pose placed = orientationPlacement(plan, k);
    std::vector<SurfacePoint> world(points.begin(), points.end());
    for (SurfacePoint& p : world) {
      p.position = placed * p.position;
      p.normal = placed.linear() * p.normal;
    }
    const Simulator simulator(part, plan.scanner, simulationOptionsFor(spec, part, placed));
    std::vector<std::vector<int>> by_view = measuredPoints(simulator, views, world);
    for (std::size_t j = 0; j < views.size(); ++j) measured[indices[j]] = std::move(by_view[j]);
  }
  return measured;
}

std::vector<PointCloud> viewClouds(const Plan& plan, const Part& part, const ResolvedSpec& spec,
                                   double spacing, const Progress& progress) {
  std::vector<PointCloud> clouds(plan.views.size());
  forEachViewCloud(plan, part, spec, spacing, progress,
                   [&](std::size_t i, PointCloud&& cloud) { clouds[i] = std::move(cloud); });
  return clouds;
}

std::vector<ClusterMap> clusterMaps(const Plan& plan, const Part& part,
                                    const ResolvedSpec& resolved, const Progress& progress) {
  const Spec& spec = resolved.spec;
  std::vector<Sample> samples;
  std::map<int, std::vector<int>> members_of;
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    samples.push_back(plan.samples[i].sample);
    if (samples.back().cluster >= 0)
      members_of[samples.back().cluster].push_back(static_cast<int>(i));
  }
  const Simulator simulator(part, plan.scanner,
                            simulationOptionsFor(resolved, part, plan.part_to_world));
  const VisibilityOptions vo =
      plannerVisibility(plan.scanner, spec.planner.vm_step, spec.working_plane);
  std::vector<ClusterMap> clusters;
  std::size_t done = 0;
  for (const auto& [id, members] : members_of) {
    report(progress, "visibility maps",
           static_cast<double>(done++) / static_cast<double>(members_of.size()));
    ClusterMap cluster;
    cluster.id = id + 1;
    cluster.members = members;
    cluster.map = combinedVisibilityMap(simulator, surfacePoints(samples, members), vo);
    Vec3 position = Vec3::Zero(), normal = Vec3::Zero();
    for (int i : members) {
      position += samples[i].position;
      normal += samples[i].normal;
    }
    cluster.position = position / static_cast<double>(members.size());
    cluster.normal = normal.normalized();
    clusters.push_back(std::move(cluster));
  }
  report(progress, "visibility maps", 1);
  return clusters;
}

ReportEvidence reportEvidence(const Plan& plan, const Part& part, const ResolvedSpec& spec,
                              const EvidenceOptions& options, const Progress& progress) {
  ReportEvidence evidence;
  if (options.clouds) {
    Box part_box;  // of the part as the scene places it
    for (const Vec3& v : part.mesh.vertices) part_box.add(plan.part_to_world * v);
    const Scanner& scanner = plan.scanner;
    const double spacing =
        options.cloud_spacing > 0
            ? options.cloud_spacing
            : std::max(std::min(std::sqrt(scanner.fov_width * scanner.fov_height / 2500),
                                part_box.diagonal() / 60),
                       scanner.point_spacing);
    evidence.clouds = viewClouds(plan, part, spec, spacing, progress);
  }
  if (options.visibility_maps && !plan.samples.empty())
    evidence.clusters = clusterMaps(plan, part, spec, progress);
  return evidence;
}

}  // namespace scanplan
