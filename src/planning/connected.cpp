// The registration-aware selection (docs/planning.md): a cover of the pool's samples whose
// views register to each other, by the markers they share or their geometry, grown from
// view to view.

#include "planning/rate_queue.h"
#include "planning/stages.h"
#include "registration/icp.h"
#include "registration/overlaps.h"

#include <scanplan/core/disjoint_sets.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <limits>
#include <map>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <queue>
#include <tuple>

namespace scanplan::detail {

namespace {

// Below this many shared samples, an overlap is not taken to register.
constexpr std::size_t kLeastShared = 6;

// A pose registering to a chosen view is taken unless it measures less than a share of what
// the best pose something could register to measures: then that one starts a new group,
// rather than the cover creeping on a sample or two at a time. Which share gives the
// largest group depends on the part: each of these is tried, the first kept unless a later
// one's largest group holds kBetter more of its views.
constexpr double kCreeps[] = {0.25, 0.1, 0};
constexpr double kBetter = 0.05;

// Poses tried as the connector of two groups (joinGroups).
constexpr std::size_t kConnectorTries = 128;

// Chains of poses joining the groups the cover leaves apart (chainTo): at most this many
// poses, found within this many pairs looked at.
constexpr std::size_t kChainLinks = 6;
constexpr std::size_t kChainTests = 10000;
constexpr std::size_t kChainFailures = 10;  // chains failing ICP before the search gives up

// Priority samples not yet covered, then the others: compared in that order.
using Gain = std::pair<int, int>;

// Whether the condition number of the samples' ICP constraints, each by the area it stands
// for, is at most `limit`.
bool conditionWithin(const Placement& at, const std::vector<PlannedSample>& samples,
                     const std::vector<int>& measured, double limit) {
  std::vector<Vec3> p, n;
  std::vector<double> w;
  for (int i : measured) {
    p.push_back(at.points[i].position);
    n.push_back(at.points[i].normal);
    w.push_back(samples[i].sample.weight);
  }
  return icpConditionWithin(p, n, limit, w);
}

// What every run of the cover reads: the pair test, the poses by sample and by marker, the
// poses something could register to, and what poses measure as the pair test sees it,
// observed once each, by whichever run asks first (runs go in parallel).
class CoverContext {
 public:
  CoverContext(const Placement& placement, const MeasuredViews& poses,
               const std::vector<PlannedSample>& planned, const SelectionAim& aimed,
               const std::vector<Marker>& markers, const Progress& progress)
      : at(placement),
        pool(poses),
        samples(planned),
        aim(aimed),
        options(registrationOptions(placement.spec.spec)),
        overlaps(at.simulator, options, markers),
        progress_(progress) {
    by_sample.resize(samples.size());
    for (std::size_t v = 0; v < pool.size(); ++v)
      for (int i : pool.samples[v]) by_sample[i].push_back(static_cast<int>(v));
    for (std::size_t i = 0; i < samples.size(); ++i)
      coverable += !by_sample[i].empty() && !at.isDone(i);
    by_group.resize(aim.needs.need.size());
    for (std::size_t i = 0; i < samples.size(); ++i)
      if (const int g = aim.needs.group[i]; g >= 0) by_group[g].push_back(static_cast<int>(i));
    if (overlaps.markers() > 0) markers_seen = overlaps.markersSeen(pool.views);
    by_marker.resize(overlaps.markers());
    for (std::size_t v = 0; v < markers_seen.size(); ++v)
      for (int m : markers_seen[v]) by_marker[m].push_back(static_cast<int>(v));
    const auto least_markers = static_cast<std::size_t>(options.min_markers);
    constrained.resize(pool.size());
    tbb::parallel_for(std::size_t{0}, pool.size(), [&](std::size_t v) {
      constrained[v] = conditionWithin(at, samples, pool.samples[v], options.max_condition) ||
                       (!markers_seen.empty() && markers_seen[v].size() >= least_markers);
    });
  }

