// Iterative pose adding and pruning by marginal coverage (DESIGN.md §5).

#include "sampling/sample_tree.h"

#include <scanplan/errors.h>
#include <scanplan/localization.h>
#include <scanplan/planning.h>
#include <scanplan/set_cover.h>
#include <scanplan/visibility.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <map>
#include <numeric>
#include <set>

namespace scanplan {

std::string_view toString(Uncoverable reason) {
  switch (reason) {
    case Uncoverable::None: return "none";
    case Uncoverable::BelowWorkingPlane: return "occluded_by_working_plane";
    case Uncoverable::OccludedByPart: return "occluded_by_part";
    case Uncoverable::NoValidPose: return "no_valid_pose";
    case Uncoverable::Lost: return "lost_in_simulation";
    case Uncoverable::Unreachable: return "unreachable_by_robot";
  }
  return "unknown";
}

std::size_t Plan::measuredCount() const {
  return static_cast<std::size_t>(
      std::count_if(samples.begin(), samples.end(),
                    [](const PlannedSample& s) { return !s.measured_by.empty(); }));
}

std::size_t Plan::notCoverableCount() const {
  return static_cast<std::size_t>(
      std::count_if(samples.begin(), samples.end(),
                    [](const PlannedSample& s) { return s.uncoverable != Uncoverable::None; }));
}

std::size_t Plan::registeredMeasuredCount() const {
  if (!registration) return measuredCount();
  std::vector<char> registered;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const int id = views[v].id;
    if (id >= static_cast<int>(registered.size())) registered.resize(id + 1, 0);
    registered[id] =
        v < registration->views.size() && registration->views[v].method != RegistrationMethod::None;
  }
  return static_cast<std::size_t>(
      std::count_if(samples.begin(), samples.end(), [&](const PlannedSample& s) {
        return std::any_of(s.measured_by.begin(), s.measured_by.end(), [&](int id) {
          return id < static_cast<int>(registered.size()) && registered[id];
        });
      }));
}

PlanningOptions planningOptionsFor(const Spec& spec) {
  PlanningOptions options;
  options.vm_step = spec.planner.vm_step;
  options.tilt_min = spec.planner.tilt_min;
  options.tilt_max = spec.planner.tilt_max;
  options.max_failures = spec.planner.max_failures;
  options.sweep_overlap = spec.planner.sweep_overlap;
  options.seed = spec.planner.seed;
  options.cell = spec.cell;
  return options;
}

SimulationOptions simulationOptionsFor(const Part& part, const Spec& spec,
                                       const Pose& part_to_world) {
  SimulationOptions simulation;
  simulation.part_to_world = part_to_world;
  simulation.working_plane = spec.working_plane;
  simulation.specular_faces = resolveFaces(part, spec.specular, spec.source);
  return simulation;
}

std::vector<Marker> specMarkers(const Spec& spec, const Part& part, const Pose& part_to_world) {
  if (!spec.markers_file.empty()) return readMarkers(spec.markers_file);
  if (!(spec.marker_grid > 0)) return {};
  TriangleMesh world = part.mesh;
  for (Vec3& v : world.vertices) v = part_to_world * v;
  std::vector<Marker> markers;
  if (spec.markers_on_part) markers = markersOnPart(world, spec.marker_grid);
  if (spec.markers_on_plate) {
    Box footprint;
    for (const Vec3& v : world.vertices) footprint.add(v);
    const auto plate = markerGrid(footprint, spec.marker_grid, spec.marker_margin);
    markers.insert(markers.end(), plate.begin(), plate.end());
  }
  return markers;
}

Pose restingPlacement(const Part& part) {
  Pose placement = Pose::Identity();
  placement.translation() = Vec3(0, 0, -part.bounds().min.z());
  return placement;
}

namespace {

constexpr double kDeg = M_PI / 180;

// The scanner body in S: a box around camera (origin) and projector, grown by the margin,
// reaching body_depth behind the camera.
std::array<Vec3, 8> bodyCorners(const Scanner& scanner, const PlanningOptions& options) {
  const double m = options.body_margin, b = scanner.baseline();
  std::array<Vec3, 8> corners;
  for (int i = 0; i < 8; ++i)
    corners[i] = Vec3(i & 1 ? b + m : -m, i & 2 ? m : -m, i & 4 ? m : -options.body_depth);
  return corners;
}

}  // namespace

