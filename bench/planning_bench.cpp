// View planning on real parts: the gdt task (faces of the AP242 PMI) and the global task on
// every NIST model, and the global task on a die-cast part. Reports samples, those some
// pose of the pool measures and those measured, views against a plain greedy over dense
// poses (denseGreedy) and against the lower bound of the pool's set cover, the samples a
// wider search reaches and those of them measured (countWiderReach), and seconds.
// BM_Register: registration, bridging and sequencing of NIST plans, with and without
// markers. BM_RegisterGlobal: the global task registered by geometry, and the markers
// proposed.
//
//   build/release/bench/scanplan_bench --benchmark_filter=Plan

#include <scanplan/cad/import.h>
#include <scanplan/io/points_csv.h>
#include <scanplan/planning.h>

#include <benchmark/benchmark.h>
#include <tbb/parallel_for.h>
#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <atomic>
#include <bit>
#include <chrono>
#include <cstdint>
#include <filesystem>
#include <map>
#include <numeric>
#include <set>
#include <span>

namespace {

using namespace scanplan;

// The reference the plan is judged against: a plain greedy set cover over dense poses
// aimed at up to 1,200 target samples spread over the targets (every k-th), along the
// normal and tilted 20° and 40° around it (6 and 8 sides), 4 rotations each, valid poses
// only, with the same simulation. Returns its views once it measures as many target samples
// as the plan, its views once it measures all it can, and the target samples some of its
// poses measure.
struct DenseGreedy {
  std::size_t views = 0, all_views = 0, reachable = 0;
};
DenseGreedy denseGreedy(const Simulator& simulator, const std::vector<SurfacePoint>& points,
                        std::size_t plan_measured) {
  const std::size_t step = std::max<std::size_t>(1, (points.size() + 1199) / 1200);
  std::vector<std::vector<int>> sets;
  for (std::size_t a = 0; a < points.size(); a += step) {
    std::vector<View> poses = ringPoses(simulator.scanner(), points[a], {20, 40}, 90, 4);
    std::erase_if(poses, [&](const View& v) { return !poseIsValid(simulator, v); });
    for (std::vector<int>& hits : measuredPoints(simulator, poses, points))
      if (!hits.empty()) sets.push_back(std::move(hits));
  }
  std::vector<char> covered(points.size(), 0);
  std::size_t reachable = 0;
  for (const auto& set : sets)
    for (int i : set)
      if (!covered[i]) {
        covered[i] = 1;
        ++reachable;
      }
  std::fill(covered.begin(), covered.end(), 0);
  DenseGreedy result;
  result.reachable = reachable;
  std::size_t measured = 0;
  for (;;) {
    std::size_t best = 0, best_gain = 0;
    for (std::size_t s = 0; s < sets.size(); ++s) {
      std::size_t gain = 0;
      for (int i : sets[s]) gain += !covered[i];
      if (gain > best_gain) {
        best_gain = gain;
        best = s;
      }
    }
    if (best_gain == 0) break;
    for (int i : sets[best]) covered[i] = 1;
    if (measured < plan_measured) ++result.views;
    measured += best_gain;
    ++result.all_views;
  }
  return result;
}

// The reference for registration by geometry: the plan's views and dense poses (as
// denseGreedy's) aimed at its samples, each with the condition number of the registration's
// surface points it measures (every fov_height / 40; Gelfand's, as the pair test computes
// it). A pose *locks* at a threshold when that condition is within it. The samples the plan
// measures that only poses which do not lock measure need such views; CBC's bound on the
// fewest of them is returned. At the registration's own limit (max_condition) these are the
// views the planner calls unconstrained; since an overlap can be better conditioned than a
// whole view, the bound is also taken at the largest condition of a view the plan
// registered by ICP.
struct GeometryReference {
  std::size_t poses = 0;
  double worst_registered = 0;   // the largest own condition of a view registered by ICP
  double strict = 0, loose = 0;  // the bounds at max_condition and at worst_registered
  double graph = 0;              // the bound by the poses' registration graph
  double graph_seconds = 0;      // its time
};

// Per pose: its condition number, the samples it measures and the registration's surface
// points it measures (indices ascending).
struct PoseReach {
  double condition = 0;
  std::vector<int> samples;
  std::vector<int> surface;
};
std::vector<PoseReach> poseReach(const Simulator& simulator, const std::vector<View>& poses,
                                 const std::vector<SurfacePoint>& samples,
                                 const std::vector<SurfacePoint>& surface) {
  std::vector<PoseReach> reach(poses.size());
  constexpr std::size_t kChunk = 2000;  // poses measured at a time, to bound memory
  for (std::size_t first = 0; first < poses.size(); first += kChunk) {
    const std::span<const View> chunk(poses.data() + first, std::min(kChunk, poses.size() - first));
    std::vector<std::vector<int>> on_samples = measuredPoints(simulator, chunk, samples);
    const std::vector<std::vector<int>> on_surface = measuredPoints(simulator, chunk, surface);
    for (std::size_t k = 0; k < chunk.size(); ++k) {
      std::vector<Vec3> p, n;
      for (int i : on_surface[k]) {
        p.push_back(surface[i].position);
        n.push_back(surface[i].normal);
      }
      reach[first + k] = {icpCondition(p, n), std::move(on_samples[k]), std::move(on_surface[k])};
    }
  }
  return reach;
}

// CBC's bound on the views among the poses that are not `enough` (by index) which the
// plan's measured samples need, when the poses that are enough measure theirs.
template <class Enough>
double neededViews(const Plan& plan, const std::vector<PoseReach>& reach, Enough enough) {
  std::vector<char> required(plan.samples.size(), 0);
  for (std::size_t i = 0; i < plan.samples.size(); ++i)
    required[i] = !plan.samples[i].measured_by.empty();
  std::vector<std::vector<int>> others;
  for (std::size_t v = 0; v < reach.size(); ++v)
    if (enough(v)) {
      for (int i : reach[v].samples) required[i] = 0;
    } else if (!reach[v].samples.empty()) {
      others.push_back(reach[v].samples);
    }
  if (std::find(required.begin(), required.end(), 1) == required.end()) return 0;
  return minimumSetCover(others, required, {1000000, 20}).lower_bound;
}

// CBC's bound on the views that do not lock at `threshold` which the plan's measured
// samples need.
double unlockedViews(const Plan& plan, const std::vector<PoseReach>& reach, double threshold) {
  return neededViews(plan, reach, [&](std::size_t v) { return reach[v].condition <= threshold; });
}

// The registration graph of poses: two poses are joined when their pair would pass the
// registration's pair test (each measures at least min_overlap of its surface points in the
// overlap, whose condition number is within max_condition). ICP verification is left out,
// so that the graph joins at least what registration could.
class PoseGraph {
 public:
  // `reach` of the `poses` on the `surface` points (poseReach).
  PoseGraph(const Simulator& simulator, const std::vector<View>& poses,
            const std::vector<PoseReach>& reach, const std::vector<SurfacePoint>& surface,
            double max_condition)
      : poses_(poses),
        seen_(reach),
        surface_(surface),
        max_condition_(max_condition),
        diagonal_(std::hypot(simulator.scanner().fov_width, simulator.scanner().fov_height)),
        words_((surface_.size() + 63) / 64),
        bits_(poses.size() * words_, 0),
        smallest_(poses.size(), 0),
        range_(poses.size(), {0, 0}),
        parent_(poses.size()) {
    std::iota(parent_.begin(), parent_.end(), 0);
    placeBits();
    tbb::parallel_for(std::size_t{0}, poses.size(), [&](std::size_t v) {
      std::size_t first = words_, last = 0;
      for (int i : reach[v].surface) {
        const std::size_t bit = bit_of_[i];
        bits_[v * words_ + bit / 64] |= std::uint64_t{1} << (bit % 64);
        first = std::min(first, bit / 64);
        last = std::max(last, bit / 64 + 1);
      }
      if (first < last) range_[v] = {first, last};
      smallest_[v] = normalEigenvalues(reach[v].surface)(0);
    });
  }