  const Observation& seen(std::size_t v) const {
    {
      const std::lock_guard lock(mutex_);
      if (const auto found = seen_.find(v); found != seen_.end()) return found->second;
    }
    Observation made = overlaps.observe({&pool.views[v], 1}).front();
    const std::lock_guard lock(mutex_);
    return seen_.emplace(v, std::move(made)).first->second;  // the first made, if two were
  }

  // Whether pool poses `fixed` and `moved` pass the registration's ICP verification
  // (checkIcp), each pair verified once and each pose's cloud made once.
  bool icpPasses(std::size_t fixed, std::size_t moved) const {
    {
      const std::lock_guard lock(mutex_);
      if (const auto found = icp_.find({fixed, moved}); found != icp_.end()) return found->second;
    }
    const bool passed =
        detail::checkIcp(at.simulator, *cloud(fixed), cloud(moved)->cloud, options).passed;
    const std::lock_guard lock(mutex_);
    return icp_.emplace(std::pair{fixed, moved}, passed).first->second;
  }

  // Cover run `run` (of kCreeps) has covered `covered` samples: progress shows the share
  // the runs have covered on average, by whole percents (with fewer cores than runs, a
  // run may not start before another ends).
  void covered(std::size_t run, std::size_t covered) const {
    if (coverable == 0) return;
    const double share = static_cast<double>(covered) / static_cast<double>(coverable);
    const std::lock_guard lock(mutex_);
    shares_[run] = share;
    const double mean = std::accumulate(std::begin(shares_), std::end(shares_), 0.0) /
                        static_cast<double>(std::size(shares_));
    if (mean <= shown_ || mean < std::min(shown_ + 0.01, 1.0)) return;  // the end always shows
    shown_ = mean;
    report(progress_, "selection: covering the samples", mean);
  }

  // Progress of the chains: `done` of the `groups` left apart sought for.
  void joined(std::size_t done, std::size_t groups) const {
    report(progress_,
           "selection: joining " + std::to_string(groups) + (groups == 1 ? " group" : " groups") +
               " apart",
           static_cast<double>(done) / static_cast<double>(groups));
  }

  // Whether the pair failed ICP verification before.
  bool icpFailed(std::size_t fixed, std::size_t moved) const {
    const std::lock_guard lock(mutex_);
    const auto found = icp_.find({fixed, moved});
    return found != icp_.end() && !found->second;
  }

  const Placement& at;
  const MeasuredViews& pool;
  const std::vector<PlannedSample>& samples;
  const SelectionAim& aim;
  const RegistrationOptions options;  // as the registration stage's
  const Overlaps overlaps;
  std::vector<std::vector<int>> by_sample;     // the poses measuring each sample
  std::vector<std::vector<int>> markers_seen;  // per pose, when there are markers
  std::vector<std::vector<int>> by_marker;     // the poses measuring each marker
  std::vector<std::vector<int>> by_group;      // the samples of each group of the aim
  std::vector<char> constrained;               // per pose: something may register to it
  std::size_t coverable = 0;                   // samples some pose measures, not done before

 private:
  std::shared_ptr<const IndexedCloud> cloud(std::size_t v) const {
    {
      const std::lock_guard lock(mutex_);
      if (const auto found = clouds_.find(v); found != clouds_.end()) return found->second;
    }
    // The pool index as the view's id, which seeds the cloud's noise and the perturbation
    // ICP starts from: poses of the pool have none of their own.
    View view = pool.views[v];
    view.id = static_cast<int>(v) + 1;
    auto made = std::make_shared<const IndexedCloud>(icpCloud(at.simulator, view, options));
    const std::lock_guard lock(mutex_);
    return clouds_.emplace(v, std::move(made)).first->second;
  }