bool poseIsValid(const Simulator& simulator, const View& view, const PlanningOptions& options) {
  const auto corners = bodyCorners(simulator.scanner(), options);
  std::array<Vec3, 8> world;
  for (int i = 0; i < 8; ++i) world[i] = view.camera_to_world * corners[i];
  if (simulator.options().working_plane)
    for (const Vec3& c : world)
      if (c.z() < 0) return false;
  // The body's 12 edges and 4 space diagonals must not cross the part or a fixture.
  std::vector<Ray> segments;
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4})
      if (!(i & bit)) segments.push_back(Ray{world[i], world[i | bit] - world[i], 0, 1});
  for (int i = 0; i < 4; ++i) segments.push_back(Ray{world[i], world[7 - i] - world[i], 0, 1});
  const auto blocked = simulator.occluded(segments);
  if (std::any_of(blocked.begin(), blocked.end(), [](bool b) { return b; })) return false;
  return !options.cell ||
         reachView(*options.cell, view, {}, 0, options.collisions.get()).reachable();
}

namespace {

// A unit baseline direction perpendicular to the view axis and horizontal (world +X when
// the axis is vertical): the rotation about the axis tried first.
Vec3 horizontalBaseline(const Vec3& axis) {
  const Vec3 horizontal = Vec3::UnitZ().cross(axis);
  return horizontal.norm() < 1e-6 ? Vec3::UnitX() : Vec3(horizontal.normalized());
}

// Poses aimed at one point from every direction of a `step`-degree grid within the
// camera's glancing cone, at the standoff, with `rotations` rotations about the axis.
std::vector<View> densePoses(const Scanner& scanner, const SurfacePoint& p,
                             const VisibilityMap& grid, int rotations) {
  std::vector<View> views;
  for (int c = 0; c < grid.cells(); ++c) {
    const Vec3 d = grid.direction(c);
    if (d.dot(p.normal) < std::cos(scanner.max_camera_angle * kDeg)) continue;
    const Vec3 horizontal = horizontalBaseline(-d);
    for (int r = 0; r < rotations; ++r) {
      View view;
      view.camera_to_world = lookAt(p.position + scanner.standoff * d, p.position,
                                    Eigen::AngleAxisd(2 * M_PI * r / rotations, -d) * horizontal);
      view.target = p.position;
      views.push_back(view);
    }
  }
  return views;
}

}  // namespace

std::vector<char> coverableByDenseCandidates(const Simulator& simulator,
                                             const std::vector<SurfacePoint>& samples,
                                             const PlanningOptions& body, double step,
                                             int rotations) {
  const VisibilityMap grid(step);
  std::vector<char> coverable(samples.size(), 0);
  constexpr std::size_t kBlock = 64;  // samples per batch of poses
  for (std::size_t first = 0; first < samples.size(); first += kBlock) {
    std::vector<View> views;
    std::vector<SurfacePoint> points;
    std::vector<std::size_t> owner;
    for (std::size_t i = first; i < std::min(samples.size(), first + kBlock); ++i)
      for (const View& view : densePoses(simulator.scanner(), samples[i], grid, rotations)) {
        views.push_back(view);
        points.push_back(samples[i]);
        owner.push_back(i);
      }
    const std::vector<Loss> losses = simulator.measurePairs(views, points);
    for (std::size_t k = 0; k < losses.size(); ++k)
      if (losses[k] == Loss::Measured && !coverable[owner[k]] &&
          poseIsValid(simulator, views[k], body))
        coverable[owner[k]] = 1;
  }
  return coverable;
}

namespace {

class Planner {
 public:
  Planner(const Simulator& simulator, std::vector<PlannedSample>& samples,
          const PlanningOptions& options)
      : simulator_(simulator), samples_(samples), options_(options), scanner_(simulator.scanner()) {
    points_.reserve(samples.size());
    for (const PlannedSample& s : samples)
      points_.push_back({s.sample.position, s.sample.normal, s.sample.face});
  }