  // Joins every pair of poses whose targets are within the field's diagonal and whose
  // pair passes; returns the poses' component roots.
  std::vector<int> components() {
    std::map<std::array<long, 3>, std::vector<int>> cells;  // poses by their target's cell
    for (std::size_t v = 0; v < poses_.size(); ++v)
      if (!seen_[v].surface.empty()) cells[cellOf(poses_[v].target)].push_back(static_cast<int>(v));
    for (std::size_t a = 0; a < poses_.size(); ++a) {
      if (seen_[a].surface.empty()) continue;
      // Each component of the neighbours joins when one of its members does.
      std::map<int, int> group_of;             // by root
      std::vector<std::pair<int, int>> tests;  // (group, pose)
      const int mine = find(static_cast<int>(a));
      for (int b : neighbours(cells, static_cast<int>(a))) {
        const int root = find(b);
        if (root == mine) continue;
        const auto found = group_of.emplace(root, static_cast<int>(group_of.size())).first;
        tests.push_back({found->second, b});
      }
      std::vector<int> roots_of(group_of.size());
      for (const auto& [root, g] : group_of) roots_of[g] = root;
      std::vector<std::atomic<char>> joined(group_of.size());
      tbb::parallel_for(std::size_t{0}, tests.size(), [&](std::size_t t) {
        const auto [g, b] = tests[t];
        if (!joined[g] && joins(static_cast<int>(a), b)) joined[g] = 1;
      });
      for (std::size_t g = 0; g < joined.size(); ++g)
        if (joined[g]) parent_[find(roots_of[g])] = find(static_cast<int>(a));
    }
    std::vector<int> roots(poses_.size());
    for (std::size_t v = 0; v < poses_.size(); ++v) roots[v] = find(static_cast<int>(v));
    return roots;
  }

