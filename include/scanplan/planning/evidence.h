#pragma once
// What the report shows beside the plan, made by the planning stages' own simulation and
// visibility maps (docs/report.md): each view's simulated cloud, and each cluster's
// Combined Visibility Map.

#include <scanplan/cad/part.h>
#include <scanplan/core/progress.h>
#include <scanplan/plan/inspection.h>
#include <scanplan/plan/plan.h>
#include <scanplan/scanner/simulation.h>
#include <scanplan/scanner/visibility.h>
#include <scanplan/spec/spec.h>

#include <functional>
#include <optional>
#include <span>
#include <vector>

namespace scanplan {

// Calls `take(index, cloud)` with each view's simulated cloud (camera rays `spacing` mm
// apart) in the plan's scene frame, the world of its first placement, one view at a time,
// the part placed as the view's orientation places it; view i is seeded i + 1.
void forEachViewCloud(const Plan& plan, const Part& part, const ResolvedSpec& spec, double spacing,
                      const Progress& progress,
                      const std::function<void(std::size_t, PointCloud&&)>& take);

// For each view of `plan` (in plan order), the indices of `points` (part frame) its
// simulation measures, each view in its rest orientation's placement.
std::vector<std::vector<int>> measuredByViews(const Plan& plan, const Part& part,
                                              const ResolvedSpec& spec,
                                              std::span<const SurfacePoint> points);

// The clouds of forEachViewCloud, per view in plan order.
std::vector<PointCloud> viewClouds(const Plan& plan, const Part& part, const ResolvedSpec& spec,
                                   double spacing, const Progress& progress = {});

// A cluster of the plan's samples and its Combined Visibility Map over all its members.
struct ClusterMap {
  int id = 0;                    // 1-based
  std::vector<int> members;      // indices into the plan's samples
  Vec3 position = Vec3::Zero();  // the members' mean position
  Vec3 normal = Vec3::UnitZ();   // and their mean normal, unit
  VisibilityMap map;
};

// What the report shows beside the plan, and how finely.
struct EvidenceOptions {
  double cloud_spacing = 0;     // mm between the camera rays of each view's cloud; 0: about
                                // 2,500 points over the field of view, finer on a part much
                                // smaller than it
  bool clouds = true;           // each view's simulated cloud
  bool visibility_maps = true;  // each cluster's Combined Visibility Map
};

struct ReportEvidence {
  std::vector<PointCloud> clouds;  // per view, in plan order; none without clouds
  std::vector<ClusterMap> clusters;
  std::optional<Inspection> inspection;  // of the plan, when one was made (scanplan inspect)
};

// The clusters of the planner's first round of iterative adding (Sample::cluster, as
// plan.json records it) with their maps, the part placed as the plan's first placement puts
// it, with the planner's map options (planner.vm_step, cell.working_plane).
std::vector<ClusterMap> clusterMaps(const Plan& plan, const Part& part, const ResolvedSpec& spec,
                                    const Progress& progress = {});

// The evidence `options` asks for: the views' clouds, then the clusters' maps.
ReportEvidence reportEvidence(const Plan& plan, const Part& part, const ResolvedSpec& spec,
                              const EvidenceOptions& options = {}, const Progress& progress = {});

}  // namespace scanplan