  // Poses for a cluster: normal positioning, then tilted directions from the CVM, each
  // with rotations about the view axis; the valid one measuring most members wins.
  std::optional<View> bestPose(const std::vector<int>& members, const Vec3& mean_point,
                               const Vec3& mean_normal, bool normal_only,
                               std::vector<Visibility>& status) {
    std::vector<Vec3> directions = {mean_normal};
    if (!normal_only) {
      VisibilityOptions vo;
      vo.step = options_.vm_step;
      vo.cone = std::min(scanner_.max_camera_angle,
                         scanner_.max_projector_angle + scanner_.triangulation_angle);
      vo.reach = scanner_.standoff;
      vo.working_plane = simulator_.options().working_plane;
      std::vector<Sample> cluster;
      for (int i : members) cluster.push_back(samples_[i].sample);
      std::vector<int> all(cluster.size());
      std::iota(all.begin(), all.end(), 0);
      const VisibilityMap cvm = combinedVisibilityMap(simulator_, cluster, all, vo, &status);
      const std::uint32_t top = cvm.max();
      if (top == 0) return std::nullopt;
      // The cells with the most visible samples, in the preferred tilt band first, then
      // closest to the mean normal.
      std::vector<std::pair<double, int>> ranked;
      for (int c = 0; c < cvm.cells(); ++c) {
        if (cvm.counts[c] < top) continue;
        const double tilt =
            std::acos(std::clamp(cvm.direction(c).dot(mean_normal), -1.0, 1.0)) / kDeg;
        const bool in_band = tilt >= options_.tilt_min && tilt <= options_.tilt_max;
        ranked.push_back({(in_band ? 0 : 1000) + tilt, c});
      }
      std::sort(ranked.begin(), ranked.end());
      for (std::size_t k = 0; k < ranked.size() && k < 4; ++k)
        directions.push_back(cvm.direction(ranked[k].second));
    }
    std::vector<SurfacePoint> targets;
    for (int i : members) targets.push_back(points_[i]);
    std::optional<View> best;
    std::size_t best_count = 0;
    for (const Vec3& d : directions) {
      const Vec3 camera = mean_point + scanner_.standoff * d;
      const Vec3 axis = -d;
      const Vec3 horizontal = horizontalBaseline(axis);
      for (int r = 0; r < options_.rotations; ++r) {
        const Vec3 hint = Eigen::AngleAxisd(2 * M_PI * r / options_.rotations, axis) * horizontal;
        View view;
        view.camera_to_world = lookAt(camera, mean_point, hint);
        view.target = mean_point;
        if (!poseIsValid(simulator_, view, options_)) continue;
        candidates_.push_back(view);
        const std::vector<Loss> losses = simulator_.measure(view, targets);
        const auto count =
            static_cast<std::size_t>(std::count(losses.begin(), losses.end(), Loss::Measured));
        if (count > best_count) {  // strict: earlier (normal, horizontal) poses win ties
          best_count = count;
          best = view;
        }
      }
    }
    return best;
  }

  // Shifts the target of `view` (keeping its orientation) towards other pending samples
  // near the cluster, in steps, as long as every member it measured stays measured and it
  // measures more pending samples (DESIGN.md §5, tilted positioning).
  View shiftTarget(const View& view, const std::vector<int>& members,
                   const std::vector<int>& pending) {
    std::vector<SurfacePoint> members_points, nearby_points;
    for (int i : members) members_points.push_back(points_[i]);
    const double reach = 0.5 * std::min(scanner_.fov_width, scanner_.fov_height);
    Vec3 pull = Vec3::Zero();
    for (int i : pending)
      if (std::find(members.begin(), members.end(), i) == members.end() &&
          (points_[i].position - view.target).norm() < 2 * reach) {
        nearby_points.push_back(points_[i]);
        pull += points_[i].position;
      }
    if (nearby_points.empty()) return view;
    pull = pull / static_cast<double>(nearby_points.size()) - view.target;
    // Move only across the view axis: the standoff stays.
    pull -= pull.dot(view.axis()) * view.axis();
    auto measuredCount = [&](const View& v, const std::vector<SurfacePoint>& pts) {
      const auto losses = simulator_.measure(v, pts);
      return static_cast<std::size_t>(std::count(losses.begin(), losses.end(), Loss::Measured));
    };
    const std::size_t members_measured = measuredCount(view, members_points);
    std::size_t best_nearby = measuredCount(view, nearby_points);
    View best = view;
    for (double fraction : {0.25, 0.5, 0.75, 1.0}) {
      View moved = view;
      const Vec3 shift = fraction * pull;
      if (shift.norm() > reach) break;
      moved.camera_to_world.translation() += shift;
      moved.target += shift;
      if (!poseIsValid(simulator_, moved, options_)) continue;
      if (measuredCount(moved, members_points) < members_measured) break;
      const std::size_t nearby = measuredCount(moved, nearby_points);
      if (nearby > best_nearby) {
        best_nearby = nearby;
        best = moved;
      }
    }
    return best;
  }

