// Bridging views (docs/registration.md): where the registration graph falls apart, views
// added one at a time towards a component apart from the main one, each registering to the
// main component and joining or coming nearer to the other, in chains of a few views.

#include "registration/graph.h"

#include <scanplan/planning/bridging.h>
#include <scanplan/planning/poses.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <limits>
#include <map>
#include <optional>

namespace scanplan {
namespace {

using detail::Observation;
using detail::RegistrationGraph;
using Sides = RegistrationGraph::Sides;

// The poses a bridge is chosen from (planning/poses.h): around targets near the main
// component, and between its views and nearby views of the other side.
std::vector<View> bridgingPoses(const RegistrationGraph& graph, const Sides& sides) {
  // Targets within reach of the main component, nearest to the others first, spread out.
  const Scanner& scanner = graph.simulator().scanner();
  std::vector<int> order;
  for (std::size_t i = 0; i < graph.points().size(); ++i)
    if (sides.to_main[i] <= scanner.fov_height / 2) order.push_back(static_cast<int>(i));
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return sides.to_other[a] < sides.to_other[b]; });
  std::vector<View> poses;
  std::vector<Vec3> targets;
  // The orientations of the main component's views, which see stably, are tried at
  // every target besides the poses around its normal: those of the kOrientations views
  // nearest to the other side.
  constexpr std::size_t kOrientations = 8;
  std::vector<std::pair<double, std::size_t>> nearest_main;  // (distance to the other side, view)
  for (std::size_t v = 0; v < graph.views().size(); ++v)
    if (sides.in_main[v]) {
      double d = std::numeric_limits<double>::infinity();
      for (int i : graph.observations()[v].points) d = std::min(d, sides.to_other[i]);
      nearest_main.push_back({d, v});
    }
  std::stable_sort(nearest_main.begin(), nearest_main.end());
  std::vector<Eigen::Matrix3d> orientations;
  for (const auto& [d, v] : nearest_main) {
    if (orientations.size() == kOrientations) break;
    const Eigen::Matrix3d r = graph.views()[v].camera_to_world.linear();
    const bool known = std::any_of(orientations.begin(), orientations.end(), [&](auto& o) {
      return Eigen::AngleAxisd(o.transpose() * r).angle() < radians(10);
    });
    if (!known) orientations.push_back(r);
  }
  for (int i : order) {
    if (targets.size() == 32) break;
    const Vec3& p = graph.points()[i].position;
    if (std::any_of(targets.begin(), targets.end(),
                    [&](const Vec3& t) { return (t - p).norm() < scanner.fov_height / 4; }))
      continue;
    targets.push_back(p);
    std::vector<View> around = posesAround(scanner, graph.points()[i]);
    for (const Eigen::Matrix3d& r : orientations) around.push_back(orientedPose(scanner, p, r));
    poses.insert(poses.end(), around.begin(), around.end());
  }
  // Poses between a view of the main component and a nearby view of another: target and
  // orientation interpolated, and each one's orientation aimed at the other's target.
  std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>> near;
  for (std::size_t m = 0; m < graph.views().size(); ++m)
    for (std::size_t o = 0; o < graph.views().size(); ++o)
      if (sides.in_main[m] && sides.in_other[o]) {
        const double d = (graph.views()[m].target - graph.views()[o].target).norm();
        if (d < 2 * scanner.fov_width) near.push_back({d, {m, o}});
      }
  std::sort(near.begin(), near.end());
  near.resize(std::min<std::size_t>(near.size(), 24));
  for (const auto& [d, pair] : near) {
    const View &a = graph.views()[pair.first], &b = graph.views()[pair.second];
    for (const auto& [t, turn] :
         {std::pair{1.0 / 3, 1.0 / 3}, {0.5, 0.5}, {2.0 / 3, 2.0 / 3}, {1.0, 0.0}, {0.0, 1.0}})
      poses.push_back(poseBetween(a, b, t, turn, scanner.standoff));
  }
  return poses;
}

