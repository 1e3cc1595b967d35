// The registration graph: pair checks and a spanning forest of verified pairs.

#include "registration/graph.h"

#include "core/kd_tree.h"
#include "registration/icp.h"
#include "registration/rigid_fit.h"

#include <scanplan/core/errors.h>
#include <scanplan/registration/registration.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>
#include <memory>
#include <numeric>
#include <queue>

namespace scanplan {

std::string_view toString(RegistrationMethod method) {
  switch (method) {
    case RegistrationMethod::Reference: return "reference";
    case RegistrationMethod::Markers: return "markers";
    case RegistrationMethod::Icp: return "icp";
    case RegistrationMethod::Robot: return "robot";
    case RegistrationMethod::ReferencePoints: return "reference_points";
    case RegistrationMethod::None: return "none";
  }
  return "unknown";
}

std::string_view toString(RegistrationMode mode) {
  switch (mode) {
    case RegistrationMode::Default: return "default";
    case RegistrationMode::Markers: return "markers";
    case RegistrationMode::Geometry: return "geometry";
    case RegistrationMode::Robot: return "robot";
    case RegistrationMode::ReferencePoints: return "reference_points";
  }
  return "unknown";
}

void validate(const RegistrationOptions& o, const std::string& source) {
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) throw InputError(source, "registration: " + what);
  };
  require(o.min_markers >= 3, "min_markers must be at least 3");
  require(o.marker_spread > 0, "marker_spread must be positive");
  require(o.marker_sigma >= 0 && o.marker_sigma < 10, "marker_sigma must be in [0, 10) mm");
  require(o.min_overlap > 0 && o.min_overlap <= 1, "min_overlap must be in (0, 1]");
  require(o.max_condition >= 1, "max_condition must be at least 1");
  require(o.point_spacing >= 0 && o.cloud_spacing >= 0, "spacings must not be negative");
  require(o.perturbation >= 0 && o.perturbation_angle >= 0 && o.perturbation_angle < 45,
          "perturbation must be >= 0 mm and in [0, 45) degrees");
  require(o.tolerance > 0, "tolerance must be positive");
  require(o.max_bridging_views >= 0, "max_bridging_views must not be negative");
  require(o.robot_accuracy >= 0 && std::isfinite(o.robot_accuracy),
          "robot_accuracy must not be negative");
  require(o.method != RegistrationMode::Robot || o.robot_accuracy > 0,
          "method robot needs robot_accuracy (mm), the robot's pose accuracy");
}

bool robotRegistersAll(const RegistrationOptions& options) {
  return options.method == RegistrationMode::Robot && options.robot_accuracy <= options.tolerance;
}

std::size_t Registration::registered() const {
  return static_cast<std::size_t>(std::count_if(
      views.begin(), views.end(), [](auto& v) { return v.method != RegistrationMethod::None; }));
}

double markerSigma(const RegistrationOptions& options, const Scanner& scanner) {
  return options.marker_sigma > 0 ? options.marker_sigma : scanner.point_spacing / 20;
}

bool Registration::links(const PairCheck& pair) const {
  return pair.markers || (pair.icp ? pair.icp->passed : pair.stable && !verified);
}

const PairCheck* Registration::pair(int a, int b) const {
  if (a > b) std::swap(a, b);
  for (const PairCheck& p : pairs)
    if (p.a == a && p.b == b) return &p;
  return nullptr;
}

bool Registration::linked(int a, int b) const {
  const PairCheck* p = pair(a, b);
  return p && links(*p);
}

namespace detail {

// ICP clouds and checks by view (id and pose), shared by the copies of a graph: no view's
// cloud is simulated twice, and no pair (a bridging candidate tried again) registered twice.
struct IcpMemo {
  using Key = std::pair<int, std::array<double, 12>>;
  std::map<Key, std::shared_ptr<const detail::IndexedCloud>> clouds;
  std::map<std::pair<Key, Key>, IcpCheck> checks;