  // The view of a sweep tile: along its normal with the field of view's width across,
  // or, when that pose is not valid or misses some of the tile's samples, the best tilted
  // pose for them if it measures more.
  std::optional<View> tilePose(const SweepTile& tile, const std::vector<int>& members) {
    View view;
    view.camera_to_world =
        lookAt(tile.centre + scanner_.standoff * tile.normal, tile.centre, tile.across);
    view.target = tile.centre;
    std::vector<SurfacePoint> targets;
    for (int i : members) targets.push_back(points_[i]);
    auto measuredCount = [&](const View& v) {
      const auto losses = simulator_.measure(v, targets);
      return static_cast<std::size_t>(std::count(losses.begin(), losses.end(), Loss::Measured));
    };
    const std::size_t count = poseIsValid(simulator_, view, options_) ? measuredCount(view) : 0;
    if (count == members.size()) return view;
    std::vector<Visibility> status;
    const std::optional<View> tilted = bestPose(members, tile.centre, tile.normal, false, status);
    if (tilted && measuredCount(*tilted) > count) return tilted;
    if (count > 0) return view;
    return std::nullopt;
  }

  const std::vector<SurfacePoint>& points() const { return points_; }
  const std::vector<View>& candidates() const { return candidates_; }

 private:
  const Simulator& simulator_;
  std::vector<PlannedSample>& samples_;
  const PlanningOptions& options_;
  const Scanner& scanner_;
  std::vector<SurfacePoint> points_;
  std::vector<View> candidates_;  // every valid pose evaluated
};

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
        target.sweep.patch = interpolatedPatch(part, set, fit_spacing, grid_spacing);
        target.grid = toWorld(target.sweep.patch->grid, part_to_world);
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

}  // namespace