 private:
  // The surface points' bits in the order of a Morton curve through them, so that what a
  // pose measures, which lies together, takes few words.
  void placeBits() {
    Box box;
    for (const SurfacePoint& p : surface_) box.add(p.position);
    const Vec3 size = (box.max - box.min).cwiseMax(Vec3::Constant(1e-9));
    auto spread = [](std::uint64_t x) {  // 21 bits to every third of 63
      x &= 0x1fffff;
      x = (x | x << 32) & 0x1f00000000ffff;
      x = (x | x << 16) & 0x1f0000ff0000ff;
      x = (x | x << 8) & 0x100f00f00f00f00f;
      x = (x | x << 4) & 0x10c30c30c30c30c3;
      return (x | x << 2) & 0x1249249249249249;
    };
    std::vector<std::pair<std::uint64_t, int>> keys(surface_.size());
    for (std::size_t i = 0; i < surface_.size(); ++i) {
      const Vec3 q = (surface_[i].position - box.min).cwiseQuotient(size) * 2097151.0;
      keys[i] = {spread(static_cast<std::uint64_t>(q.x())) |
                     spread(static_cast<std::uint64_t>(q.y())) << 1 |
                     spread(static_cast<std::uint64_t>(q.z())) << 2,
                 static_cast<int>(i)};
    }
    std::sort(keys.begin(), keys.end());
    bit_of_.resize(surface_.size());
    point_at_.resize(surface_.size());
    for (std::size_t k = 0; k < keys.size(); ++k) {
      bit_of_[keys[k].second] = k;
      point_at_[k] = keys[k].second;
    }
  }

  // The eigenvalues (ascending) of the normals' part of ICP's matrix over `points`.
  Eigen::Vector3d normalEigenvalues(const std::vector<int>& points) const {
    Eigen::Matrix3d normals = Eigen::Matrix3d::Zero();
    for (int i : points) normals += surface_[i].normal * surface_[i].normal.transpose();
    return Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(normals, Eigen::EigenvaluesOnly)
        .eigenvalues();
  }

  // The cell of a target: cells as wide as the field's diagonal, the farthest apart two
  // targets of an overlapping pair are taken to be.
  std::array<long, 3> cellOf(const Vec3& p) const {
    return {std::lround(std::floor(p.x() / diagonal_)), std::lround(std::floor(p.y() / diagonal_)),
            std::lround(std::floor(p.z() / diagonal_))};
  }

  std::vector<int> neighbours(const std::map<std::array<long, 3>, std::vector<int>>& cells,
                              int a) const {
    const auto c = cellOf(poses_[a].target);
    std::vector<int> near;
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy)
        for (long dz = -1; dz <= 1; ++dz)
          if (const auto found = cells.find({c[0] + dx, c[1] + dy, c[2] + dz});
              found != cells.end())
            for (int b : found->second)
              if (b > a && (poses_[b].target - poses_[a].target).norm() <= diagonal_)
                near.push_back(b);
    return near;
  }