  const Progress& progress_;
  mutable std::mutex mutex_;
  mutable double shares_[std::size(kCreeps)] = {};   // per cover run: share covered
  mutable double shown_ = 0;                         // the share progress showed last
  mutable std::map<std::size_t, Observation> seen_;  // by pool index
  mutable std::map<std::size_t, std::shared_ptr<const IndexedCloud>> clouds_;  // by pool index
  mutable std::map<std::pair<std::size_t, std::size_t>, bool> icp_;  // (fixed, moved): passed
};

// Grows the cover one view at a time, each the pose that measures most samples not yet
// covered among those registering to a view already chosen; another group of views is
// started only when none of those measures anything new.
//
// Which poses register to a chosen view is foreseen from the samples and markers they
// share, and confirmed by the registration's own pair test (registration/overlaps.h)
// before a pose is chosen: samples are too sparse to judge an overlap by, but cheap to
// rule one out.
class ConnectedCover {
  // A chosen view a pose may register to: judged 1 when foreseen to (markers it shares
  // judge at once), -1 when not, 0 while not yet judged.
  struct Partner {
    std::size_t view;
    signed char judged;
  };

 public:
  // The cover run `run` of kCreeps.
  ConnectedCover(const CoverContext& context, std::size_t run)
      : context_(context),
        run_(run),
        at_(context.at),
        pool_(context.pool),
        samples_(context.samples),
        options_(context.options),
        overlaps_(context.overlaps),
        by_sample_(context.by_sample),
        markers_seen_(context.markers_seen),
        by_marker_(context.by_marker),
        constrained_(context.constrained),
        shared_(context.pool.size()) {}

  // One cover, with its run's creep the share below which a new group starts, and the
  // share of its views in its largest group of views registering to each other.
  std::pair<std::vector<std::size_t>, double> run(std::size_t pinned) {
    const double creep = kCreeps[run_];
    reset(pinned);
    for (std::size_t v = 0; v < pinned; ++v) choose(v);
    while (!met()) {
      const auto linked = best(linked_, [&](std::size_t v) { return hasPartner(v); });
      const auto seed = best(seeds_, [&](std::size_t v) { return constrained_[v] != 0; });
      const bool jump = seed && (!linked || total(gain_[*linked]) < creep * total(gain_[*seed]));
      if (linked && !jump) {
        if (const auto partner = registeredPartner(*linked)) choose(*linked, partner);
        continue;
      }
      // A new group of views, from a pose that something could register to.
      if (seed) {
        if (overlaps_.constrained(seen(*seed))) {
          choose(*seed);
        } else {
          constrained_[*seed] = 0;
        }
        continue;
      }
      const auto next = best(all_, [](std::size_t) { return true; });
      if (!next) break;
      choose(*next);
    }
    if (std::none_of(parent_.begin(), parent_.end(), [](auto& p) { return p.has_value(); }))
      return {};
    joinGroups(false);
    dropRedundantLeaves();
    return {chosen_, static_cast<double>(largestGroup()) / static_cast<double>(chosen_.size())};
  }

  // The cover run made, with the groups still apart joined through chains of poses where
  // that can be done (chainTo).
  std::vector<std::size_t> chained() {
    joinGroups(true);
    dropRedundantLeaves();
    return chosen_;
  }

 private:
  void reset(std::size_t pinned) {
    pinned_ = pinned;
    unmet_ = context_.aim.needs.need;
    covered_.resize(samples_.size());
    for (std::size_t i = 0; i < samples_.size(); ++i) covered_[i] = at_.isDone(i);
    gain_.assign(pool_.size(), {0, 0});
    for (std::size_t v = 0; v < pool_.size(); ++v)
      for (int i : pool_.samples[v])
        if (gains(i)) ++part(gain_[v], i);
    newly_covered_ = 0;
    used_.assign(pool_.size(), 0);
    partners_.assign(pool_.size(), {});
    chosen_.clear();
    parent_.clear();
    links_.clear();
    tested_.clear();
    linked_ = seeds_ = all_ = {};
    for (std::size_t v = 0; v < pool_.size(); ++v) {
      all_.push(v, rate(v));
      if (constrained_[v]) seeds_.push(v, rate(v));
    }
  }

