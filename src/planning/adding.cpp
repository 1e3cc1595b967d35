// Iterative pose adding and the rescue pass (docs/planning.md): the views that measure the
// samples, cluster by cluster, then sample by sample.

#include "planning/stages.h"

#include <scanplan/sampling/clustering.h>
#include <scanplan/scanner/visibility.h>

#include <algorithm>
#include <numeric>
#include <optional>

#include <tbb/parallel_for.h>

namespace scanplan::detail {

std::vector<int> measuredBy(const Simulator& simulator, const View& view,
                            std::span<const SurfacePoint> points) {
  const std::vector<Loss> losses = simulator.measure(view, points);
  std::vector<int> hits;
  for (std::size_t i = 0; i < losses.size(); ++i)
    if (losses[i] == Loss::Measured) hits.push_back(static_cast<int>(i));
  return hits;
}

bool addView(View view, std::vector<int> measured, std::vector<PlannedSample>& samples,
             MeasuredViews& added) {
  if (measured.empty()) return false;
  view.id = static_cast<int>(added.size()) + 1;
  for (int i : measured) samples[i].measured_by.push_back(view.id);
  added.add(view, std::move(measured));
  return true;
}

std::optional<View> clusterPose(const Placement& at, const std::vector<Sample>& members,
                                const Vec3& mean_point, const Vec3& mean_normal, bool normal_only,
                                std::vector<Visibility>& status, std::vector<View>& candidates) {
  const PlannerSettings& settings = at.settings();
  ClusterDirections options;
  options.tilt_min = settings.tilt_min;
  options.tilt_max = settings.tilt_max;
  options.visibility =
      plannerVisibility(at.scanner(), settings.vm_step, at.simulator.options().working_plane);
  std::vector<SurfacePoint> targets;
  for (const Sample& s : members) targets.push_back({s.position, s.normal, s.face});
  std::vector<View> poses;
  for (const Vec3& d :
       clusterDirections(at.simulator, members, mean_normal, normal_only, options, status))
    for (const View& view : aimedPoses(at.scanner(), mean_point, d, settings.rotations))
      poses.push_back(view);
  std::vector<std::optional<std::size_t>> counts(poses.size());  // none: not a valid pose
  tbb::parallel_for(std::size_t{0}, poses.size(), [&](std::size_t k) {
    if (poseIsValid(at.simulator, poses[k], at.cell))
      counts[k] = measuredBy(at.simulator, poses[k], targets).size();
  });
  std::optional<View> best;
  std::size_t best_count = 0;
  for (std::size_t k = 0; k < poses.size(); ++k) {
    if (!counts[k]) continue;
    candidates.push_back(poses[k]);
    if (*counts[k] > best_count) {  // strict: earlier (normal, horizontal) poses win ties
      best_count = *counts[k];
      best = poses[k];
    }
  }
  return best;
}

namespace {

// Samples still to aim at: not measured, not done elsewhere, not given up.
std::vector<int> pendingSamples(const Placement& at, const std::vector<PlannedSample>& samples,
                                const std::vector<int>& failures) {
  std::vector<int> pending;
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].measured_by.empty() && !at.isDone(i) && failures[i] < at.settings().max_failures)
      pending.push_back(static_cast<int>(i));
  return pending;
}

// The pending samples near `view`'s target (within the field of view) that are not
// `members`: what the target shift tries to take in too.
std::vector<SurfacePoint> nearbyPending(const Placement& at, const View& view,
                                        const std::vector<int>& members,
                                        const std::vector<int>& pending) {
  const double reach = std::min(at.scanner().fov_width, at.scanner().fov_height);
  std::vector<SurfacePoint> nearby;
  for (int i : pending)
    if (std::find(members.begin(), members.end(), i) == members.end() &&
        (at.points[i].position - view.target).norm() < reach)
      nearby.push_back(at.points[i]);
  return nearby;
}

// What adding reads and extends from round to round.
struct Adding {
  std::vector<PlannedSample>& samples;
  MeasuredViews& added;
  std::vector<View>& candidates;
  std::vector<int> failures;  // per sample: views aimed at it that missed it
  std::vector<Visibility> visibility;
  int round = 0;
};