  static Key key(const View& view) {
    Key key{view.id, {}};
    const Eigen::Matrix<double, 3, 4> m = view.camera_to_world.matrix().topRows<3>();
    std::copy(m.data(), m.data() + 12, key.second.begin());
    return key;
  }
};

namespace {

// Every view registered to nothing registered by the robot, into the reference's frame.
void registerByRobot(Registration& registration) {
  for (ViewRegistration& view : registration.views)
    if (view.method == RegistrationMethod::None) {
      view.method = RegistrationMethod::Robot;
      view.to = registration.reference;
    }
}

}  // namespace

RegistrationGraph::RegistrationGraph(const Simulator& simulator, const RegistrationOptions& options,
                                     const std::vector<Marker>& markers, const Progress& progress)
    : simulator_(simulator),
      options_(options),
      progress_(progress),
      overlaps_(std::make_shared<const detail::Overlaps>(simulator, options, markers)),
      points_(overlaps_->points()),
      spacing_(overlaps_->spacing()),
      memo_(std::make_shared<IcpMemo>()) {}

std::vector<Observation> RegistrationGraph::observe(std::span<const View> views) const {
  return overlaps_->observe(views);
}

PairCheck RegistrationGraph::check(const View& a, const Observation& oa, const View& b,
                                   const Observation& ob) const {
  return overlaps_->check(a, oa, b, ob);
}

void RegistrationGraph::add(std::span<const View> views) {
  const std::vector<Observation> seen = observe(views);
  std::vector<std::size_t> fresh;
  for (std::size_t k = 0; k < views.size(); ++k) {
    const auto pairs = insert(views[k], seen[k]);
    fresh.insert(fresh.end(), pairs.begin(), pairs.end());
  }
  // Without markers, nearly every view of a stable pair is verified by ICP: their clouds
  // are made at once, which keeps both cores busy.
  if (options_.verify && overlaps_->markers() == 0) {
    std::vector<std::size_t> stable;
    for (std::size_t p : fresh)
      if (pairs_[p].stable) stable.push_back(p);
    makeClouds(stable);
  }
  connect(fresh, true);
}

RegistrationGraph::Sides RegistrationGraph::sidesOf(int towards) {
  const int main = mainComponent();
  Sides sides;
  sides.in_main.resize(views_.size());
  sides.in_other.resize(views_.size());
  std::vector<char> on_main(points_.size()), on_other(points_.size());  // per surface point
  for (std::size_t v = 0; v < views_.size(); ++v) {
    sides.in_main[v] = find(static_cast<int>(v)) == main;
    sides.in_other[v] = find(static_cast<int>(v)) == towards;
    for (int i : seen_[v].points) {
      on_main[i] |= sides.in_main[v];
      on_other[i] |= sides.in_other[v];
    }
  }
  for (std::size_t i = 0; i < points_.size(); ++i) {
    if (on_main[i]) sides.main_points.push_back(points_[i].position);
    if (on_other[i]) sides.other_points.push_back(points_[i].position);
  }
  if (sides.main_points.empty() || sides.other_points.empty()) return sides;
  if (to_main_.first != sides.in_main) to_main_ = {sides.in_main, distances(sides.main_points)};
  sides.to_main = to_main_.second;
  sides.to_other = distances(sides.other_points);
  sides.gap = std::numeric_limits<double>::infinity();
  for (std::size_t v = 0; v < views_.size(); ++v)
    if (sides.in_main[v])
      for (int i : seen_[v].points) sides.gap = std::min(sides.gap, sides.to_other[i]);
  return sides;
}

bool RegistrationGraph::addJoined(const View& view, const Observation& seen, std::size_t partner) {
  const std::size_t index = views_.size();
  const std::vector<std::size_t> fresh = insert(view, seen);
  const auto pair = std::find_if(fresh.begin(), fresh.end(),
                                 [&](std::size_t p) { return ends_[p].first == partner; });
  if (pair != fresh.end() && verify(*pair)) {
    connect(fresh);
    return true;
  }
  // Not registrable after all: take it back out.
  views_.resize(index);
  seen_.resize(index);
  sets_.truncate(index);
  constrained_.resize(index);
  framed_.resize(index);
  if (frame_ == static_cast<int>(index)) frame_ = -1;
  pairs_.resize(pairs_.size() - fresh.size());
  ends_.resize(pairs_.size());
  return false;
}

bool RegistrationGraph::verify(std::size_t p) {
  PairCheck& pair = pairs_[p];
  if (pair.markers) return true;
  if (!pair.stable) return false;
  if (!options_.verify) return true;
  if (!pair.icp) registerPairs({p});
  return pair.icp->passed;
}

int RegistrationGraph::find(int v) { return sets_.find(v); }

std::size_t RegistrationGraph::components() {
  std::size_t count = 0;
  for (std::size_t v = 0; v < views_.size(); ++v)
    count += find(static_cast<int>(v)) == static_cast<int>(v);
  return count;
}

int RegistrationGraph::mainComponent() {
  if (frame_ >= 0) return find(frame_);
  std::map<int, std::size_t> sizes;
  for (std::size_t v = 0; v < views_.size(); ++v) ++sizes[find(static_cast<int>(v))];
  int best = -1;
  for (std::size_t v = 0; v < views_.size(); ++v) {
    const int root = find(static_cast<int>(v));
    if (best < 0 || sizes[root] > sizes[best]) best = root;
  }
  return best;
}

std::vector<int> RegistrationGraph::bridgeable() {
  const int main = mainComponent();
  std::vector<int> roots;
  for (std::size_t v = 0; v < views_.size(); ++v) {
    const int root = find(static_cast<int>(v));
    if (root != main && constrained_[v] &&
        std::find(roots.begin(), roots.end(), root) == roots.end())
      roots.push_back(root);
  }
  std::sort(roots.begin(), roots.end());
  return roots;
}

Registration RegistrationGraph::result(std::size_t first_bridge) {
  Registration registration;
  registration.pairs = pairs_;
  registration.verified = options_.verify;
  registration.components = components();
  registration.views.resize(views_.size());
  for (std::size_t v = first_bridge; v < views_.size(); ++v) registration.views[v].bridge = true;
  for (std::size_t v = 0; v < views_.size(); ++v) {
    registration.views[v].constrained = constrained_[v];
    registration.views[v].markers = seen_[v].markers;
  }
  registration.bridging_views = views_.size() - first_bridge;
  if (views_.empty()) return registration;
  // The reference: in the main component (the frame's, when views see the reference
  // points), the view that sees the most markers, else the first.
  const int main = mainComponent();
  int reference = -1;
  for (std::size_t v = 0; v < views_.size(); ++v) {
    if (find(static_cast<int>(v)) != main) continue;
    if (reference < 0 || seen_[v].markers.size() > seen_[reference].markers.size())
      reference = static_cast<int>(v);
  }
  registration.reference = views_[reference].id;
  // Views seeing the reference points register into their frame, the reference too; else
  // the reference fixes the frame.
  std::vector<std::size_t> roots;
  for (std::size_t v = 0; v < views_.size(); ++v)
    if (framed_[v]) {
      registration.views[v].method = RegistrationMethod::ReferencePoints;
      roots.push_back(v);
    }
  if (roots.empty()) {
    registration.views[reference].method = RegistrationMethod::Reference;
    roots.push_back(static_cast<std::size_t>(reference));
  }
  for (const auto& [v, p] : leastErrorLinks(registration, roots)) {
    const auto [i, j] = ends_[p];
    registration.views[v].method =
        pairs_[p].markers ? RegistrationMethod::Markers : RegistrationMethod::Icp;
    registration.views[v].to = views_[i == v ? j : i].id;
  }
  return registration;
}

bool RegistrationGraph::surer(std::size_t a, std::size_t b) const {
  const PairCheck &x = pairs_[a], &y = pairs_[b];
  if (x.markers != y.markers) return x.markers;
  if (x.markers) return x.shared_markers > y.shared_markers;
  return x.condition < y.condition;
}

double RegistrationGraph::linkVariance(std::size_t p) const {
  const PairCheck& pair = pairs_[p];
  if (!pair.markers) {
    const double error = pair.icp ? pair.icp->error : options_.tolerance;
    return error * error;
  }
  const auto& [i, j] = ends_[p];
  std::vector<Vec3> at = overlaps_->markerPositions(shared(seen_[i].markers, seen_[j].markers));
  // About the markers' centroid, where the fit's shift and turn are apart.
  Vec3 centre = Vec3::Zero();
  for (const Vec3& q : at) centre += q / static_cast<double>(at.size());
  for (Vec3& q : at) q -= centre;
  const Scanner& s = simulator_.scanner();
  const TwistCovariance fit = rigidFitCovariance(at, std::sqrt(2.0) * markerSigma(options_, s));
  const double lever = std::hypot(s.fov_width, s.fov_height) / 2;
  return fit.bottomRightCorner<3, 3>().trace() + lever * lever * fit.topLeftCorner<3, 3>().trace();
}

std::map<std::size_t, std::size_t> RegistrationGraph::leastErrorLinks(
    const Registration& registration, const std::vector<std::size_t>& roots) const {
  std::vector<std::vector<std::size_t>> incident(views_.size());  // pairs that link
  std::vector<double> cost(pairs_.size(), 0);
  for (std::size_t p = 0; p < pairs_.size(); ++p)
    if (registration.links(pairs_[p])) {
      incident[ends_[p].first].push_back(p);
      incident[ends_[p].second].push_back(p);
      cost[p] = linkVariance(p);
    }
  std::vector<double> total(views_.size(), std::numeric_limits<double>::infinity());
  using Entry = std::pair<double, std::size_t>;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
  for (std::size_t v : roots) {
    total[v] = 0;
    queue.push({0, v});
  }
  std::map<std::size_t, std::size_t> link;  // view -> the pair it registers by
  while (!queue.empty()) {
    const auto [d, v] = queue.top();
    queue.pop();
    if (d > total[v]) continue;
    for (std::size_t p : incident[v]) {
      const std::size_t other = ends_[p].first == v ? ends_[p].second : ends_[p].first;
      if (d + cost[p] < total[other]) {
        total[other] = d + cost[p];
        link[other] = p;
        queue.push({total[other], other});
      }
    }
  }
  return link;
}

std::vector<std::size_t> RegistrationGraph::insert(const View& view, const Observation& seen) {
  const std::size_t index = views_.size();
  views_.push_back(view);
  seen_.push_back(seen);
  sets_.add();
  constrained_.push_back(overlaps_->constrained(seen));
  // Views seeing the reference points are one component: each registers into their frame.
  framed_.push_back(overlaps_->framed(seen.markers));
  if (framed_.back()) {
    if (frame_ < 0) frame_ = static_cast<int>(index);
    sets_.join(static_cast<int>(index), frame_);
  }
  std::vector<PairCheck> checks(index);
  tbb::parallel_for(std::size_t{0}, index, [&](std::size_t j) {
    checks[j] = check(views_[j], seen_[j], views_[index], seen_[index]);
  });
  std::vector<std::size_t> fresh;
  for (std::size_t j = 0; j < index; ++j) {
    PairCheck& pair = checks[j];
    if (pair.shared_markers == 0 && pair.overlap_area == 0) continue;
    pairs_.push_back(pair);
    ends_.push_back({j, index});
    fresh.push_back(pairs_.size() - 1);
  }
  return fresh;
}

std::vector<double> RegistrationGraph::distances(const std::vector<Vec3>& to) const {
  const detail::PointCloudAdaptor cloud{to};
  detail::PointTree tree(3, cloud, nanoflann::KDTreeSingleIndexAdaptorParams(16));
  tree.buildIndex();
  std::vector<double> result(points_.size());
  tbb::parallel_for(std::size_t{0}, points_.size(), [&](std::size_t i) {
    unsigned nearest = 0;
    double squared = 0;
    tree.knnSearch(points_[i].position.data(), 1, &nearest, &squared);
    result[i] = std::sqrt(squared);
  });
  return result;
}

void RegistrationGraph::connect(std::vector<std::size_t> candidates, bool shown) {
  std::stable_sort(candidates.begin(), candidates.end(),
                   [&](std::size_t x, std::size_t y) { return surer(x, y); });
  const auto registrable = static_cast<std::size_t>(std::count_if(
      candidates.begin(), candidates.end(), [&](std::size_t p) { return pairs_[p].passes(); }));
  std::size_t verified_up_to = 0;  // candidates before this index were ICP-verified ahead
  std::size_t walked = 0;          // registrable candidates passed
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    const std::size_t p = candidates[k];
    const PairCheck& pair = pairs_[p];
    if (!pair.passes()) continue;
    ++walked;
    const int a = find(static_cast<int>(ends_[p].first));
    const int b = find(static_cast<int>(ends_[p].second));
    if (a == b) continue;
    if (k >= verified_up_to) {
      if (shown)
        report(progress_, "registration: pairs by ICP",
               static_cast<double>(walked) / static_cast<double>(registrable));
      verified_up_to = verifyAhead(candidates, k);
    }
    if (!verify(p)) continue;
    sets_.join(std::max(a, b), std::min(a, b));
  }
}

