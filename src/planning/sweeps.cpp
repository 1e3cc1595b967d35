// Sweep positioning (docs/sweep.md): surfaces much wider than the field of view, tile by
// tile.

#include "core/kd_tree.h"
#include "planning/stages.h"

#include <map>
#include <set>

namespace scanplan::detail {
namespace {

struct SweepTarget {
  Sweep sweep;
  SurfaceGrid grid;  // world frame
};

SurfaceGrid toWorld(SurfaceGrid grid, const Pose& part_to_world) {
  for (Vec3& p : grid.points) p = part_to_world * p;
  for (Vec3& n : grid.normals) n = part_to_world.linear() * n;
  return grid;
}

// The sweeps the samples ask for: one per set of like-facing faces of the surface task,
// over its interpolated patch; one per gdt face whose samples spread over twice the field
// of view, over the face's parameters (its own patch on a mesh part).
std::vector<SweepTarget> sweepTargets(const Part& part, const std::vector<PlannedSample>& samples,
                                      const Pose& part_to_world, const Scanner& scanner,
                                      const std::vector<char>& done) {
  const double grid_spacing = std::min(scanner.fov_width, scanner.fov_height) / 16;
  const double fit_spacing = std::min(scanner.fov_width, scanner.fov_height) / 12;
  std::set<int> surface_faces;
  std::map<int, std::vector<Vec3>> gdt_faces;
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (!done.empty() && done[i]) continue;
    const PlannedSample& s = samples[i];
    if (s.sample.task == TaskType::Surface) surface_faces.insert(s.sample.face);
    if (s.sample.task == TaskType::Gdt) gdt_faces[s.sample.face].push_back(s.sample.position);
  }
  std::vector<SweepTarget> targets;
  constexpr double kMaxSpread = 80;  // degrees: a set seen along one direction
  if (!surface_faces.empty())
    for (const std::vector<int>& set :
         segmentByNormal(part, {surface_faces.begin(), surface_faces.end()}, kMaxSpread)) {
      SweepTarget target;
      target.sweep.task = TaskType::Surface;
      target.sweep.faces = set;
      if (normalSpread(part, set) <= kMaxSpread) {
        const InterpolatedPatch patch = interpolatedPatch(part, set, fit_spacing, grid_spacing);
        target.sweep.patch = SweepPatch{patch.frame.linear().col(2), patch.tolerance,
                                        patch.max_deviation, patchShape(patch)};
        target.grid = toWorld(patch.grid, part_to_world);
      } else if (part.brep) {
        // One face turning too far to be seen along one direction (a cylinder): swept
        // over its own parameters.
        target.grid = toWorld(faceGrid(part, set.front(), grid_spacing), part_to_world);
      } else {
        continue;  // left to iterative adding
      }
      targets.push_back(std::move(target));
    }
  for (const auto& [face, points] : gdt_faces) {
    if (!needsSweep(points, scanner)) continue;
    if (!part.brep && normalSpread(part, {face}) > kMaxSpread) continue;
    SweepTarget target;
    target.sweep.task = TaskType::Gdt;
    target.sweep.faces = {face};
    target.grid =
        toWorld(part.brep ? faceGrid(part, face, grid_spacing)
                          : interpolatedPatch(part, {face}, fit_spacing, grid_spacing).grid,
                part_to_world);
    targets.push_back(std::move(target));
  }
  return targets;
}

// The samples of `target` by tile: each goes to the tile of its nearest inside grid node.
std::vector<std::vector<int>> tileMembers(const SweepTarget& target,
                                          const std::vector<SweepTile>& tiles,
                                          const std::vector<PlannedSample>& samples,
                                          const std::vector<char>& done) {
  std::vector<Vec3> nodes;
  std::vector<int> node_tile;
  for (std::size_t t = 0; t < tiles.size(); ++t)
    for (std::size_t k : tiles[t].nodes) {
      nodes.push_back(target.grid.points[k]);
      node_tile.push_back(static_cast<int>(t));
    }
  std::vector<std::vector<int>> members(tiles.size());
  if (nodes.empty()) return members;
  const detail::PointCloudAdaptor cloud{nodes};
  detail::PointTree tree(3, cloud);
  tree.buildIndex();
  const std::set<int> faces(target.sweep.faces.begin(), target.sweep.faces.end());
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const Sample& s = samples[i].sample;
    if (s.task != target.sweep.task || !faces.count(s.face) || (!done.empty() && done[i])) continue;
    unsigned nearest = 0;
    double distance = 0;
    tree.knnSearch(s.position.data(), 1, &nearest, &distance);
    members[node_tile[nearest]].push_back(static_cast<int>(i));
  }
  return members;
}

// The view of a sweep tile: its tilePose, or, when that pose is not valid or misses some
// of the tile's samples, the best tilted pose for them if it measures more.
std::optional<View> tileView(const Placement& at, const SweepTile& tile,
                             const std::vector<int>& members, const std::vector<Sample>& samples,
                             std::vector<View>& candidates) {
  const View view = tilePose(at.scanner(), tile);
  std::vector<SurfacePoint> targets;
  for (int i : members) targets.push_back(at.points[i]);
  auto measuredCount = [&](const View& v) { return measuredBy(at.simulator, v, targets).size(); };
  const std::size_t count = poseIsValid(at.simulator, view, at.cell) ? measuredCount(view) : 0;
  if (count == members.size()) return view;
  std::vector<Sample> member_samples;
  for (int i : members) member_samples.push_back(samples[i]);
  std::vector<Visibility> status;
  const std::optional<View> tilted =
      clusterPose(at, member_samples, tile.centre, tile.normal, false, status, candidates);
  if (tilted && measuredCount(*tilted) > count) return tilted;
  if (count > 0) return view;
  return std::nullopt;
}

}  // namespace

std::vector<Sweep> sweepViews(const Placement& at, std::vector<PlannedSample>& samples,
                              MeasuredViews& added, std::vector<View>& candidates,
                              const Progress& progress) {
  std::vector<Sample> world;
  for (const PlannedSample& s : samples) world.push_back(s.sample);
  std::vector<Sweep> sweeps;
  for (SweepTarget& target : sweepTargets(at.part, samples, at.simulator.options().part_to_world,
                                          at.scanner(), at.done)) {
    report(progress,
           "sweep positioning over " + std::to_string(target.sweep.faces.size()) + " face(s)", 0);
    const std::vector<SweepTile> tiles =
        sweepTiles(target.grid, at.scanner(), at.settings().sweep_overlap);
    const std::vector<std::vector<int>> members = tileMembers(target, tiles, samples, at.done);
    target.sweep.tiles = tiles.size();
    for (std::size_t t = 0; t < tiles.size(); ++t) {
      if (members[t].empty()) continue;
      std::optional<View> view = tileView(at, tiles[t], members[t], world, candidates);
      if (!view) continue;
      view->task = std::string(toString(target.sweep.task));
      if (addView(*view, measuredBy(at.simulator, *view, at.points), samples, added))
        target.sweep.views.push_back(static_cast<int>(added.size()));
    }
    // The tiling without overlap too, as candidates: the fewest views a face can take.
    if (target.sweep.task == TaskType::Gdt)
      for (const SweepTile& tile : sweepTiles(target.grid, at.scanner(), 0)) {
        const View view = tilePose(at.scanner(), tile);
        if (poseIsValid(at.simulator, view, at.cell)) candidates.push_back(view);
      }
    sweeps.push_back(std::move(target.sweep));
  }
  return sweeps;
}

}  // namespace scanplan::detail