  // Per chosen view (pool index), the root of its group: the views registering to one
  // another through their parents and the links of joined groups.
  std::map<std::size_t, std::size_t> groups() const {
    std::map<std::size_t, int> at;  // pool index: its place in chosen_
    for (std::size_t k = 0; k < chosen_.size(); ++k) at[chosen_[k]] = static_cast<int>(k);
    DisjointSets sets(chosen_.size());
    for (std::size_t k = 0; k < chosen_.size(); ++k)
      if (parent_[k]) sets.join(static_cast<int>(k), at.at(*parent_[k]));
    for (const auto& [a, b] : links_) sets.join(at.at(a), at.at(b));
    std::map<std::size_t, std::size_t> root;
    for (std::size_t k = 0; k < chosen_.size(); ++k)
      root[chosen_[k]] = chosen_[static_cast<std::size_t>(sets.find(static_cast<int>(k)))];
    return root;
  }

  // The most chosen views in one group.
  std::size_t largestGroup() const {
    std::map<std::size_t, std::size_t> size_of_root;
    std::size_t largest = 0;
    for (const auto& [v, root] : groups()) largest = std::max(largest, ++size_of_root[root]);
    return largest;
  }

  // Joins the other groups to the largest, the larger first, each through a connector: a
  // pose of the pool that registers to a view of both, measuring nothing new (joinGroup);
  // with `chains`, through a chain of such poses instead (chainTo).
  void joinGroups(bool chains) {
    std::map<std::size_t, std::vector<std::size_t>> members;  // by root
    for (const auto& [v, r] : groups()) members[r].push_back(v);
    std::vector<std::vector<std::size_t>> others;
    for (auto& [r, views] : members) others.push_back(std::move(views));
    std::stable_sort(others.begin(), others.end(),
                     [](auto& a, auto& b) { return a.size() > b.size(); });
    std::vector<std::size_t> main = std::move(others.front());
    std::vector<std::size_t> with_main(pool_.size(), 0);  // per pose: samples shared with main
    const auto share = [&](std::size_t c) {
      for (const auto& [v, n] : sharing(pool_.samples[c], by_sample_)) with_main[v] += n;
    };
    for (std::size_t c : main) share(c);
    for (std::size_t k = 1; k < others.size(); ++k) {
      if (chains) context_.joined(k - 1, others.size() - 1);
      const std::vector<std::size_t> added =
          chains ? chainTo(main, others[k], with_main) : joinGroup(main, others[k], with_main);
      if (added.empty()) continue;
      for (std::size_t c : others[k]) share(c);
      for (std::size_t c : added) share(c);
      main.insert(main.end(), others[k].begin(), others[k].end());
      main.insert(main.end(), added.begin(), added.end());
    }
    if (chains && others.size() > 1) context_.joined(others.size() - 1, others.size() - 1);
  }

  // Joins `group` to `main` (the pool's poses sharing `with_main` samples with it): of the
  // poses that share samples with both, the kConnectorTries sharing most with the lesser
  // side are tried. The connector chosen, or none.
  std::vector<std::size_t> joinGroup(const std::vector<std::size_t>& main,
                                     const std::vector<std::size_t>& group,
                                     const std::vector<std::size_t>& with_main) {
    std::map<std::size_t, std::size_t> with_group;  // pose: samples shared with the group
    for (std::size_t c : group)
      for (const auto& [v, n] : sharing(pool_.samples[c], by_sample_)) with_group[v] += n;
    std::vector<std::pair<std::size_t, std::size_t>> candidates;  // (least shared, pose)
    for (const auto& [v, n] : with_group)
      if (!used_[v] && with_main[v] > 0) candidates.push_back({std::min(n, with_main[v]), v});
    std::stable_sort(candidates.begin(), candidates.end(),
                     [](auto& a, auto& b) { return a.first > b.first; });
    candidates.resize(std::min(candidates.size(), kConnectorTries));
    for (const auto& [n, v] : candidates) {
      const auto to_group = registeredAmong(v, group);
      if (!to_group) continue;
      const auto to_main = registeredAmong(v, main);
      if (!to_main) continue;
      choose(v, to_main);
      links_.push_back({v, *to_group});
      return {v};
    }
    return {};
  }

