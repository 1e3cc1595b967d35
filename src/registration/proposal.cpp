// Markers proposed where views register to nothing (docs/registration.md).

#include <scanplan/core/disjoint_sets.h>
#include <scanplan/registration/registration.h>
#include <scanplan/solve/set_cover.h>

#include <algorithm>
#include <iterator>
#include <map>
#include <numeric>

namespace scanplan {
namespace {

// CBC's search for the proposal and for its bound.
constexpr SolveLimits kLimits{1000, 60};

// The pairs of views markers must join: a spanning forest over the pairs that see at least
// `least` candidates in common, the pairs that register already taken first and free, then
// those with the most candidates in common. Each pair with the candidates both see, and
// per view whether a pair joins it.
struct Joins {
  std::vector<std::vector<int>> pairs;
  std::vector<char> joined;
};
Joins pairsToJoin(std::span<const View> views, const Registration& registration,
                  const std::vector<std::vector<int>>& seen, std::size_t least) {
  std::map<std::pair<int, int>, std::vector<int>> common;  // view indices -> candidates
  std::map<int, std::vector<int>> viewers;                 // candidate -> view indices
  for (std::size_t v = 0; v < views.size(); ++v)
    for (int c : seen[v]) viewers[c].push_back(static_cast<int>(v));
  for (const auto& [c, by] : viewers)
    for (std::size_t i = 0; i < by.size(); ++i)
      for (std::size_t j = i + 1; j < by.size(); ++j) common[{by[i], by[j]}].push_back(c);

  DisjointSets sets(views.size());
  std::map<int, int> index;  // view id -> index
  for (std::size_t v = 0; v < views.size(); ++v) index[views[v].id] = static_cast<int>(v);
  for (const PairCheck& pair : registration.pairs)
    if (registration.links(pair) && index.count(pair.a) && index.count(pair.b))
      sets.join(index[pair.a], index[pair.b]);
  std::vector<std::pair<std::pair<int, int>, std::vector<int>>> ranked(common.begin(),
                                                                       common.end());
  std::stable_sort(ranked.begin(), ranked.end(),
                   [](auto& x, auto& y) { return x.second.size() > y.second.size(); });
  Joins joins;
  joins.joined.resize(views.size(), 0);
  for (auto& [ends, candidates] : ranked) {
    if (candidates.size() < least) break;
    if (!sets.join(ends.first, ends.second)) continue;
    joins.pairs.push_back(std::move(candidates));
    joins.joined[ends.first] = joins.joined[ends.second] = 1;
  }
  return joins;
}

// Of `pair`'s candidates not taken, the one farthest from the line through the two markers
// of `shared` farthest apart (any, with fewer than two); -1 when none is left.
int farthestFromLine(const std::vector<Marker>& candidates, const std::vector<int>& pair,
                     const std::vector<char>& taken, const std::vector<Vec3>& shared) {
  Vec3 a = Vec3::Zero(), b = Vec3::Zero();
  for (const Vec3& p : shared)
    for (const Vec3& q : shared)
      if ((p - q).norm() > (a - b).norm()) {
        a = p;
        b = q;
      }
  const Vec3 direction = (b - a).norm() > 0 ? Vec3((b - a).normalized()) : Vec3::Zero();
  int best = -1;
  double best_distance = -1;
  for (int c : pair) {
    if (taken[c]) continue;
    const Vec3 d = candidates[c].position - a;
    const double distance = (d - d.dot(direction) * direction).norm();
    if (distance > best_distance) {
      best_distance = distance;
      best = c;
    }
  }
  return best;
}

// Adds to `taken` candidates of `seen` (a view's or a pair's), farthest from the line of
// those taken and of the markers at `placed` first, until they register together
// (markersRegister) or none is left.
void spreadOut(const std::vector<Marker>& candidates, const std::vector<int>& seen,
               std::vector<char>& taken, const RegistrationOptions& options,
               std::vector<Vec3> placed = {}) {
  for (int c : seen)
    if (taken[c]) placed.push_back(candidates[c].position);
  while (!markersRegister(placed, options.min_markers, options.marker_spread)) {
    const int c = farthestFromLine(candidates, seen, taken, placed);
    if (c < 0) break;
    taken[c] = 1;
    placed.push_back(candidates[c].position);
  }
}

// With reference points, each view registered to nothing that sees min_markers candidates
// and markers in all needs that many, spread out: the fewest candidates that give them
// with the markers each sees already (CBC), whose bound is the proposal's.
MarkerProposal proposeReferencePoints(std::span<const View> views, const Registration& registration,
                                      const std::vector<Marker>& candidates,
                                      const std::vector<std::vector<int>>& seen,
                                      const std::vector<std::vector<Vec3>>& seen_placed,
                                      const RegistrationOptions& options) {
  MarkerProposal proposal;
  std::vector<std::vector<int>> views_of(candidates.size());
  std::vector<std::size_t> served;  // view indices
  std::vector<int> need;            // per view served
  for (std::size_t v = 0; v < views.size() && v < registration.views.size(); ++v) {
    const auto least = static_cast<std::size_t>(options.min_markers);
    if (registration.views[v].method != RegistrationMethod::None) continue;
    if (seen[v].size() + seen_placed[v].size() < least) {
      proposal.unserved.push_back(views[v].id);
      continue;
    }
    for (int c : seen[v]) views_of[c].push_back(static_cast<int>(served.size()));
    served.push_back(v);
    need.push_back(static_cast<int>(least - std::min(least - 1, seen_placed[v].size())));
  }
  const SetCoverResult cover = minimumMulticover(views_of, need, kLimits);
  std::vector<char> taken(candidates.size(), 0);
  for (int c : cover.chosen) taken[c] = 1;
  for (std::size_t v : served) spreadOut(candidates, seen[v], taken, options, seen_placed[v]);
  // Those spread out may leave some of the cover's without use: each is dropped when every
  // view served that registers still does without it.
  const auto registers = [&](std::size_t v) {
    std::vector<Vec3> markers = seen_placed[v];
    for (int c : seen[v])
      if (taken[c]) markers.push_back(candidates[c].position);
    return markersRegister(markers, options.min_markers, options.marker_spread);
  };
  // A view whose candidates all lie near one line keeps the cover's markers it sees: it
  // registers by none, and is counted among the views the proposal does not serve.
  std::vector<std::size_t> registering;
  std::vector<char> kept(candidates.size(), 0);
  for (std::size_t v : served)
    if (registers(v))
      registering.push_back(v);
    else {
      proposal.unserved.push_back(views[v].id);
      for (int c : seen[v]) kept[c] = 1;
    }
  for (int c : cover.chosen) {
    if (kept[c]) continue;
    taken[c] = 0;
    if (!std::all_of(registering.begin(), registering.end(), registers)) taken[c] = 1;
  }
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (taken[c]) proposal.markers.push_back(candidates[c]);
  std::sort(proposal.unserved.begin(), proposal.unserved.end());
  proposal.views = registering.size();
  proposal.lower_bound = static_cast<std::size_t>(cover.lower_bound);
  return proposal;
}

}  // namespace

MarkerProposal proposeMarkers(const Simulator& simulator, std::span<const View> views,
                              const Registration& registration,
                              const std::vector<Marker>& candidates,
                              const std::vector<Marker>& placed,
                              const RegistrationOptions& options) {
  MarkerProposal proposal;
  const auto seenBy = [&](const std::vector<Marker>& markers) {
    std::vector<SurfacePoint> points;
    for (const Marker& m : markers) points.push_back({m.position, m.normal, 0});
    return measuredPoints(simulator, views, points);
  };
  const std::vector<std::vector<int>> seen = seenBy(candidates);
  if (options.method == RegistrationMode::ReferencePoints) {
    std::vector<std::vector<Vec3>> seen_placed(views.size());
    const std::vector<std::vector<int>> placed_seen = seenBy(placed);
    for (std::size_t v = 0; v < views.size(); ++v)
      for (int m : placed_seen[v]) seen_placed[v].push_back(placed[m].position);
    return proposeReferencePoints(views, registration, candidates, seen, seen_placed, options);
  }
  const auto least = static_cast<std::size_t>(options.min_markers);
  const Joins joins = pairsToJoin(views, registration, seen, least);
  const std::vector<std::vector<int>>& pairs = joins.pairs;

  // The fewest candidates giving every pair min_markers in common (CBC), then more for the
  // pairs whose markers lie too near one line, farthest from that line first.
  std::vector<std::vector<int>> pairs_of(candidates.size());
  for (std::size_t p = 0; p < pairs.size(); ++p)
    for (int c : pairs[p]) pairs_of[c].push_back(static_cast<int>(p));
  std::vector<char> taken(candidates.size(), 0);
  for (int c :
       minimumMulticover(pairs_of, std::vector<int>(pairs.size(), options.min_markers), kLimits)
           .chosen)
    taken[c] = 1;
  for (const std::vector<int>& pair : pairs) spreadOut(candidates, pair, taken, options);
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (taken[c]) proposal.markers.push_back(candidates[c]);

  // The bound: each view registered to nothing that the proposal joins needs min_markers
  // markers it sees: the multicover's lower bound.
  std::vector<std::vector<int>> views_of(candidates.size());
  for (std::size_t v = 0; v < views.size() && v < registration.views.size(); ++v) {
    if (registration.views[v].method != RegistrationMethod::None) continue;
    if (!joins.joined[v]) {
      proposal.unserved.push_back(views[v].id);
      continue;
    }
    for (int c : seen[v]) views_of[c].push_back(static_cast<int>(proposal.views));
    ++proposal.views;
  }
  const SetCoverResult bound =
      minimumMulticover(views_of, std::vector<int>(proposal.views, options.min_markers), kLimits);
  proposal.lower_bound = static_cast<std::size_t>(bound.lower_bound);
  return proposal;
}

}  // namespace scanplan
