// The registration graph: pair checks, a spanning tree of verified pairs, bridging views.

#include "kd_tree.h"
#include "registration/icp.h"
#include "registration/overlaps.h"

#include <scanplan/errors.h>
#include <scanplan/planning/poses.h>
#include <scanplan/registration.h>

#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <memory>
#include <numeric>

namespace scanplan {

std::string_view toString(RegistrationMethod method) {
  switch (method) {
    case RegistrationMethod::Reference: return "reference";
    case RegistrationMethod::Markers: return "markers";
    case RegistrationMethod::Icp: return "icp";
    case RegistrationMethod::Robot: return "robot";
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
  }
  return "unknown";
}

void validate(const RegistrationOptions& o, const std::string& source) {
  auto require = [&](bool ok, const std::string& what) {
    if (!ok) throw InputError(source, "registration: " + what);
  };
  require(o.min_markers >= 3, "min_markers must be at least 3");
  require(o.marker_spread > 0, "marker_spread must be positive");
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

bool Registration::links(const PairCheck& pair) const {
  return pair.markers || (pair.icp ? pair.icp->passed : pair.stable && !verified);
}

bool Registration::linked(int a, int b) const {
  if (a > b) std::swap(a, b);
  for (const PairCheck& pair : pairs)
    if (pair.a == a && pair.b == b) return links(pair);
  return false;
}

namespace {

using detail::Observation;

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

class Graph {
 public:
  Graph(const Simulator& simulator, const RegistrationOptions& options,
        const std::vector<Marker>& markers, const Progress& progress)
      : simulator_(simulator),
        options_(options),
        progress_(progress),
        overlaps_(std::make_shared<const detail::Overlaps>(simulator, options, markers)),
        points_(overlaps_->points()),
        spacing_(overlaps_->spacing()) {}

  std::vector<Observation> observe(std::span<const View> views) const {
    return overlaps_->observe(views);
  }

  PairCheck check(const View& a, const Observation& oa, const View& b,
                  const Observation& ob) const {
    return overlaps_->check(a, oa, b, ob);
  }

  // Adds views and the checks of their pairs with every view before them; then joins the
  // components by the new pairs (markers first, then the most stable, verified lazily).
  void add(std::span<const View> views) {
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

  // A bridging view: aimed at the surface next to the main component, towards the
  // component whose root is `towards`. The candidate kept registers to the main component
  // (verified) and, when one does, to that component too; otherwise it brings the main
  // component closer to it. Nothing when no candidate does either.
  std::optional<View> bridge(const CellCheck& cell, int id, int towards) {
    const Sides sides = sidesOf(towards);
    if (sides.main_points.empty() || sides.other_points.empty()) return std::nullopt;
    std::vector<View> poses = bridgingPoses(sides);
    std::erase_if(poses, [&](const View& pose) { return !poseIsValid(simulator_, pose, cell); });
    for (View& pose : poses) {
      pose.id = id;
      pose.task = "bridge";
    }
    const std::vector<Observation> seen = observe(poses);
    const std::vector<Candidate> candidates = bridgeCandidates(sides, poses, seen);
    constexpr std::size_t kTries = 5;  // candidates verified before giving up
    for (std::size_t c = 0; c < std::min(candidates.size(), kTries); ++c) {
      const std::size_t v = candidates[c].partner, k = candidates[c].pose;
      const std::size_t index = views_.size();
      const std::vector<std::size_t> fresh = insert(poses[k], seen[k]);
      const auto partner = std::find_if(fresh.begin(), fresh.end(),
                                        [&](std::size_t p) { return ends_[p].first == v; });
      if (partner != fresh.end() && verify(*partner)) {
        connect(fresh);
        return poses[k];
      }
      // Not registrable after all: take it back out.
      views_.resize(index);
      seen_.resize(index);
      parent_.resize(index);
      constrained_.resize(index);
      pairs_.resize(pairs_.size() - fresh.size());
      ends_.resize(pairs_.size());
    }
    return std::nullopt;
  }

  // The two sides a bridge joins: the main component and the one it is bridged towards,
  // their views and surface points, and how far every surface point is from each.
  struct Sides {
    std::vector<char> in_main, in_other;  // per view
    std::vector<Vec3> main_points, other_points;
    std::vector<double> to_main, to_other;  // per surface point
    double gap = 0;                         // from the main component's points to the other's
  };

  Sides sidesOf(int towards) {
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

  // The poses a bridge is chosen from (planning/poses.h): around targets near the main
  // component, and between its views and nearby views of the other side.
  std::vector<View> bridgingPoses(const Sides& sides) const {
    // Targets within reach of the main component, nearest to the others first, spread out.
    const Scanner& scanner = simulator_.scanner();
    std::vector<int> order;
    for (std::size_t i = 0; i < points_.size(); ++i)
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
    for (std::size_t v = 0; v < views_.size(); ++v)
      if (sides.in_main[v]) {
        double d = std::numeric_limits<double>::infinity();
        for (int i : seen_[v].points) d = std::min(d, sides.to_other[i]);
        nearest_main.push_back({d, v});
      }
    std::stable_sort(nearest_main.begin(), nearest_main.end());
    std::vector<Eigen::Matrix3d> orientations;
    for (const auto& [d, v] : nearest_main) {
      if (orientations.size() == kOrientations) break;
      const Eigen::Matrix3d r = views_[v].camera_to_world.linear();
      const bool known = std::any_of(orientations.begin(), orientations.end(), [&](auto& o) {
        return Eigen::AngleAxisd(o.transpose() * r).angle() < radians(10);
      });
      if (!known) orientations.push_back(r);
    }
    for (int i : order) {
      if (targets.size() == 32) break;
      const Vec3& p = points_[i].position;
      if (std::any_of(targets.begin(), targets.end(),
                      [&](const Vec3& t) { return (t - p).norm() < scanner.fov_height / 4; }))
        continue;
      targets.push_back(p);
      std::vector<View> around = posesAround(scanner, points_[i]);
      for (const Eigen::Matrix3d& r : orientations) around.push_back(orientedPose(scanner, p, r));
      poses.insert(poses.end(), around.begin(), around.end());
    }
    // Poses between a view of the main component and a nearby view of another: target and
    // orientation interpolated, and each one's orientation aimed at the other's target.
    std::vector<std::pair<double, std::pair<std::size_t, std::size_t>>> near;
    for (std::size_t m = 0; m < views_.size(); ++m)
      for (std::size_t o = 0; o < views_.size(); ++o)
        if (sides.in_main[m] && sides.in_other[o]) {
          const double d = (views_[m].target - views_[o].target).norm();
          if (d < 2 * scanner.fov_width) near.push_back({d, {m, o}});
        }
    std::sort(near.begin(), near.end());
    near.resize(std::min<std::size_t>(near.size(), 24));
    for (const auto& [d, pair] : near) {
      const View &a = views_[pair.first], &b = views_[pair.second];
      for (const auto& [t, turn] :
           {std::pair{1.0 / 3, 1.0 / 3}, {0.5, 0.5}, {2.0 / 3, 2.0 / 3}, {1.0, 0.0}, {0.0, 1.0}})
        poses.push_back(poseBetween(a, b, t, turn, scanner.standoff));
    }
    return poses;
  }

  struct Candidate {
    std::size_t pose;
    std::size_t partner;
    bool joins = false;
    double nearest = 0;
  };

  // Candidates that register to the main component: the best partner there, whether
  // they reach another component, and how near to the others they measure; those that
  // join first, then the nearest.
  std::vector<Candidate> bridgeCandidates(const Sides& sides, const std::vector<View>& poses,
                                          const std::vector<Observation>& seen) const {
    std::vector<std::optional<Candidate>> found(poses.size());
    tbb::parallel_for(std::size_t{0}, poses.size(), [&](std::size_t k) {
      const auto registers = [&](std::size_t v) {
        const PairCheck pair = check(views_[v], seen_[v], poses[k], seen[k]);
        return pair.markers || pair.stable ? std::optional(pair) : std::nullopt;
      };
      // A pose neither joining the other side nor coming nearer to it is no candidate:
      // that is known before its pairs with the main component are checked.
      double nearest = std::numeric_limits<double>::infinity();
      for (int i : seen[k].points) nearest = std::min(nearest, sides.to_other[i]);
      bool joins = false;
      for (std::size_t v = 0; v < views_.size() && !joins; ++v)
        joins = sides.in_other[v] && registers(v);
      if (!joins && !(nearest < sides.gap - spacing_)) return;
      std::optional<std::size_t> partner;
      PairCheck best;
      for (std::size_t v = 0; v < views_.size(); ++v) {
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

  // Verifies the pair (when verification is on and it is an ICP pair).
  bool verify(std::size_t p) {
    PairCheck& pair = pairs_[p];
    if (pair.markers) return true;
    if (!pair.stable) return false;
    if (!options_.verify) return true;
    if (!pair.icp) registerPairs({p});
    return pair.icp->passed;
  }

  int find(int v) {
    while (parent_[v] != v) v = parent_[v] = parent_[parent_[v]];
    return v;
  }

  std::size_t components() {
    std::size_t count = 0;
    for (std::size_t v = 0; v < views_.size(); ++v)
      count += find(static_cast<int>(v)) == static_cast<int>(v);
    return count;
  }

  // The root of the largest component (ties: the one with the earliest view).
  int mainComponent() {
    std::map<int, std::size_t> sizes;
    for (std::size_t v = 0; v < views_.size(); ++v) ++sizes[find(static_cast<int>(v))];
    int best = -1;
    for (std::size_t v = 0; v < views_.size(); ++v) {
      const int root = find(static_cast<int>(v));
      if (best < 0 || sizes[root] > sizes[best]) best = root;
    }
    return best;
  }

  // The roots of the components other than the main one that hold a view something
  // could register to.
  std::vector<int> bridgeable() {
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

  // The registration of each view: a tree rooted at the reference view, over the pairs
  // used. Views from `first_bridge` on are bridging views.
  Registration result(std::size_t first_bridge) {
    Registration registration;
    registration.pairs = pairs_;
    registration.verified = options_.verify;
    registration.components = components();
    registration.views.resize(views_.size());
    for (std::size_t v = first_bridge; v < views_.size(); ++v) registration.views[v].bridge = true;
    for (std::size_t v = 0; v < views_.size(); ++v)
      registration.views[v].constrained = constrained_[v];
    registration.bridging_views = views_.size() - first_bridge;
    if (views_.empty()) return registration;
    // The reference: in the main component, the view that sees the most markers, else the
    // first.
    const int main = mainComponent();
    int reference = -1;
    for (std::size_t v = 0; v < views_.size(); ++v) {
      if (find(static_cast<int>(v)) != main) continue;
      if (reference < 0 || seen_[v].markers.size() > seen_[reference].markers.size())
        reference = static_cast<int>(v);
    }
    registration.reference = views_[reference].id;
    registration.views[reference].method = RegistrationMethod::Reference;
    std::vector<int> queue{reference};
    std::vector<char> reached(views_.size(), 0);
    reached[reference] = 1;
    for (std::size_t q = 0; q < queue.size(); ++q) {
      const int v = queue[q];
      for (std::size_t p : used_) {
        const auto [i, j] = ends_[p];
        const int other = static_cast<int>(i) == v   ? static_cast<int>(j)
                          : static_cast<int>(j) == v ? static_cast<int>(i)
                                                     : -1;
        if (other < 0 || reached[other]) continue;
        reached[other] = 1;
        registration.views[other].method =
            pairs_[p].markers ? RegistrationMethod::Markers : RegistrationMethod::Icp;
        registration.views[other].to = views_[v].id;
        queue.push_back(other);
      }
    }
    return registration;
  }

 private:
  // Stores the view and the checks of its pairs with every view before it; returns the
  // indices of those pairs.
  std::vector<std::size_t> insert(const View& view, const Observation& seen) {
    const std::size_t index = views_.size();
    views_.push_back(view);
    seen_.push_back(seen);
    parent_.push_back(static_cast<int>(index));
    constrained_.push_back(overlaps_->constrained(seen));
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

  // Distance from each surface point to the nearest of `to`.
  std::vector<double> distances(const std::vector<Vec3>& to) const {
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

  // Joins components by the `candidates` pairs, in the manner of Kruskal's algorithm;
  // `shown`: with progress (the share of the registrable pairs walked).
  void connect(std::vector<std::size_t> candidates, bool shown = false) {
    std::stable_sort(candidates.begin(), candidates.end(), [&](std::size_t x, std::size_t y) {
      const PairCheck &a = pairs_[x], &b = pairs_[y];
      if (a.markers != b.markers) return a.markers;
      if (a.markers) return a.shared_markers > b.shared_markers;
      return a.condition < b.condition;
    });
    const auto registrable = static_cast<std::size_t>(
        std::count_if(candidates.begin(), candidates.end(),
                      [&](std::size_t p) { return pairs_[p].markers || pairs_[p].stable; }));
    std::size_t verified_up_to = 0;  // candidates before this index were ICP-verified ahead
    std::size_t walked = 0;          // registrable candidates passed
    for (std::size_t k = 0; k < candidates.size(); ++k) {
      const std::size_t p = candidates[k];
      const PairCheck& pair = pairs_[p];
      if (!pair.markers && !pair.stable) continue;
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
      parent_[std::max(a, b)] = std::min(a, b);
      used_.push_back(p);
    }
  }

  // Runs the ICP checks of the next few candidates from `first` that would join two
  // components as things stand, in parallel; returns the index after the last one looked
  // at. Some may turn out not to be needed once an earlier one joins their components;
  // the tree is the same as with one check at a time. Six checks a core: with fewer, a
  // core waits idle behind the longest check of a batch.
  std::size_t verifyAhead(const std::vector<std::size_t>& candidates, std::size_t first) {
    if (!options_.verify) return candidates.size();
    const std::size_t batch_size =
        6 * static_cast<std::size_t>(tbb::this_task_arena::max_concurrency());
    std::vector<std::size_t> batch;
    std::size_t k = first;
    for (; k < candidates.size() && batch.size() < batch_size; ++k) {
      const std::size_t p = candidates[k];
      const PairCheck& pair = pairs_[p];
      if (pair.markers || !pair.stable || pair.icp) continue;
      if (find(static_cast<int>(ends_[p].first)) == find(static_cast<int>(ends_[p].second)))
        continue;
      batch.push_back(p);
    }
    registerPairs(batch);
    return k;
  }

  // The ICP clouds of the views of `pairs` not made before, in parallel.
  void makeClouds(const std::vector<std::size_t>& pairs) {
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

  // The ICP checks of `pairs`, in parallel; pairs checked before (as the same views) are not
  // checked again, and the clouds of the others' views are made once each.
  void registerPairs(const std::vector<std::size_t>& pairs) {
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

  const Simulator& simulator_;
  const RegistrationOptions& options_;
  const Progress& progress_;
  std::shared_ptr<const detail::Overlaps> overlaps_;  // shared by the copies of a graph
  const std::vector<SurfacePoint>& points_;
  double spacing_ = 0;
  std::vector<View> views_;
  std::vector<Observation> seen_;
  std::vector<PairCheck> pairs_;
  std::vector<std::pair<std::size_t, std::size_t>> ends_;  // view indices of each pair
  std::vector<int> parent_;                                // union-find over view indices
  std::vector<char> constrained_;  // per view: something could register to it
  std::vector<std::size_t> used_;  // pairs of the spanning tree
  std::shared_ptr<IcpMemo> memo_ = std::make_shared<IcpMemo>();
  // The last main component (per view: in it) and each surface point's distance from it,
  // the same for every component bridged towards until a bridge joins one.
  std::pair<std::vector<char>, std::vector<double>> to_main_;
};

// Every view registered to nothing registered by the robot, into the reference's frame.
void registerByRobot(Registration& registration) {
  for (ViewRegistration& view : registration.views)
    if (view.method == RegistrationMethod::None) {
      view.method = RegistrationMethod::Robot;
      view.to = registration.reference;
    }
}

}  // namespace

Registration registerViews(const Simulator& simulator, std::vector<View>& views,
                           const std::vector<Marker>& markers, const RegistrationOptions& options,
                           const CellCheck& cell, const Progress& progress) {
  validate(options, "registration");
  const RegistrationMode method = options.method != RegistrationMode::Default ? options.method
                                  : markers.empty() ? RegistrationMode::Geometry
                                                    : RegistrationMode::Markers;
  // With a robot accurate enough, every view registers: bridges would add nothing.
  const bool by_robot = robotRegistersAll(options);
  static const std::vector<Marker> no_markers;
  std::optional<Graph> graph;
  graph.emplace(simulator, options, method == RegistrationMode::Geometry ? no_markers : markers,
                progress);
  report(progress, "registration: overlaps of " + std::to_string(views.size()) + " views", 0);
  graph->add(views);
  const std::size_t first_bridge = views.size();
  int next_id = 1;
  for (const View& view : views) next_id = std::max(next_id, view.id + 1);

  // Bridging, component by component (those with a view something could register to):
  // views are added one at a time towards it; those that only come closer are kept when,
  // within kChain views, the chain joins it to the main component, and else taken back.
  constexpr std::size_t kChain = 5;
  std::optional<Graph> joined(*graph);
  std::vector<int> hopeless;  // component roots no chain reached
  const std::size_t components = graph->components();
  std::size_t tries = 0;
  const auto budget = static_cast<std::size_t>(options.max_bridging_views);
  while (options.bridging && !by_robot && views.size() - first_bridge < budget) {
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
      const std::optional<View> bridge = graph->bridge(cell, next_id, towards);
      if (!bridge) break;
      views.push_back(*bridge);
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
  Registration registration = graph->result(first_bridge);
  registration.markers = markers.size();
  registration.method = method;
  registration.required = options.required;
  if (method == RegistrationMode::Robot) registration.robot_accuracy = options.robot_accuracy;
  if (by_robot) registerByRobot(registration);
  return registration;
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
    into.robot_accuracy = from.robot_accuracy;
  }
  shift(from.reference);
  if (into.reference == 0) into.reference = from.reference;
}

}  // namespace scanplan