std::size_t RegistrationGraph::verifyAhead(const std::vector<std::size_t>& candidates,
                                           std::size_t first) {
  if (!options_.verify) return candidates.size();
  const std::size_t batch_size =
      6 * static_cast<std::size_t>(tbb::this_task_arena::max_concurrency());
  std::vector<std::size_t> batch;
  std::size_t k = first;
  for (; k < candidates.size() && batch.size() < batch_size; ++k) {
    const std::size_t p = candidates[k];
    const PairCheck& pair = pairs_[p];
    if (pair.markers || !pair.stable || pair.icp) continue;
    if (find(static_cast<int>(ends_[p].first)) == find(static_cast<int>(ends_[p].second))) continue;
    batch.push_back(p);
  }
  registerPairs(batch);
  return k;
}

void RegistrationGraph::makeClouds(const std::vector<std::size_t>& pairs) {
  std::vector<std::size_t> views;
  for (std::size_t p : pairs)
    for (std::size_t v : {ends_[p].first, ends_[p].second})
      if (!memo_->clouds.count(IcpMemo::key(views_[v])) &&
          std::find(views.begin(), views.end(), v) == views.end())
        views.push_back(v);
  std::vector<std::shared_ptr<const detail::IndexedCloud>> clouds(views.size());
  tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t k) {
    clouds[k] = std::make_shared<const detail::IndexedCloud>(
        icpCloud(simulator_, views_[views[k]], options_));
  });
  for (std::size_t k = 0; k < views.size(); ++k)
    memo_->clouds[IcpMemo::key(views_[views[k]])] = clouds[k];
}