namespace {

// Plans the views for `sampled` (part frame) with the part placed by `part_to_world`;
// samples marked in `done` (measured in another placement) are not aimed at and count as
// covered in the selection.
Plan planPlacement(const Part& part, const Spec& spec, const std::vector<Sample>& sampled,
                   const Pose& part_to_world, const std::vector<char>& done,
                   const PlanningOptions& given, const Progress& progress) {
  PlanningOptions options = given;
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  auto stage_start = start;
  Plan plan;
  auto lap = [&](const std::string& stage) {
    const auto now = Clock::now();
    plan.times.push_back({stage, std::chrono::duration<double>(now - stage_start).count()});
    stage_start = now;
  };
  plan.part_file = part.file;
  plan.part_faces = part.faces.size();
  plan.part_to_world = part_to_world;
  plan.scanner = spec.scanner;
  for (std::size_t i = 0; i < sampled.size(); ++i) {
    PlannedSample planned;
    planned.sample = sampled[i];
    planned.sample.position = part_to_world * sampled[i].position;
    planned.sample.normal = part_to_world.linear() * sampled[i].normal;
    planned.sample.tangent = part_to_world.linear() * sampled[i].tangent;
    if (!done.empty() && done[i]) planned.failures = options.max_failures;  // never pending
    plan.samples.push_back(planned);
  }
  auto isDone = [&](std::size_t i) { return !done.empty() && done[i]; };

  report(progress, "building the scene", 0);
  plan.fixture_faces = resolveFaces(part, spec.fixture, spec.source).size();
  const Simulator simulator(part, spec.scanner,
                            simulationOptionsFor(part, spec, plan.part_to_world));
  if (options.cell)
    options.collisions = std::make_shared<const CellCollisions>(
        *options.cell, part.mesh, plan.part_to_world, simulator.options().fixtures,
        simulator.options().working_plane, options.cell->clearance);
  Planner planner(simulator, plan.samples, options);
  lap("scene");

  std::vector<View> views;
  std::vector<std::vector<int>> measured;  // per view: sample indices it measures

  // Sweep positioning: one view per tile, kept through the selection below.
  std::vector<std::size_t> pinned;  // indices into `views` of the sweeps' views
  std::vector<std::vector<std::size_t>> sweep_views;
  for (SweepTarget& target :
       sweepTargets(part, plan.samples, plan.part_to_world, spec.scanner, done)) {
    report(progress,
           "sweep positioning over " + std::to_string(target.sweep.faces.size()) + " face(s)", 0);
    const std::vector<SweepTile> tiles =
        sweepTiles(target.grid, spec.scanner, options.sweep_overlap);
    const std::vector<std::vector<int>> members = tileMembers(target, tiles, plan.samples, done);
    target.sweep.tiles = tiles.size();
    sweep_views.emplace_back();
    for (std::size_t t = 0; t < tiles.size(); ++t) {
      if (members[t].empty()) continue;
      std::optional<View> view = planner.tilePose(tiles[t], members[t]);
      if (!view) continue;
      view->task = std::string(toString(target.sweep.task));
      const std::vector<Loss> losses = simulator.measure(*view, planner.points());
      std::vector<int> hits;
      for (std::size_t i = 0; i < losses.size(); ++i)
        if (losses[i] == Loss::Measured) hits.push_back(static_cast<int>(i));
      if (hits.empty()) continue;
      view->id = static_cast<int>(views.size()) + 1;
      for (int i : hits) plan.samples[i].measured_by.push_back(view->id);
      sweep_views.back().push_back(views.size());
      pinned.push_back(views.size());
      views.push_back(*view);
      measured.push_back(std::move(hits));
    }
    plan.sweeps.push_back(std::move(target.sweep));
  }
  lap("sweeps");

  // Iterative pose adding.
  std::vector<Visibility> visibility(plan.samples.size(), Visibility::Free);
  ClusteringOptions clustering = clusteringOptionsFor(spec.scanner, options.seed);
  for (int round = 1;; ++round) {
    std::vector<int> pending;
    for (std::size_t i = 0; i < plan.samples.size(); ++i) {
      const PlannedSample& s = plan.samples[i];
      if (s.measured_by.empty() && s.failures < options.max_failures)
        pending.push_back(static_cast<int>(i));
    }
    if (pending.empty()) break;
    report(progress,
           "planning views, round " + std::to_string(round) + " (" +
               std::to_string(pending.size()) + " samples left)",
           0);
    std::vector<Sample> subset;
    for (int i : pending) subset.push_back(plan.samples[i].sample);
    const std::vector<Cluster> clusters = clusterSamples(subset, clustering);
    std::vector<std::size_t> order(clusters.size());
    std::iota(order.begin(), order.end(), 0);
    std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
      return clusters[a].samples.size() > clusters[b].samples.size();
    });
    bool added = false;
    for (std::size_t k : order) {
      std::vector<int> members;
      for (int local : clusters[k].samples) {
        const int i = pending[local];
        if (plan.samples[i].measured_by.empty())
          members.push_back(i);  // a view this round may have taken it
      }
      if (members.empty()) continue;
      const bool normal_only = plan.samples[members.front()].sample.task == TaskType::Trim;
      std::vector<Visibility> status;
      Vec3 mean_point = Vec3::Zero(), normal_sum = Vec3::Zero();
      for (int i : members) {
        mean_point += plan.samples[i].sample.position;
        normal_sum += plan.samples[i].sample.normal;
      }
      mean_point /= static_cast<double>(members.size());
      const Vec3 mean_normal =
          normal_sum.norm() > 1e-9 ? Vec3(normal_sum.normalized()) : Vec3::UnitZ();
      const std::optional<View> pose =
          planner.bestPose(members, mean_point, mean_normal, normal_only, status);
      for (std::size_t m = 0; m < status.size(); ++m) visibility[members[m]] = status[m];
      for (int i : members) ++plan.samples[i].failures;  // undone below for those measured
      if (!pose) continue;
      View view = planner.shiftTarget(*pose, members, pending);
      view.id = static_cast<int>(views.size()) + 1;
      view.task = std::string(toString(plan.samples[members.front()].sample.task));
      const std::vector<Loss> losses = simulator.measure(view, planner.points());
      std::vector<char> is_member(plan.samples.size(), 0);
      for (int i : members) is_member[i] = 1;
      std::vector<int> hits;
      for (std::size_t i = 0; i < losses.size(); ++i) {
        if (losses[i] == Loss::Measured) {
          hits.push_back(static_cast<int>(i));
          if (plan.samples[i].measured_by.empty() && is_member[i]) --plan.samples[i].failures;
          plan.samples[i].measured_by.push_back(view.id);
        } else if (is_member[i]) {
          plan.samples[i].last_loss = losses[i];
        }
      }
      if (hits.empty()) continue;
      views.push_back(view);
      measured.push_back(std::move(hits));
      added = true;
    }
    if (!added) break;
  }
  lap("view planning");

  // Rescue: a sample still unmeasured gets a pose aimed at it alone, the first valid one
  // of a dense set (10° directions, 8 rotations) whose simulation measures it.
  report(progress, "aiming at the samples left", 0);
  const VisibilityMap dense_grid(10);
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    if (!plan.samples[i].measured_by.empty() || isDone(i)) continue;
    const SurfacePoint& point = planner.points()[i];
    const std::vector<View> poses = densePoses(spec.scanner, point, dense_grid, 8);
    const std::vector<SurfacePoint> same(poses.size(), point);
    const std::vector<Loss> losses = simulator.measurePairs(poses, same);
    for (std::size_t k = 0; k < poses.size(); ++k) {
      if (losses[k] != Loss::Measured || !poseIsValid(simulator, poses[k], options)) continue;
      View view = poses[k];
      view.id = static_cast<int>(views.size()) + 1;
      view.task = std::string(toString(plan.samples[i].sample.task));
      const std::vector<Loss> all = simulator.measure(view, planner.points());
      std::vector<int> hits;
      for (std::size_t j = 0; j < all.size(); ++j)
        if (all[j] == Loss::Measured) {
          hits.push_back(static_cast<int>(j));
          plan.samples[j].measured_by.push_back(view.id);
        }
      views.push_back(view);
      measured.push_back(std::move(hits));
      break;
    }
  }
  lap("rescue");

  // Selection over the pool of the added views and every other valid pose evaluated on
  // the way (each simulated on all samples): a greedy set cover by marginal coverage,
  // then views whose samples all others also measure are dropped (last chosen first),
  // then the rest is ordered by marginal coverage, priority samples first.
  report(progress,
         "selecting among " + std::to_string(views.size() + planner.candidates().size()) + " poses",
         0);
  {
    // The added views' coverage is known; only the other candidates are simulated.
    const auto coverage = simulator.measure(planner.candidates(), planner.points());
    views.insert(views.end(), planner.candidates().begin(), planner.candidates().end());
    for (const std::vector<Loss>& losses : coverage) {
      std::vector<int> hits;
      for (std::size_t i = 0; i < losses.size(); ++i)
        if (losses[i] == Loss::Measured) hits.push_back(static_cast<int>(i));
      measured.push_back(std::move(hits));
    }
  }
  // gain(v): (priority, other) samples v measures that are not yet covered.
  // The sweeps' views are chosen first and stay.
  auto greedy = [&](const std::vector<std::size_t>& pool, bool priority_first) {
    std::vector<char> covered(plan.samples.size(), 0), used(views.size(), 0);
    for (std::size_t i = 0; i < covered.size(); ++i) covered[i] = isDone(i);
    std::vector<std::size_t> chosen = pinned;
    for (std::size_t v : pinned) {
      used[v] = 1;
      for (int i : measured[v]) covered[i] = 1;
    }
    for (;;) {
      std::size_t best = views.size();
      std::pair<std::size_t, std::size_t> best_gain{0, 0};
      for (std::size_t v : pool) {
        if (used[v]) continue;
        std::pair<std::size_t, std::size_t> gain{0, 0};
        for (int i : measured[v])
          if (!covered[i])
            (plan.samples[i].sample.role == Role::Priority ? gain.first : gain.second)++;
        if (!priority_first) gain = {gain.first + gain.second, 0};
        if (gain > best_gain) {
          best_gain = gain;
          best = v;
        }
      }
      if (best == views.size()) return chosen;
      used[best] = 1;
      chosen.push_back(best);
      for (int i : measured[best]) covered[i] = 1;
    }
  };
  std::vector<std::size_t> all(views.size());
  std::iota(all.begin(), all.end(), 0);
  std::vector<std::size_t> kept = greedy(all, false);
  std::vector<int> times_measured(plan.samples.size(), 0);
  for (std::size_t v : kept)
    for (int i : measured[v]) ++times_measured[i];
  for (std::size_t k = kept.size(); k-- > pinned.size();) {
    const auto& mine = measured[kept[k]];
    if (std::all_of(mine.begin(), mine.end(),
                    [&](int i) { return times_measured[i] > 1 || isDone(i); })) {
      for (int i : mine) --times_measured[i];
      kept.erase(kept.begin() + static_cast<std::ptrdiff_t>(k));
    }
  }
  kept = greedy(kept, true);
  for (std::size_t v : kept)
    if (views[v].task.empty()) {  // a candidate: the task of most of the samples it measures
      std::map<TaskType, int> tasks;
      for (int i : measured[v]) ++tasks[plan.samples[i].sample.task];
      views[v].task =
          std::string(toString(std::max_element(tasks.begin(), tasks.end(), [](auto& a, auto& b) {
                                 return a.second < b.second;
                               })->first));
    }
  for (PlannedSample& s : plan.samples) s.measured_by.clear();
  for (std::size_t k = 0; k < kept.size(); ++k) {
    View view = views[kept[k]];
    view.id = static_cast<int>(k) + 1;
    plan.views.push_back(view);
    for (int i : measured[kept[k]]) plan.samples[i].measured_by.push_back(view.id);
  }
  for (std::size_t s = 0; s < plan.sweeps.size(); ++s)
    for (std::size_t v : sweep_views[s])
      plan.sweeps[s].views.push_back(
          static_cast<int>(std::find(pinned.begin(), pinned.end(), v) - pinned.begin()) + 1);
  lap("pruning");

  CellSolutions solutions;  // of the final views, with a cell
  if (options.registration) {
    plan.markers = specMarkers(spec, part, plan.part_to_world);
    RegistrationOptions registration = spec.registration;
    registration.seed = options.seed;
    const std::size_t planned = plan.views.size();
    plan.registration =
        registerViews(simulator, plan.views, plan.markers, registration, options, progress);
    // Bridging views measure samples too.
    const auto bridges = std::span<const View>(plan.views).subspan(planned);
    const auto losses = simulator.measure(bridges, planner.points());
    for (std::size_t b = 0; b < bridges.size(); ++b)
      for (std::size_t i = 0; i < losses[b].size(); ++i)
        if (losses[b][i] == Loss::Measured) plan.samples[i].measured_by.push_back(bridges[b].id);
    lap("registration");
    report(progress, "sequencing " + std::to_string(plan.views.size()) + " views", 0);
    if (options.cell) {
      // In joint space: the order by the robot's travel time, lengths in mm as always.
      solutions = cellSolutions(*options.cell, plan.views, options.collisions.get());
      plan.sequence = sequenceViews(shortestPaths(jointTravelTimes(*options.cell, solutions)),
                                    shortestPaths(directCosts(simulator, plan.views)), plan.views,
                                    *plan.registration);
    } else {
      plan.sequence = sequenceViews(simulator, plan.views, *plan.registration);
    }
    lap("sequencing");
  }
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    PlannedSample& s = plan.samples[i];
    if (!s.measured_by.empty() || isDone(i)) continue;
    s.uncoverable = visibility[i] == Visibility::BelowWorkingPlane ? Uncoverable::BelowWorkingPlane
                    : visibility[i] == Visibility::OccludedByPart  ? Uncoverable::OccludedByPart
                    : s.last_loss == Loss::Measured                ? Uncoverable::NoValidPose
                                                                   : Uncoverable::Lost;
  }
  if (options.cell) {
    // No valid pose: because of the robot, when poses clear of the part measure it.
    std::vector<std::size_t> unposed;
    std::vector<SurfacePoint> points;
    for (std::size_t i = 0; i < plan.samples.size(); ++i)
      if (plan.samples[i].uncoverable == Uncoverable::NoValidPose) {
        unposed.push_back(i);
        points.push_back(planner.points()[i]);
      }
    PlanningOptions free = options;
    free.cell.reset();
    const std::vector<char> coverable =
        coverableByDenseCandidates(simulator, points, free, options.vm_step * 2, options.rotations);
    for (std::size_t k = 0; k < unposed.size(); ++k)
      if (coverable[k]) plan.samples[unposed[k]].uncoverable = Uncoverable::Unreachable;
  }

  if (options.cell) {
    plan.cell = options.cell;
    if (solutions.size() != plan.views.size())  // not sequenced in joint space
      solutions = cellSolutions(*options.cell, plan.views, options.collisions.get());
    plan.cell_poses = cellPoses(*options.cell, plan.views, visitingOrder(plan), solutions);
  }

  if (options.bound) {
    report(progress, "exact set cover over " + std::to_string(views.size()) + " poses", 0);
    const std::vector<std::vector<int>>& sets = measured;
    std::vector<char> required(plan.samples.size());
    for (std::size_t i = 0; i < plan.samples.size(); ++i)
      required[i] = !plan.samples[i].measured_by.empty();
    const SetCoverResult cover = minimumSetCover(sets, required, options.bound_time_limit);
    PlanBound bound;
    bound.candidates = views.size();
    bound.ilp_views = cover.chosen.size();
    bound.lower_bound = cover.lower_bound;
    bound.optimal = cover.optimal;
    bound.seconds = cover.seconds;
    plan.bound = bound;
    lap("set cover bound");
  }
  plan.seconds = std::chrono::duration<double>(Clock::now() - start).count();
  return plan;
}