  // The pair test without ICP. Before the condition number, two rejections that cannot
  // reject a passing pair: too few points in common; and the overlap's normals, whose
  // matrix is below each pose's (its smallest eigenvalue at most theirs) and whose largest
  // eigenvalue is at least a third of its trace, the number of points.
  bool joins(int a, int b) const {
    const std::size_t na = seen_[a].surface.size(), nb = seen_[b].surface.size();
    const double least = min_overlap_ * static_cast<double>(std::max(na, nb));
    if (static_cast<double>(std::min(na, nb)) < least) return false;
    const std::size_t first = std::max(range_[a].first, range_[b].first);
    const std::size_t last = std::min(range_[a].second, range_[b].second);
    std::size_t common = 0;
    const std::uint64_t *x = &bits_[a * words_], *y = &bits_[b * words_];
    for (std::size_t w = first; w < last; ++w) common += std::popcount(x[w] & y[w]);
    if (static_cast<double>(common) < least) return false;
    if (static_cast<double>(common) / 3 > max_condition_ * std::min(smallest_[a], smallest_[b]))
      return false;
    std::vector<int> both;
    for (std::size_t w = first; w < last; ++w)
      for (std::uint64_t m = x[w] & y[w]; m; m &= m - 1)
        both.push_back(point_at_[w * 64 + static_cast<std::size_t>(std::countr_zero(m))]);
    const Eigen::Vector3d e = normalEigenvalues(both);
    if (!(e(0) * max_condition_ >= e(2))) return false;
    std::vector<Vec3> p, n;
    for (int i : both) {
      p.push_back(surface_[i].position);
      n.push_back(surface_[i].normal);
    }
    return icpCondition(p, n) <= max_condition_;
  }

  int find(int v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }

  const std::vector<View>& poses_;
  const std::vector<PoseReach>& seen_;
  const std::vector<SurfacePoint>& surface_;
  const double max_condition_;
  const double min_overlap_ = RegistrationOptions{}.min_overlap;
  const double diagonal_;  // the field's
  std::size_t words_;
  std::vector<std::uint64_t> bits_;  // per pose, the surface points it measures
  std::vector<double> smallest_;     // per pose, the smallest eigenvalue of its normals' part
  std::vector<std::pair<std::size_t, std::size_t>> range_;  // per pose, the words with its bits
  std::vector<std::size_t> bit_of_;                         // per surface point
  std::vector<int> point_at_;                               // per bit
  std::vector<int> parent_;                                 // union-find
};

// The reference by the registration graph of the poses: a view registers only within the
// component of the reference view. The plan's measured samples that no pose of the largest
// component measures need views outside it, which register to nothing; CBC's bound on
// their fewest is returned.
double unjoinedViews(const Simulator& simulator, const Plan& plan, const std::vector<View>& poses,
                     const std::vector<PoseReach>& reach, const std::vector<SurfacePoint>& surface,
                     double max_condition) {
  const std::vector<int> roots =
      PoseGraph(simulator, poses, reach, surface, max_condition).components();
  std::map<int, std::size_t> sizes;
  int largest = -1;
  for (int root : roots)
    if (++sizes[root]; largest < 0 || sizes[root] > sizes[largest]) largest = root;
  return neededViews(plan, reach, [&](std::size_t v) { return roots[v] == largest; });
}