// One view for the cluster of `members` (pending, unmeasured samples): its pose, its
// target shifted towards the other `pending` samples nearby. True when a view was added.
bool addClusterView(const Placement& at, const std::vector<int>& members,
                    const std::vector<int>& pending, Adding& state) {
  std::vector<Sample> cluster;
  std::vector<SurfacePoint> member_points;
  Vec3 mean_point = Vec3::Zero(), normal_sum = Vec3::Zero();
  for (int i : members) {
    cluster.push_back(state.samples[i].sample);
    member_points.push_back(at.points[i]);
    mean_point += cluster.back().position;
    normal_sum += cluster.back().normal;
  }
  mean_point /= static_cast<double>(members.size());
  const Vec3 mean_normal = normal_sum.norm() > 1e-9 ? Vec3(normal_sum.normalized()) : Vec3::UnitZ();
  const bool normal_only = cluster.front().task == TaskType::Trim;
  std::vector<Visibility> status;
  const std::optional<View> pose =
      clusterPose(at, cluster, mean_point, mean_normal, normal_only, status, state.candidates);
  for (std::size_t m = 0; m < status.size(); ++m) state.visibility[members[m]] = status[m];
  if (!pose) {
    for (int i : members) ++state.failures[i];
    return false;
  }
  View view = shiftedTarget(at.simulator, *pose, member_points,
                            nearbyPending(at, *pose, members, pending), at.cell);
  view.task = std::string(toString(cluster.front().task));
  const std::vector<Loss> losses = at.simulator.measure(view, at.points);
  std::vector<int> hits;
  for (std::size_t i = 0; i < losses.size(); ++i)
    if (losses[i] == Loss::Measured) hits.push_back(static_cast<int>(i));
  for (int i : members)
    if (losses[i] != Loss::Measured) {
      ++state.failures[i];
      state.samples[i].last_loss = losses[i];
    }
  return addView(view, std::move(hits), state.samples, state.added);
}

// One round: the pending samples clustered, one view per cluster, largest first. True
// when a view was added.
bool addRound(const Placement& at, const std::vector<int>& pending,
              const ClusteringOptions& clustering, Adding& state) {
  std::vector<Sample> subset;
  for (int i : pending) subset.push_back(state.samples[i].sample);
  const std::vector<Cluster> clusters = clusterSamples(subset, clustering);
  if (state.round == 1)  // the clusters the report shows with their visibility maps
    for (std::size_t k = 0; k < pending.size(); ++k)
      state.samples[pending[k]].sample.cluster = subset[k].cluster;
  std::vector<std::size_t> order(clusters.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return clusters[a].samples.size() > clusters[b].samples.size();
  });
  bool added = false;
  for (std::size_t k : order) {
    std::vector<int> members;
    for (int local : clusters[k].samples)  // a view this round may have taken some
      if (state.samples[pending[local]].measured_by.empty()) members.push_back(pending[local]);
    if (!members.empty()) added = addClusterView(at, members, pending, state) || added;
  }
  return added;
}

// The first valid pose of `poses`, aimed at sample `i`, that measures it.
std::optional<View> firstMeasuring(const Placement& at, std::size_t i,
                                   const std::vector<View>& poses) {
  const std::vector<SurfacePoint> same(poses.size(), at.points[i]);
  const std::vector<Loss> losses = at.simulator.measurePairs(poses, same);
  for (std::size_t k = 0; k < poses.size(); ++k)
    if (losses[k] == Loss::Measured && poseIsValid(at.simulator, poses[k], at.cell))
      return poses[k];
  return std::nullopt;
}

// Where the rescue puts a sample in the field when no pose aimed at it measures it (camera
// frame: shares of the field's width and height and of the depth of field), in this
// order. First farther and across the field away from the projector, where the camera's
// and the projector's rays meet at a narrower angle (about 19 degrees for the generic
// scanner's 25), through openings too narrow for the poses aimed at the sample. Then the
// four places of the wider reference's 74 (coverableByWiderCandidates) that a greedy
// cover takes first: they reach 309 of the 393 samples that only such places reach on the
// GD&T faces of NIST CTC 01, CTC 02, CTC 04 and FTC 06, seen past edges at other angles.
// Last the three a greedy cover takes first on the samples those five leave to the wider
// reference on FTC 06's GD&T faces, the die-cast part and CTC 02's GD&T faces (34 of 65).
constexpr double kRescuePlaces[][3] = {
    {-0.45, 0, 0.25},    {0.25, -0.45, 0.25}, {-0.45, -0.25, 0.25}, {0.45, -0.45, 0},
    {-0.45, 0.25, 0.25}, {-0.45, 0.25, 0},    {-0.45, -0.45, 0.25}, {0.25, 0.45, 0.25}};

// `aimed` moved so that the sample each is aimed at lies at `place` (of kRescuePlaces).
std::vector<View> placed(const Scanner& scanner, const std::vector<View>& aimed,
                         const double (&place)[3]) {
  const Vec3 at = placeInVolume(scanner, place[0], place[1], place[2]);
  std::vector<View> result;
  for (const View& view : aimed) result.push_back(shiftedInView(view, -at));
  return result;
}