void RegistrationGraph::registerPairs(const std::vector<std::size_t>& pairs) {
  auto key = [&](std::size_t p) {
    return std::pair{IcpMemo::key(views_[ends_[p].first]), IcpMemo::key(views_[ends_[p].second])};
  };
  std::vector<std::size_t> fresh;
  for (std::size_t p : pairs)
    if (const auto found = memo_->checks.find(key(p)); found != memo_->checks.end())
      pairs_[p].icp = found->second;
    else
      fresh.push_back(p);
  makeClouds(fresh);
  tbb::parallel_for(std::size_t{0}, fresh.size(), [&](std::size_t k) {
    const auto [fixed, moved] = key(fresh[k]);
    pairs_[fresh[k]].icp = detail::checkIcp(simulator_, *memo_->clouds.at(fixed),
                                            memo_->clouds.at(moved)->cloud, options_);
  });
  for (std::size_t p : fresh) memo_->checks[key(p)] = *pairs_[p].icp;
}

RegistrationMode registrationMethod(const RegistrationOptions& options,
                                    const std::vector<Marker>& markers) {
  return options.method != RegistrationMode::Default ? options.method
         : markers.empty()                           ? RegistrationMode::Geometry
                                                     : RegistrationMode::Markers;
}

RegistrationGraph graphOf(const Simulator& simulator, std::span<const View> views,
                          const std::vector<Marker>& markers, const RegistrationOptions& options,
                          const Progress& progress) {
  validate(options, "registration");
  static const std::vector<Marker> no_markers;
  const bool geometry = registrationMethod(options, markers) == RegistrationMode::Geometry;
  RegistrationGraph graph(simulator, options, geometry ? no_markers : markers, progress);
  report(progress, "registration: overlaps of " + std::to_string(views.size()) + " views", 0);
  graph.add(views);
  return graph;
}