GeometryReference geometryReference(const Simulator& simulator, const Plan& plan,
                                    double max_condition) {
  const std::vector<SurfacePoint> samples = plan.samplePoints();
  const std::size_t step = std::max<std::size_t>(1, (samples.size() + 1199) / 1200);
  std::vector<View> poses = plan.views;  // the plan's own first, then the dense ones
  for (std::size_t a = 0; a < samples.size(); a += step)
    for (const View& v : ringPoses(simulator.scanner(), samples[a], {20, 40}, 90, 4))
      if (poseIsValid(simulator, v)) poses.push_back(v);
  // The registration's surface points, as Overlaps spaces them by default.
  const std::vector<SurfacePoint> surface =
      simulator.surfacePoints(simulator.scanner().fov_height / 40);
  const std::vector<PoseReach> reach = poseReach(simulator, poses, samples, surface);
  GeometryReference result;
  const auto start = std::chrono::steady_clock::now();
  result.graph = unjoinedViews(simulator, plan, poses, reach, surface, max_condition);
  result.graph_seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  result.poses = poses.size();
  for (std::size_t v = 0; v < plan.views.size(); ++v)
    if (plan.registration && plan.registration->views[v].method == RegistrationMethod::Icp)
      result.worst_registered = std::max(result.worst_registered, reach[v].condition);
  result.strict = unlockedViews(plan, reach, max_condition);
  result.loose = unlockedViews(plan, reach, std::max(max_condition, result.worst_registered));
  return result;
}

// The reference of coverage that searches more widely than the planner's candidates
// (coverableByWiderCandidates: every sample, poses aimed at it and moved off it): the
// samples it reaches, those only its moved poses reach, and how many of each the plan
// measures, sample by sample.
void countWiderReach(benchmark::State& state, const Simulator& simulator, const Plan& plan,
                     const std::vector<SurfacePoint>& points) {
  const std::vector<char> centred = coverableByDenseCandidates(simulator, points);
  const std::vector<char> wider = coverableByWiderCandidates(simulator, points);
  std::size_t reach = 0, measured = 0, moved_only = 0, moved_only_measured = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    const bool by_plan = !plan.samples[i].measured_by.empty();
    reach += wider[i];
    measured += wider[i] && by_plan;
    moved_only += wider[i] && !centred[i];
    moved_only_measured += wider[i] && !centred[i] && by_plan;
  }
  state.counters["wider_reachable"] = static_cast<double>(reach);
  state.counters["wider_measured"] = static_cast<double>(measured);
  state.counters["wider_moved_only"] = static_cast<double>(moved_only);
  state.counters["wider_moved_only_measured"] = static_cast<double>(moved_only_measured);
}

void planPart(benchmark::State& state, const std::string& relative, bool gdt) {
  const std::string path = std::string(SCANPLAN_SHARED_DATA) + "/" + relative;
  if (!std::filesystem::exists(path)) return state.SkipWithError("shared data not found");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  if (gdt) {
    spec.gdt_from_file = true;
    spec.tasks = {Task{TaskType::Gdt, {}, {}, {}}};
  }
  PlanningOptions options;
  options.registration = false;  // BM_Register measures it
  Plan plan;
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    plan = planViews(part, spec, options);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  SimulationOptions simulation;
  simulation.part_to_world = plan.part_to_world;
  const Simulator simulator(part, plan.scanner, simulation);
  const std::vector<SurfacePoint> points = plan.samplePoints();
  const DenseGreedy dense = denseGreedy(simulator, points, plan.measuredCount());
  state.counters["samples"] = static_cast<double>(plan.samples.size());
  state.counters["dense_reachable"] = static_cast<double>(dense.reachable);
  state.counters["measured"] = static_cast<double>(plan.measuredCount());
  state.counters["views"] = static_cast<double>(plan.views.size());
  state.counters["dense_greedy_views"] = static_cast<double>(dense.views);
  state.counters["dense_greedy_all_views"] = static_cast<double>(dense.all_views);
  state.counters["lower_bound"] = plan.bound->lower_bound;
  state.counters["views_over_bound"] =
      static_cast<double>(plan.views.size()) / std::max(plan.bound->lower_bound, 1.0);
  state.counters["plan_seconds"] = seconds;
  countWiderReach(state, simulator, plan, points);
}