  // Joins `group` to `main` through a chain of up to kChainLinks poses of the pool, each
  // registering to the one before, the first to a view of the group and the last to one
  // of main: the registration's pair test, then its ICP verification once a chain is
  // found. The chain grows from the group's views over the poses foreseen to register
  // (mayRegister), those aimed nearest to main first, within kChainTests pairs and
  // kChainFailures chains that fail ICP. After a failure the poses reached through the
  // failed link are reached again, if they can be, another way. The chain's poses, or none.
  std::vector<std::size_t> chainTo(const std::vector<std::size_t>& main,
                                   const std::vector<std::size_t>& group,
                                   const std::vector<std::size_t>& with_main) {
    std::map<std::size_t, std::size_t> before;  // pose: the one it registers to
    // The distance from a pose's target to the nearest of main's: the poses nearest main
    // are looked at first.
    const auto distance = [&](std::size_t v) {
      double d = std::numeric_limits<double>::infinity();
      for (std::size_t m : main)
        d = std::min(d, (pool_.views[m].target - pool_.views[v].target).norm());
      return d;
    };
    // (distance, links, pose, the pose it registers to: itself in the group)
    using Entry = std::tuple<double, std::size_t, std::size_t, std::size_t>;
    std::priority_queue<Entry, std::vector<Entry>, std::greater<>> queue;
    for (std::size_t c : group) queue.push({distance(c), 0, c, c});
    // Whether the entry still stands: its pose is reached as it was when queued.
    const auto stands = [&](std::size_t u, std::size_t parent) {
      const auto link = before.find(u);
      return parent == u || (link != before.end() && link->second == parent);
    };
    std::size_t tests = 0, failures = 0;
    while (!queue.empty()) {
      const auto [d, links, u, parent] = queue.top();
      queue.pop();
      if (links == kChainLinks || !stands(u, parent)) continue;
      for (const auto& [v, both] : sharing(pool_.samples[u], by_sample_)) {
        if (used_[v] || before.count(v) || !mayRegister(pool_.samples[u], pool_.samples[v], both))
          continue;
        if (++tests > kChainTests) return {};
        if (context_.icpFailed(u, v) || !pairRegisters(u, v)) continue;
        before[v] = u;
        queue.push({distance(v), links + 1, v, u});
        if (with_main[v] == 0) continue;
        const auto to_main = registeredAmong(v, main);
        if (!to_main) continue;
        if (!verified(*to_main, v, before)) {
          if (++failures == kChainFailures) return {};
          forgetBroken(before);
          if (!stands(u, parent)) break;
          continue;
        }
        const std::vector<std::size_t> chain = chainFrom(v, before);  // v first, the group's last
        for (std::size_t k = 0; k + 1 < chain.size(); ++k)
          choose(chain[k], k == 0 ? *to_main : chain[k - 1]);
        links_.push_back({chain[chain.size() - 2], chain.back()});
        return {chain.begin(), chain.end() - 1};
      }
    }
    return {};
  }

  // Whether poses `u` and `v` pass the registration's pair test, each pair tested once.
  bool pairRegisters(std::size_t u, std::size_t v) {
    const auto [found, fresh] = tested_.try_emplace({u, v}, false);
    if (fresh) found->second = overlaps_.passes(pool_.views[u], seen(u), pool_.views[v], seen(v));
    return found->second;
  }

  // The chain `before` (pose: the one it registers to) leads back from `v`: `v` first, the
  // group's view it starts from last.
  static std::vector<std::size_t> chainFrom(std::size_t v,
                                            const std::map<std::size_t, std::size_t>& before) {
    std::vector<std::size_t> chain{v};
    for (auto link = before.find(v); link != before.end(); link = before.find(link->second))
      chain.push_back(link->second);
    return chain;
  }