// The observations of bridging poses, kept across the tries: after a view that only comes
// nearer, the next try looks at nearly the same poses, and components side by side are
// bridged from the same targets. The oldest are forgotten past kKeptPoints points in all.
// Kept only without a turning table, whose angle, besides the pose, decides what a view
// sees.
class Observed {
 public:
  explicit Observed(bool keep) : keep_(keep) {}

  // What `poses` observe: those met before as they were, the others observed now.
  std::vector<Observation> of(const RegistrationGraph& graph, const std::vector<View>& poses) {
    if (!keep_) return graph.observe(poses);
    std::vector<View> fresh;
    for (const View& pose : poses)
      if (!known_.count(key(pose))) fresh.push_back(pose);
    std::vector<Observation> seen = graph.observe(fresh);
    for (std::size_t k = 0; k < fresh.size(); ++k) keep(key(fresh[k]), std::move(seen[k]));
    std::vector<Observation> result;
    for (const View& pose : poses) result.push_back(known_.at(key(pose)));
    forgetOldest();
    return result;
  }

 private:
  static constexpr std::size_t kKeptPoints = std::size_t{1} << 25;  // 128 MB of indices

  using Key = std::array<double, 16>;
  static Key key(const View& pose) {
    Key k;
    Eigen::Map<Eigen::Matrix4d>(k.data()) = pose.camera_to_world.matrix();
    return k;
  }

  void keep(const Key& k, Observation seen) {
    const std::size_t points = seen.points.size();
    if (!known_.emplace(k, std::move(seen)).second) return;
    kept_points_ += points;
    order_.push_back(k);
  }

  void forgetOldest() {
    while (kept_points_ > kKeptPoints && !order_.empty()) {
      const auto oldest = known_.find(order_.front());
      kept_points_ -= oldest->second.points.size();
      known_.erase(oldest);
      order_.pop_front();
    }
  }

  bool keep_;
  std::map<Key, Observation> known_;
  std::deque<Key> order_;  // of known_, the oldest first
  std::size_t kept_points_ = 0;
};

struct Candidate {
  std::size_t pose;
  std::size_t partner;
  bool joins = false;
  double nearest = 0;
};

// Candidates that register to the main component: the best partner there, whether
// they reach another component, and how near to the others they measure; those that
// join first, then the nearest.
std::vector<Candidate> bridgeCandidates(const RegistrationGraph& graph, const Sides& sides,
                                        const std::vector<View>& poses,
                                        const std::vector<Observation>& seen) {
  std::vector<std::optional<Candidate>> found(poses.size());
  tbb::parallel_for(std::size_t{0}, poses.size(), [&](std::size_t k) {
    const auto registers = [&](std::size_t v) {
      const PairCheck pair =
          graph.check(graph.views()[v], graph.observations()[v], poses[k], seen[k]);
      return pair.passes() ? std::optional(pair) : std::nullopt;
    };
    // A pose neither joining the other side nor coming nearer to it is no candidate:
    // that is known before its pairs with the main component are checked.
    double nearest = std::numeric_limits<double>::infinity();
    for (int i : seen[k].points) nearest = std::min(nearest, sides.to_other[i]);
    bool joins = false;
    for (std::size_t v = 0; v < graph.views().size() && !joins; ++v)
      joins = sides.in_other[v] && registers(v);
    if (!joins && !(nearest < sides.gap - graph.spacing())) return;
    std::optional<std::size_t> partner;
    PairCheck best;
    for (std::size_t v = 0; v < graph.views().size(); ++v) {
      if (!sides.in_main[v]) continue;
      const std::optional<PairCheck> pair = registers(v);
      if (pair && (!partner || (pair->markers && !best.markers) ||
                   (pair->markers == best.markers && pair->condition < best.condition))) {
        partner = v;
        best = *pair;
      }
    }
    if (partner) found[k] = Candidate{k, *partner, joins, joins ? 0.0 : nearest};
  });
  std::vector<Candidate> candidates;
  for (const auto& candidate : found)
    if (candidate) candidates.push_back(*candidate);
  std::stable_sort(candidates.begin(), candidates.end(), [](auto& a, auto& b) {
    return a.joins != b.joins ? a.joins : a.nearest < b.nearest;
  });
  return candidates;
}