// Registration, bridging and sequencing after the gdt and global tasks on a NIST model,
// without markers and with markers every 50 mm on the plate and on the part.
void registerPart(benchmark::State& state, const std::string& name, bool markers) {
  const std::string path = std::string(SCANPLAN_SHARED_DATA) + "/nist/" + name;
  if (!std::filesystem::exists(path)) return state.SkipWithError("shared data not found");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  spec.gdt_from_file = true;
  spec.tasks = {Task{TaskType::Gdt, {}, {}, {}}, Task{TaskType::Global, {}, {}, {}}};
  if (markers) {
    spec.marker_grid = 50;
    spec.markers_on_part = true;
  }
  Plan plan;
  for (auto _ : state) plan = planViews(part, spec);
  const Registration& r = *plan.registration;
  std::size_t verified = 0, passed = 0, unconstrained = 0;
  for (const PairCheck& pair : r.pairs)
    if (pair.icp) {
      ++verified;
      passed += pair.icp->passed;
    }
  for (const ViewRegistration& view : r.views)
    unconstrained += view.method == RegistrationMethod::None && !view.constrained;
  for (const StageTime& t : plan.times)
    if (t.stage == "registration") state.counters["registration_seconds"] = t.seconds;
  state.counters["views"] = static_cast<double>(plan.views.size());
  state.counters["registered"] = static_cast<double>(r.registered());
  state.counters["bridging"] = static_cast<double>(r.bridging_views);
  state.counters["unconstrained"] = static_cast<double>(unconstrained);
  state.counters["icp_verified"] = static_cast<double>(verified);
  state.counters["icp_passed"] = static_cast<double>(passed);
  state.counters["measured"] = static_cast<double>(plan.measuredCount());
  state.counters["measured_registered"] = static_cast<double>(plan.registeredMeasuredCount());
  state.counters["path_m"] = plan.sequence->length / 1000;
  state.counters["nn_path_m"] = plan.sequence->nearest_neighbour_length / 1000;
}

// The global task without markers, registered by geometry: views, the share registered,
// bridging views, the markers proposed (and their bound), seconds with and without
// registration; then the plan made again with the proposed markers.
void registerGlobal(benchmark::State& state, const std::string& relative) {
  const std::string path = std::string(SCANPLAN_SHARED_DATA) + "/" + relative;
  if (!std::filesystem::exists(path)) return state.SkipWithError("shared data not found");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  Plan plan;
  double seconds = 0;
  for (auto _ : state) {
    const auto start = std::chrono::steady_clock::now();
    plan = planViews(part, spec);
    seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  }
  const Registration& r = *plan.registration;
  for (const StageTime& t : plan.times)
    if (t.stage == "registration") state.counters["registration_seconds"] = t.seconds;
  state.counters["plan_seconds"] = seconds;
  state.counters["views"] = static_cast<double>(plan.views.size());
  state.counters["registered"] = static_cast<double>(r.registered());
  state.counters["bridging"] = static_cast<double>(r.bridging_views);
  std::size_t loose = 0;  // registered by ICP though not constrained
  for (const ViewRegistration& view : r.views)
    loose += view.method == RegistrationMethod::Icp && !view.constrained;
  state.counters["registered_unconstrained"] = static_cast<double>(loose);
  {
    PlanningOptions coverage_only;
    coverage_only.registration = false;
    const auto start = std::chrono::steady_clock::now();
    const Plan plain = planViews(part, spec, coverage_only);
    state.counters["seconds_without_registration"] =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    state.counters["views_without_registration"] = static_cast<double>(plain.views.size());
  }
  const Simulator simulator(
      part, plan.scanner, simulationOptionsFor(resolveSpec(part, spec), part, plan.part_to_world));
  const GeometryReference reference =
      geometryReference(simulator, plan, spec.registration.max_condition);
  state.counters["reference_poses"] = static_cast<double>(reference.poses);
  state.counters["worst_registered_condition"] = reference.worst_registered;
  state.counters["unregistrable_bound"] = reference.strict;
  state.counters["unregistrable_bound_loose"] = reference.loose;
  state.counters["unregistrable_bound_graph"] = reference.graph;
  state.counters["graph_seconds"] = reference.graph_seconds;
  if (!plan.proposed_markers || plan.proposed_markers->markers.empty()) return;
  state.counters["proposed_markers"] = static_cast<double>(plan.proposed_markers->markers.size());
  state.counters["proposed_bound"] = static_cast<double>(plan.proposed_markers->lower_bound);
  const std::string csv = std::filesystem::temp_directory_path() / "scanplan-bench-markers.csv";
  writeMarkers(plan.proposed_markers->markers, csv);
  spec.markers_file = csv;
  spec.marker_grid = 0;
  const Plan marked = planViews(part, spec);
  state.counters["views_with_markers"] = static_cast<double>(marked.views.size());
  state.counters["registered_with_markers"] =
      static_cast<double>(marked.registration->registered());
}