  // Forgets the poses of `before` whose chain holds a link that failed ICP: they may yet be
  // reached another way.
  void forgetBroken(std::map<std::size_t, std::size_t>& before) const {
    const auto broken = [&](std::size_t v) {
      const std::vector<std::size_t> chain = chainFrom(v, before);
      for (std::size_t k = 0; k + 1 < chain.size(); ++k)
        if (context_.icpFailed(chain[k + 1], chain[k])) return true;
      return false;
    };
    std::vector<std::size_t> lost;  // all found first: erasing cuts the chains walked
    for (const auto& link : before)
      if (broken(link.first)) lost.push_back(link.first);
    for (std::size_t v : lost) before.erase(v);
  }

  // Whether `v` registers to `fixed` by ICP, and so does every link of the chain `before`
  // leads back from it.
  bool verified(std::size_t fixed, std::size_t v,
                const std::map<std::size_t, std::size_t>& before) const {
    if (!context_.icpPasses(fixed, v)) return false;
    const std::vector<std::size_t> chain = chainFrom(v, before);
    for (std::size_t k = 0; k + 1 < chain.size(); ++k)
      if (!context_.icpPasses(chain[k + 1], chain[k])) return false;
    return true;
  }

  // The first of `views` (chosen) that shares samples with pose `v` and with which it
  // passes the registration's pair test.
  std::optional<std::size_t> registeredAmong(std::size_t v, const std::vector<std::size_t>& views) {
    for (std::size_t c : views) {
      if (!intersect(pool_.samples[c], pool_.samples[v])) continue;
      if (overlaps_.passes(pool_.views[c], seen(c), pool_.views[v], seen(v))) return c;
    }
    return std::nullopt;
  }

  // Drops the chosen views, last first, whose samples others measure too and to which no
  // other view registers.
  void dropRedundantLeaves() {
    std::map<std::size_t, int> children;
    for (std::size_t k = 0; k < chosen_.size(); ++k)
      if (parent_[k]) ++children[*parent_[k]];
    for (const auto& [a, b] : links_) {
      ++children[a];
      ++children[b];
    }
    const std::vector<char> kept = keptViews(
        at_, pool_, chosen_, pinned_, samples_.size(),
        [&](std::size_t k) { return children[chosen_[k]] > 0; },
        [&](std::size_t k) {
          if (parent_[k]) --children[*parent_[k]];
        });
    std::vector<std::size_t> chosen;
    std::vector<std::optional<std::size_t>> parent;
    for (std::size_t k = 0; k < chosen_.size(); ++k)
      if (kept[k]) {
        chosen.push_back(chosen_[k]);
        parent.push_back(parent_[k]);
      }
    chosen_ = std::move(chosen);
    parent_ = std::move(parent);
  }

  static double total(const Gain& gain) { return gain.first + gain.second; }

  // Whether measuring sample `i` gains the aim anything: it is not covered yet, and its
  // group still needs samples. A sample nothing asks for gains nothing, nor does one whose
  // group has its need; with every sample asked for, each gains until it is covered.
  bool gains(int i) const {
    const int g = context_.aim.needs.group[i];
    return !covered_[i] && g >= 0 && unmet_[g] > 0;
  }

  // Whether every group of the aim has its need.
  bool met() const {
    return std::all_of(unmet_.begin(), unmet_.end(), [](double u) { return u <= 0; });
  }

  // A pose's gain per its cost: (priority, other).
  std::pair<double, double> rate(std::size_t v) const {
    const double cost = context_.aim.costs[v];
    return {gain_[v].first / cost, gain_[v].second / cost};
  }

  int& part(Gain& gain, int sample) const {
    return samples_[sample].sample.role == Role::Priority ? gain.first : gain.second;
  }