// A bridging view: aimed at the surface next to the main component, towards the
// component whose root is `towards`. The candidate kept registers to the main component
// (verified) and, when one does, to that component too; otherwise it brings the main
// component closer to it. Nothing when no candidate does either.
std::optional<View> bridge(RegistrationGraph& graph, const CellCheck& cell, int id, int towards,
                           Observed& observed) {
  const Sides sides = graph.sidesOf(towards);
  if (sides.main_points.empty() || sides.other_points.empty()) return std::nullopt;
  std::vector<View> poses = bridgingPoses(graph, sides);
  std::erase_if(poses,
                [&](const View& pose) { return !poseIsValid(graph.simulator(), pose, cell); });
  for (View& pose : poses) {
    pose.id = id;
    pose.task = "bridge";
  }
  const std::vector<Observation> seen = observed.of(graph, poses);
  const std::vector<Candidate> candidates = bridgeCandidates(graph, sides, poses, seen);
  constexpr std::size_t kTries = 5;  // candidates verified before giving up
  for (std::size_t c = 0; c < std::min(candidates.size(), kTries); ++c) {
    const std::size_t k = candidates[c].pose;
    if (graph.addJoined(poses[k], seen[k], candidates[c].partner)) return poses[k];
  }
  return std::nullopt;
}

}  // namespace

Registration registerWithBridging(const Simulator& simulator, std::vector<View>& views,
                                  const std::vector<Marker>& markers,
                                  const RegistrationOptions& options, const CellCheck& cell,
                                  const Progress& progress) {
  // With a robot accurate enough, every view registers: bridges would add nothing.
  if (!options.bridging || robotRegistersAll(options))
    return registerViews(simulator, views, markers, options, progress);
  std::optional<RegistrationGraph> graph;
  graph.emplace(detail::graphOf(simulator, views, markers, options, progress));
  const std::size_t first_bridge = views.size();
  int next_id = 1;
  for (const View& view : views) next_id = std::max(next_id, view.id + 1);

  // Bridging, component by component (those with a view something could register to):
  // views are added one at a time towards it; those that only come closer are kept when,
  // within kChain views, the chain joins it to the main component, and else taken back.
  constexpr std::size_t kChain = 5;
  std::optional<RegistrationGraph> joined(*graph);
  std::vector<int> hopeless;  // component roots no chain reached
  const std::size_t components = graph->components();
  std::size_t tries = 0;
  Observed observed(options.table == nullptr);
  const auto budget = static_cast<std::size_t>(options.max_bridging_views);
  while (views.size() - first_bridge < budget) {
    int towards = -1;
    for (int root : graph->bridgeable())
      if (std::find(hopeless.begin(), hopeless.end(), root) == hopeless.end()) {
        towards = root;
        break;
      }
    if (towards < 0) break;
    // Every try ends a component's turn: joined, or given up.
    report(progress, "registration: bridging " + std::to_string(components) + " components",
           std::min(1.0, static_cast<double>(tries++) / static_cast<double>(components - 1)));
    const std::size_t kept = views.size(), before = graph->components();
    while (graph->components() == before && views.size() - kept < kChain &&
           views.size() - first_bridge < budget) {
      const std::optional<View> view = bridge(*graph, cell, next_id, towards, observed);
      if (!view) break;
      views.push_back(*view);
      ++next_id;
    }
    if (graph->components() < before) {
      joined.emplace(*graph);
    } else {
      views.resize(kept);
      graph.emplace(*joined);
      hopeless.push_back(towards);
    }
  }
  return detail::finishRegistration(*graph, first_bridge,
                                    detail::registrationMethod(options, markers), markers, options);
}

}  // namespace scanplan