Registration finishRegistration(RegistrationGraph& graph, std::size_t first_bridge,
                                RegistrationMode method, const std::vector<Marker>& markers,
                                const RegistrationOptions& options) {
  Registration registration = graph.result(first_bridge);
  registration.markers = markers.size();
  registration.method = method;
  registration.required = options.required;
  registration.aligned_as_taken = options.aligned_as_taken;
  if (method == RegistrationMode::Robot) registration.robot_accuracy = options.robot_accuracy;
  if (robotRegistersAll(options)) registerByRobot(registration);
  return registration;
}

}  // namespace detail

Registration registerViews(const Simulator& simulator, std::span<const View> views,
                           const std::vector<Marker>& markers, const RegistrationOptions& options,
                           const Progress& progress) {
  detail::RegistrationGraph graph = detail::graphOf(simulator, views, markers, options, progress);
  return detail::finishRegistration(graph, views.size(),
                                    detail::registrationMethod(options, markers), markers, options);
}

void appendRegistration(Registration& into, Registration from, int id_offset) {
  auto shift = [&](int& id) {
    if (id > 0) id += id_offset;
  };
  const bool first = into.views.empty();
  for (ViewRegistration& r : from.views) {
    shift(r.to);
    into.views.push_back(r);
  }
  for (PairCheck& pair : from.pairs) {
    shift(pair.a);
    shift(pair.b);
    into.pairs.push_back(pair);
  }
  into.markers += from.markers;
  into.components += from.components;
  into.bridging_views += from.bridging_views;
  into.verified = first ? from.verified : into.verified && from.verified;
  if (first) {
    into.method = from.method;
    into.required = from.required;
    into.aligned_as_taken = from.aligned_as_taken;
    into.robot_accuracy = from.robot_accuracy;
  }
  shift(from.reference);
  if (into.reference == 0) into.reference = from.reference;
}

}  // namespace scanplan