  // Foreseen to register by the `both` samples they share: enough of them, at least half
  // min_overlap of what each measures (mayShare), constraining ICP within ten times the
  // limit (constrains).
  bool mayRegister(const std::vector<int>& a, const std::vector<int>& b, std::size_t both) const {
    return mayShare(a, b, both) && constrains(a, b);
  }
  bool mayShare(const std::vector<int>& a, const std::vector<int>& b, std::size_t both) const {
    const double least = options_.min_overlap / 2;
    return both >= kLeastShared &&
           static_cast<double>(both) >= least * static_cast<double>(a.size()) &&
           static_cast<double>(both) >= least * static_cast<double>(b.size());
  }
  bool constrains(const std::vector<int>& a, const std::vector<int>& b) const {
    std::vector<int> overlap;
    std::set_intersection(a.begin(), a.end(), b.begin(), b.end(), std::back_inserter(overlap));
    return conditionWithin(at_, samples_, overlap, 10 * options_.max_condition);
  }

  const Observation& seen(std::size_t v) const { return context_.seen(v); }

  // Whether partner `p` of pose `v` is foreseen to register to it: by markers, or by the
  // samples they share, whose ICP constraint is judged here, when first asked.
  bool foreseen(Partner& p, std::size_t v) const {
    if (!p.judged) p.judged = constrains(pool_.samples[p.view], pool_.samples[v]) ? 1 : -1;
    return p.judged > 0;
  }

  // Whether `v` has a partner foreseen to register to it; those found not to are forgotten.
  bool hasPartner(std::size_t v) {
    std::vector<Partner>& partners = partners_[v];
    while (!partners.empty() && !foreseen(partners.front(), v)) partners.erase(partners.begin());
    return !partners.empty();
  }

  // The first of `v`'s foreseen partners with which it passes the registration's pair
  // test; none, and they are forgotten, when it passes with none.
  std::optional<std::size_t> registeredPartner(std::size_t v) {
    for (Partner& p : partners_[v]) {
      if (!foreseen(p, v)) continue;
      const std::size_t c = p.view;
      if (overlaps_.passes(pool_.views[c], seen(c), pool_.views[v], seen(v))) return c;
    }
    partners_[v].clear();
    return std::nullopt;
  }

  // Whether the sorted `a` and `b` have an element in common.
  static bool intersect(const std::vector<int>& a, const std::vector<int>& b) {
    for (auto i = a.begin(), j = b.begin(); i != a.end() && j != b.end();) {
      if (*i == *j) return true;
      *i < *j ? ++i : ++j;
    }
    return false;
  }

  // The pose of `queue` passing `allowed` with the largest gain per cost (the first on
  // ties), none gaining.
  template <class Allowed>
  std::optional<std::size_t> best(RateQueue& queue, Allowed allowed) const {
    return queue.top([&](std::size_t v) { return rate(v); },
                     [&](std::size_t v) { return !used_[v] && allowed(v); });
  }

  void choose(std::size_t c, std::optional<std::size_t> partner = std::nullopt) {
    used_[c] = 1;
    chosen_.push_back(c);
    parent_.push_back(partner);
    for (int i : pool_.samples[c]) {
      if (covered_[i]) continue;
      const bool gained = gains(i);
      covered_[i] = 1;
      ++newly_covered_;
      if (!gained) continue;
      for (int v : by_sample_[i]) --part(gain_[v], i);
      const int g = context_.aim.needs.group[i];
      if (--unmet_[g] > 0) continue;
      // The group has its need: its samples left gain nothing any more.
      for (int j : context_.by_group[static_cast<std::size_t>(g)])
        if (!covered_[j])
          for (int v : by_sample_[j]) --part(gain_[v], j);
    }
    context_.covered(run_, newly_covered_);
    // The poses that may register to it: by markers, or by samples, whose ICP constraint is
    // judged when it matters (foreseen).
    std::vector<std::pair<std::size_t, signed char>> partnered;
    if (!markers_seen_.empty())
      for (const auto& [v, both] : sharing(markers_seen_[c], by_marker_))
        if (!used_[v] && both >= static_cast<std::size_t>(options_.min_markers))
          partnered.push_back({v, 1});
    for (const auto& [v, both] : sharing(pool_.samples[c], by_sample_))
      if (!used_[v] && mayShare(pool_.samples[c], pool_.samples[v], both))
        partnered.push_back({v, 0});
    std::stable_sort(partnered.begin(), partnered.end(),
                     [](auto& a, auto& b) { return a.first < b.first; });
    for (std::size_t k = 0; k < partnered.size(); ++k) {
      const auto [v, judged] = partnered[k];
      if (k > 0 && partnered[k - 1].first == v) continue;  // by markers, judged
      if (partners_[v].empty()) linked_.push(v, rate(v));
      partners_[v].push_back({c, judged});
    }
  }