// The directions of a grid of `step` degrees from which sample `i` is seen without
// occlusion, within the camera's angle limit.
VisibilityMap freeDirections(const Placement& at, std::size_t i, double step) {
  VisibilityOptions options;
  options.step = step;
  options.cone = at.scanner().max_camera_angle;
  options.reach = at.scanner().standoff;
  return combinedVisibilityMap(at.simulator, {at.points[i]}, options);
}

// How many directions of `free` are free.
std::size_t freeCount(const VisibilityMap& free) {
  return static_cast<std::size_t>(
      std::count_if(free.counts.begin(), free.counts.end(), [](std::uint32_t n) { return n > 0; }));
}

// At most this many free directions on the fine grid make an opening narrow enough to
// look through again, more finely: through a wider one the rescue grid's own poses pass,
// and they are lost for other reasons.
constexpr std::size_t kNarrowCells = 40;

// Poses aimed at sample `i` along the `free` directions, with `rotations` rotations each,
// when those are few (kNarrowCells): an opening narrower than the rescue grid's step may
// let camera and projector both in.
std::vector<View> throughNarrowOpening(const Placement& at, std::size_t i,
                                       const VisibilityMap& free, int rotations) {
  std::vector<View> result;
  if (freeCount(free) > kNarrowCells) return result;
  for (int c = 0; c < free.cells(); ++c) {
    if (free.counts[c] == 0) continue;
    const std::vector<View> around =
        aimedPoses(at.scanner(), at.points[i].position, free.direction(c), rotations);
    result.insert(result.end(), around.begin(), around.end());
  }
  return result;
}

// The rescue's pose for sample `i`: the first valid pose that measures it of the dense
// poses aimed at it; where none does and the sample is seen from some direction of a grid
// of half the step, of those through a narrow opening (planner.rescue.narrow), then of the
// dense poses placed off the centre, place by place (kRescuePlaces).
std::optional<View> rescuePose(const Placement& at, std::size_t i, const VisibilityMap& grid) {
  const PlannerSettings& settings = at.settings();
  const std::vector<View> aimed =
      densePoses(at.scanner(), at.points[i], grid, settings.rescue_rotations);
  if (auto found = firstMeasuring(at, i, aimed)) return found;
  const VisibilityMap free = freeDirections(at, i, settings.rescue_step / 2);
  if (freeCount(free) == 0) return std::nullopt;
  if (settings.rescue_narrow)
    if (auto found =
            firstMeasuring(at, i, throughNarrowOpening(at, i, free, 2 * settings.rescue_rotations)))
      return found;
  for (const auto& place : kRescuePlaces)
    if (auto found = firstMeasuring(at, i, placed(at.scanner(), aimed, place))) return found;
  return std::nullopt;
}

}  // namespace

std::vector<Visibility> addViews(const Placement& at, std::vector<PlannedSample>& samples,
                                 MeasuredViews& added, std::vector<View>& candidates,
                                 const Progress& progress) {
  Adding state{samples, added, candidates, std::vector<int>(samples.size(), 0),
               std::vector<Visibility>(samples.size(), Visibility::Free)};
  const ClusteringOptions clustering = clusteringOptionsFor(at.scanner(), at.settings().seed);
  for (int round = 1;; ++round) {
    const std::vector<int> pending = pendingSamples(at, samples, state.failures);
    if (pending.empty()) break;
    report(progress,
           "planning views, round " + std::to_string(round) + " (" +
               std::to_string(pending.size()) + " samples left)",
           0);
    state.round = round;
    if (!addRound(at, pending, clustering, state)) break;
  }
  return state.visibility;
}

void rescueViews(const Placement& at, std::vector<PlannedSample>& samples, MeasuredViews& added) {
  const PlannerSettings& settings = at.settings();
  const VisibilityMap grid(settings.rescue_step);
  std::vector<std::size_t> pending;
  for (std::size_t i = 0; i < samples.size(); ++i)
    if (samples[i].measured_by.empty() && !at.isDone(i)) pending.push_back(i);
  // A sample's rescue pose depends on the sample alone: found for all at once, then added
  // in the samples' order, but for the samples a rescue view added before has measured.
  std::vector<std::optional<View>> found(pending.size());
  tbb::parallel_for(std::size_t{0}, pending.size(),
                    [&](std::size_t k) { found[k] = rescuePose(at, pending[k], grid); });
  for (std::size_t k = 0; k < pending.size(); ++k) {
    const std::size_t i = pending[k];
    if (!found[k] || !samples[i].measured_by.empty()) continue;
    found[k]->task = std::string(toString(samples[i].sample.task));
    addView(*found[k], measuredBy(at.simulator, *found[k], at.points), samples, added);
  }
}

}  // namespace scanplan::detail