// Appends `part` (planned in a later rest orientation) to `merged`: its views, registration,
// sequence and sweeps with ids shifted past merged's, and the samples it measures.
void mergeOrientation(Plan& merged, Plan part, const RestOrientation& rest) {
  const int offset = static_cast<int>(merged.views.size());
  auto shift = [&](int& id) {
    if (id > 0) id += offset;
  };
  PlannedOrientation orientation;
  orientation.rest = rest;
  orientation.markers = part.markers;
  for (View& view : part.views) {
    shift(view.id);
    orientation.views.push_back(view.id);
    merged.views.push_back(view);
  }
  if (part.registration) {
    const int reference = part.registration->reference;
    orientation.reference = reference > 0 ? reference + offset : 0;
    appendRegistration(*merged.registration, std::move(*part.registration), offset);
  }
  if (part.sequence) {
    for (int id : part.sequence->views) merged.sequence->views.push_back(id + offset);
    merged.sequence->length += part.sequence->length;
    merged.sequence->nearest_neighbour_length += part.sequence->nearest_neighbour_length;
  }
  merged.cell = part.cell;
  merged.cell_poses.insert(merged.cell_poses.end(), part.cell_poses.begin(), part.cell_poses.end());
  for (Sweep& sweep : part.sweeps) {
    for (int& id : sweep.views) shift(id);
    merged.sweeps.push_back(std::move(sweep));
  }
  for (std::size_t i = 0; i < merged.samples.size(); ++i) {
    PlannedSample& s = merged.samples[i];
    for (int id : part.samples[i].measured_by) s.measured_by.push_back(id + offset);
    // Still not measured: the reason found in the latest orientation.
    s.uncoverable = s.measured_by.empty() ? part.samples[i].uncoverable : Uncoverable::None;
    s.last_loss = part.samples[i].last_loss;
  }
  for (const StageTime& t : part.times) {
    auto same = std::find_if(merged.times.begin(), merged.times.end(),
                             [&](const StageTime& m) { return m.stage == t.stage; });
    if (same == merged.times.end())
      merged.times.push_back(t);
    else
      same->seconds += t.seconds;
  }
  merged.orientations.push_back(std::move(orientation));
}

}  // namespace