  // The poses sharing any of `seen` (samples or markers, measured by the poses `poses_of`
  // lists), with how many each shares.
  std::vector<std::pair<std::size_t, std::size_t>> sharing(
      const std::vector<int>& seen, const std::vector<std::vector<int>>& poses_of) {
    std::vector<int> touched;
    for (int i : seen)
      for (int v : poses_of[i])
        if (shared_[v]++ == 0) touched.push_back(v);
    std::vector<std::pair<std::size_t, std::size_t>> result;
    for (int v : touched) {
      result.push_back({static_cast<std::size_t>(v), static_cast<std::size_t>(shared_[v])});
      shared_[v] = 0;
    }
    return result;
  }

  const CoverContext& context_;
  const std::size_t run_;
  const Placement& at_;
  const MeasuredViews& pool_;
  const std::vector<PlannedSample>& samples_;
  const RegistrationOptions& options_;
  const Overlaps& overlaps_;
  const std::vector<std::vector<int>>& by_sample_;
  const std::vector<std::vector<int>>& markers_seen_;
  const std::vector<std::vector<int>>& by_marker_;
  std::vector<char> constrained_;  // per pose: something may still register to it
  std::vector<int> shared_;        // per pose: what it shares, while sharing() counts
  std::vector<Gain> gain_;         // per pose: samples it measures that gain the aim (gains)
  std::vector<char> covered_, used_;
  std::size_t newly_covered_ = 0;               // samples covered not done before
  std::vector<double> unmet_;                   // per group of the aim: need left
  std::vector<std::vector<Partner>> partners_;  // per pose: chosen views it may register to
  RateQueue linked_;                            // poses with partners, by rate
  RateQueue seeds_;                             // poses something may register to, by rate
  RateQueue all_;                               // every pose, by rate
  std::size_t pinned_ = 0;
  std::vector<std::size_t> chosen_;
  std::vector<std::optional<std::size_t>> parent_;  // per chosen view: the one it registers to
  std::vector<std::pair<std::size_t, std::size_t>> links_;      // connector, view of a joined group
  std::map<std::pair<std::size_t, std::size_t>, bool> tested_;  // pair tests of chains: passed
};

}  // namespace

std::vector<std::size_t> connectedCover(const Placement& at, const MeasuredViews& pool,
                                        std::size_t pinned,
                                        const std::vector<PlannedSample>& samples,
                                        const SelectionAim& aim, const std::vector<Marker>& markers,
                                        const Progress& progress) {
  const CoverContext context(at, pool, samples, aim, markers, progress);
  // The covers of every creep share, in parallel; kept in kCreeps' order.
  std::vector<std::optional<ConnectedCover>> runs(std::size(kCreeps));
  std::vector<std::pair<std::vector<std::size_t>, double>> covers(std::size(kCreeps));
  tbb::parallel_for(std::size_t{0}, covers.size(),
                    [&](std::size_t k) { covers[k] = runs[k].emplace(context, k).run(pinned); });
  std::optional<std::size_t> best;
  double best_share = -1;
  for (std::size_t k = 0; k < covers.size(); ++k) {
    if (!covers[k].first.empty() && covers[k].second >= best_share + kBetter) {
      best = k;
      best_share = covers[k].second;
    }
  }
  if (!best) return {};
  return runs[*best]->chained();
}

}  // namespace scanplan::detail