// The global task on a marker plate (markers every 40 mm around the part) registered by
// reference points, against the dense reference of what those markers can frame
// (framedByDenseCandidates): the plan's measured samples that no pose seeing three plate
// markers measures, and the plan's views that measure one of them. A view of any plan that
// measures such a sample cannot register by the plate, so the unframeable samples no view
// can hold two of (farther apart than the measuring volume's diameter, or with normals
// more than twice the camera's glancing angle apart: a greedy packing of them) bound the
// views that cannot from below.
void frameOnPlate(benchmark::State& state, const std::string& relative) {
  const std::string path = std::string(SCANPLAN_SHARED_DATA) + "/" + relative;
  if (!std::filesystem::exists(path)) return state.SkipWithError("shared data not found");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  spec.marker_grid = 40;
  spec.registration.method = RegistrationMode::ReferencePoints;
  Plan plan;
  for (auto _ : state) plan = planViews(part, spec);
  const Simulator simulator(
      part, plan.scanner, simulationOptionsFor(resolveSpec(part, spec), part, plan.part_to_world));
  const std::vector<SurfacePoint> points = plan.samplePoints();
  std::vector<SurfacePoint> measured;
  std::vector<std::size_t> index(plan.samples.size(), SIZE_MAX);
  for (std::size_t i = 0; i < plan.samples.size(); ++i)
    if (!plan.samples[i].measured_by.empty()) {
      index[i] = measured.size();
      measured.push_back(points[i]);
    }
  const std::vector<char> framed =
      framedByDenseCandidates(simulator, measured, plan.markers, registrationOptions(spec));
  std::set<int> bound_to_fail;  // views measuring a sample no framed pose measures
  for (std::size_t i = 0; i < plan.samples.size(); ++i)
    if (index[i] != SIZE_MAX && !framed[index[i]])
      bound_to_fail.insert(plan.samples[i].measured_by.begin(), plan.samples[i].measured_by.end());
  const Scanner& scanner = plan.scanner;
  const double far = (scanner.standoff + scanner.depth_of_field / 2) / scanner.standoff;
  const double diameter =
      std::hypot(scanner.fov_width * far, scanner.fov_height * far, scanner.depth_of_field);
  const double apart = std::cos(2 * scanner.max_camera_angle * M_PI / 180);
  std::vector<SurfacePoint> packed;  // unframeable samples no view holds two of
  for (std::size_t k = 0; k < measured.size(); ++k)
    if (!framed[k] && std::all_of(packed.begin(), packed.end(), [&](const SurfacePoint& p) {
          return (p.position - measured[k].position).norm() > diameter ||
                 p.normal.dot(measured[k].normal) < apart;
        }))
      packed.push_back(measured[k]);
  const auto frameable = static_cast<double>(std::count(framed.begin(), framed.end(), 1));
  state.counters["views"] = static_cast<double>(plan.views.size());
  state.counters["registered"] = static_cast<double>(plan.registration->registered());
  state.counters["framed"] = static_cast<double>(std::count_if(
      plan.registration->views.begin(), plan.registration->views.end(),
      [](const ViewRegistration& v) { return v.method == RegistrationMethod::ReferencePoints; }));
  state.counters["measured"] = static_cast<double>(measured.size());
  state.counters["frameable_share"] =
      frameable / std::max(static_cast<double>(measured.size()), 1.0);
  state.counters["views_unframeable"] = static_cast<double>(bound_to_fail.size());
  state.counters["unframeable_views_bound"] = static_cast<double>(packed.size());
}