Pose placementFor(const Part& part, const Spec& spec) {
  if (spec.rest_pose) return *spec.rest_pose;
  if (spec.rest_face) return restOnFace(part, spec.rest_face, spec.source).part_to_world;
  if (spec.rest_auto || spec.rest_all) return restOrientations(part).front().part_to_world;
  return restingPlacement(part);
}

Plan planViews(const Part& part, const Spec& spec, const PlanningOptions& options,
               const Progress& progress) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  report(progress, "sampling", 0);
  const std::vector<Sample> sampled = sampleSpec(part, spec, samplingOptionsFor(spec.scanner));
  if (sampled.empty())
    throw PlanningError(spec.source, "the spec's tasks leave no sample to plan for");
  const StageTime sampling{"sampling", std::chrono::duration<double>(Clock::now() - start).count()};
  auto finish = [&](Plan& plan) {
    plan.times.insert(plan.times.begin(), sampling);
    plan.seconds = std::chrono::duration<double>(Clock::now() - start).count();
    return plan;
  };
  if (!spec.rest_all) {
    Plan plan = planPlacement(part, spec, sampled, placementFor(part, spec), {}, options, progress);
    return finish(plan);
  }

  // Every rest orientation in turn, steadiest first, each aiming at what the earlier ones
  // left unmeasured; an orientation that adds no view is left out (but the first).
  const std::vector<RestOrientation> rests = restOrientations(part);
  Plan merged;
  std::vector<char> done(sampled.size(), 0);
  for (std::size_t k = 0; k < rests.size(); ++k) {
    if (k > 0 && std::all_of(done.begin(), done.end(), [](char d) { return d != 0; })) break;
    report(progress,
           "rest orientation " + std::to_string(k + 1) + " of " + std::to_string(rests.size()), 0);
    Plan plan = planPlacement(part, spec, sampled, rests[k].part_to_world, done, options, progress);
    if (k > 0 && plan.views.empty()) continue;
    for (std::size_t i = 0; i < plan.samples.size(); ++i)
      done[i] = done[i] || !plan.samples[i].measured_by.empty();
    if (k == 0) {
      merged = plan;
      merged.views.clear();
      merged.cell_poses.clear();
      merged.sweeps.clear();
      merged.times.clear();
      for (PlannedSample& s : merged.samples) s.measured_by.clear();
      if (plan.registration) merged.registration = Registration{};
      if (plan.sequence) merged.sequence = Sequence{};
    }
    mergeOrientation(merged, std::move(plan), rests[k]);
  }
  return finish(merged);
}

}  // namespace scanplan