// verifyPlan of a plan of about 2,000 views: CTC 02's global task with a laser-line
// scanner whose field is cut to 60 x 38 mm, planned without registration, then verified
// with registration by geometry (the plan claims no view registered): its coverage, every
// pair of views whose measured surfaces overlap, ICP where they could register, and the
// sequence.
void verifyManyViews(benchmark::State& state) {
  const std::string path =
      std::string(SCANPLAN_SHARED_DATA) + "/nist/nist_ctc_02_asme1_ap242-e2.stp";
  if (!std::filesystem::exists(path)) return state.SkipWithError("shared data not found");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  spec.scanner = scannerPreset("laser-line");
  spec.scanner.fov_width = 60;
  spec.scanner.fov_height = 38;
  PlanningOptions coverage_only;
  coverage_only.registration = false;
  Plan plan = planViews(part, spec, coverage_only);
  plan.registration.emplace();
  plan.registration->method = RegistrationMode::Geometry;
  plan.registration->required = false;
  plan.registration->views.resize(plan.views.size());
  PlanCheck check;
  for (auto _ : state) check = verifyPlan(plan, part, spec);
  const Registration& r = *check.plan.registration;
  std::size_t verified = 0;
  for (const PairCheck& pair : r.pairs) verified += pair.icp.has_value();
  state.counters["views"] = static_cast<double>(plan.views.size());
  state.counters["overlapping_pairs"] = static_cast<double>(r.pairs.size());
  state.counters["icp_verified"] = static_cast<double>(verified);
  state.counters["registered"] = static_cast<double>(r.registered());
}

const int registered = [] {
  for (const char* name : {"nist_ctc_01_asme1_ap242-e1.stp", "nist_ctc_03_asme1_ap242-e2.stp",
                           "nist_ftc_06_asme1_ap242-e1.stp"})
    for (const bool markers : {false, true})
      benchmark::RegisterBenchmark(
          (std::string("BM_Register/") + name + (markers ? "/markers" : "/no_markers")).c_str(),
          [name, markers](benchmark::State& state) { registerPart(state, name, markers); })
          ->Unit(benchmark::kSecond)
          ->Iterations(1);
  for (const char* name : {"nist_ctc_01_asme1_ap242-e1.stp", "nist_ctc_02_asme1_ap242-e2.stp",
                           "nist_ctc_03_asme1_ap242-e2.stp", "nist_ctc_04_asme1_ap242-e1.stp",
                           "nist_ftc_06_asme1_ap242-e1.stp", "nist_ftc_07_asme1_ap242-e2.stp",
                           "nist_ftc_08_asme1_ap242-e1.stp", "nist_ftc_11_asme1_ap242-e1.stp"})
    for (const bool gdt : {true, false})
      benchmark::RegisterBenchmark(
          (std::string(gdt ? "BM_PlanGdt/" : "BM_PlanGlobal/") + name).c_str(),
          [name, gdt](benchmark::State& state) {
            planPart(state, std::string("nist/") + name, gdt);
          })
          ->Unit(benchmark::kSecond)
          ->Iterations(1);
  // Every NIST model and the die-cast part, by their paths in the shared data.
  constexpr std::array kParts = {"nist/nist_ctc_01_asme1_ap242-e1.stp",
                                 "nist/nist_ctc_02_asme1_ap242-e2.stp",
                                 "nist/nist_ctc_03_asme1_ap242-e2.stp",
                                 "nist/nist_ctc_04_asme1_ap242-e1.stp",
                                 "nist/nist_ftc_06_asme1_ap242-e1.stp",
                                 "nist/nist_ftc_07_asme1_ap242-e2.stp",
                                 "nist/nist_ftc_08_asme1_ap242-e1.stp",
                                 "nist/nist_ftc_11_asme1_ap242-e1.stp",
                                 "mech/asi_repatch-hpdc.stp"};
  for (const char* name : kParts) {
    benchmark::RegisterBenchmark((std::string("BM_RegisterGlobal/") + name).c_str(),
                                 [name](benchmark::State& state) { registerGlobal(state, name); })
        ->Unit(benchmark::kSecond)
        ->Iterations(1);
    benchmark::RegisterBenchmark((std::string("BM_FrameOnPlate/") + name).c_str(),
                                 [name](benchmark::State& state) { frameOnPlate(state, name); })
        ->Unit(benchmark::kSecond)
        ->Iterations(1);
  }
  benchmark::RegisterBenchmark("BM_VerifyManyViews", verifyManyViews)
      ->Unit(benchmark::kSecond)
      ->Iterations(1)
      ->UseRealTime();
  benchmark::RegisterBenchmark(
      "BM_PlanGlobal/asi_repatch-hpdc.stp",
      [](benchmark::State& state) { planPart(state, "mech/asi_repatch-hpdc.stp", false); })
      ->Unit(benchmark::kSecond)
      ->Iterations(1);
  return 0;
}();

}  // namespace
