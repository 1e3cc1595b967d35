// The selection of the plan's views from the candidate pool (docs/planning.md), and the
// exact set cover that bounds it.

#include "planning/rate_queue.h"
#include "planning/stages.h"

#include <scanplan/planning/capability.h>
#include <scanplan/registration/sequencing.h>
#include <scanplan/robot/cycle.h>
#include <scanplan/robot/kinematics.h>
#include <scanplan/solve/set_cover.h>

#include <tbb/parallel_invoke.h>

#include <algorithm>
#include <map>
#include <numeric>

namespace scanplan::detail {

MeasuredViews candidatePool(const Placement& at, MeasuredViews added,
                            const std::vector<View>& candidates, const Progress& progress) {
  // The added views' coverage is known; only the other candidates are simulated, in
  // batches so that progress shows.
  constexpr std::size_t kBatch = 1000;
  const std::string stage = "simulating " + std::to_string(candidates.size()) + " candidate poses";
  const IndexedPoints samples(at.points);
  for (std::size_t first = 0; first < candidates.size(); first += kBatch) {
    report(progress, stage, static_cast<double>(first) / static_cast<double>(candidates.size()));
    const auto batch = std::span<const View>(candidates)
                           .subspan(first, std::min(kBatch, candidates.size() - first));
    std::vector<std::vector<int>> measured = samples.measured(at.simulator, batch);
    for (std::size_t k = 0; k < batch.size(); ++k) added.add(batch[k], std::move(measured[k]));
  }
  report(progress, stage, 1);
  return added;
}

namespace {

// Greedy set cover over the views of `pool` listed in `among`, starting from the `pinned`
// first views of the pool: each step takes the view whose samples not yet covered are
// most, priority samples first ((priority, other), compared in that order), the first on
// ties. Samples done in an earlier placement count as covered.
std::vector<std::size_t> greedyCover(const Placement& at, const MeasuredViews& pool,
                                     const std::vector<std::size_t>& among, std::size_t pinned,
                                     const std::vector<PlannedSample>& samples) {
  std::vector<char> covered(samples.size(), 0), used(pool.size(), 0);
  for (std::size_t i = 0; i < covered.size(); ++i) covered[i] = at.isDone(i);
  std::vector<std::size_t> chosen;
  auto choose = [&](std::size_t v) {
    used[v] = 1;
    chosen.push_back(v);
    for (int i : pool.samples[v]) covered[i] = 1;
  };
  for (std::size_t v = 0; v < pinned; ++v) choose(v);
  // (priority, other) samples not covered, of the view at place k of `among`
  const auto gain_of = [&](std::size_t k) {
    RateQueue::Rate gain{0, 0};
    for (int i : pool.samples[among[k]])
      if (!covered[i]) (samples[i].sample.role == Role::Priority ? gain.first : gain.second)++;
    return gain;
  };
  const auto unused = [&](std::size_t k) { return !used[among[k]]; };
  // Ties go to the earliest place in `among`, as a scan in its order takes them.
  RateQueue queue;
  for (std::size_t k = 0; k < among.size(); ++k)
    if (unused(k)) queue.push(k, gain_of(k));
  while (const std::optional<std::size_t> k = queue.top(gain_of, unused)) choose(among[*k]);
  return chosen;
}

// `chosen` without the views (last first, the `pinned` first ones kept) whose samples all
// other chosen views also measure.
std::vector<std::size_t> withoutRedundant(const Placement& at, const MeasuredViews& pool,
                                          const std::vector<std::size_t>& chosen,
                                          std::size_t pinned, std::size_t samples) {
  const std::vector<char> kept = keptViews(at, pool, chosen, pinned, samples);
  std::vector<std::size_t> result;
  for (std::size_t k = 0; k < chosen.size(); ++k)
    if (kept[k]) result.push_back(chosen[k]);
  return result;
}

// The samples the exact selection must cover: those some pool view measures and neither a
// pinned view nor an earlier placement does.
std::vector<char> requiredSamples(const Placement& at, const MeasuredViews& pool,
                                  std::size_t pinned, std::size_t samples) {
  std::vector<char> required(samples, 0);
  for (const std::vector<int>& measured : pool.samples)
    for (int i : measured) required[i] = !at.isDone(i);
  for (std::size_t v = 0; v < pinned; ++v)
    for (int i : pool.samples[v]) required[i] = 0;
  return required;
}

// What the exact selection may spend: planner.selection_nodes decides the plan;
// planner.selection_seconds caps it for safety.
SolveLimits selectionLimits(const Placement& at) {
  return {at.settings().selection_nodes, at.settings().selection_seconds};
}

// The pool's views after the pinned ones, as sets of samples.
std::vector<std::vector<int>> unpinnedSets(const MeasuredViews& pool, std::size_t pinned) {
  return {pool.samples.begin() + static_cast<long>(pinned), pool.samples.end()};
}

// The exact part of the selection: the fewest views after the `pinned` ones that measure
// every required sample, CBC starting from the greedy cover `greedy`. Pool indices, the
// pinned ones first.
std::pair<std::vector<std::size_t>, SetCoverResult> exactCover(
    const Placement& at, const MeasuredViews& pool, std::size_t pinned,
    const std::vector<std::size_t>& greedy, std::size_t samples, const Progress& progress) {
  std::vector<int> start;
  for (std::size_t k = pinned; k < greedy.size(); ++k)
    start.push_back(static_cast<int>(greedy[k] - pinned));
  const SetCoverResult cover = minimumSetCover(
      unpinnedSets(pool, pinned), requiredSamples(at, pool, pinned, samples), selectionLimits(at),
      start, [&](double share) { report(progress, "selection: exact cover", share); });
  std::vector<std::size_t> chosen(pinned);
  std::iota(chosen.begin(), chosen.end(), 0);
  for (int c : cover.chosen) chosen.push_back(static_cast<std::size_t>(c) + pinned);
  return {chosen, cover};
}

// The groups of the partial cover: 0 for the priority samples, then one per task type for
// the others; under planner.aim characteristics, then one per face the characteristics are
// judged on, which holds the gdt task's samples on it: their own faces (`own`) and their
// datum features'.
struct CoverageGroups {
  std::vector<int> own, faces;  // faces: theirs and their datums', sorted
  bool by_characteristics = false;

  explicit CoverageGroups(const Placement& at)
      : by_characteristics(at.settings().aim == Aim::Characteristics) {
    if (!by_characteristics) return;
    own = verifiedFaces(at.part.gdt);
    faces = judgedFaces(at.part.gdt);
  }
  std::size_t size() const { return 1 + kTaskTypes.size() + faces.size(); }
  // A sample's group, or -1: a gdt sample the characteristics do not ask for.
  int of(const Sample& s) const {
    if (by_characteristics && s.task == TaskType::Gdt) {
      const auto it = std::lower_bound(faces.begin(), faces.end(), s.face);
      if (it == faces.end() || *it != s.face) return -1;
      return static_cast<int>(1 + kTaskTypes.size()) + static_cast<int>(it - faces.begin());
    }
    if (s.role == Role::Priority) return 0;
    return 1 + static_cast<int>(std::find(kTaskTypes.begin(), kTaskTypes.end(), s.task) -
                                kTaskTypes.begin());
  }
  // The share of its samples a group needs measured: a characteristic's face as capability
  // asks of its area, a datum feature's as its frame needs.
  double share(std::size_t g, const CoverageTargets& coverage) const {
    if (g == 0) return coverage.priority;
    if (g <= kTaskTypes.size()) return coverage.of(Role::Normal, kTaskTypes[g - 1]);
    const int face = faces[g - 1 - kTaskTypes.size()];
    return std::binary_search(own.begin(), own.end(), face) ? kCoveredEnough : kDatumsCoveredEnough;
  }
};

// How many views of `order` (pool indices, by marginal coverage) meet `needs`.
std::size_t prefixMeeting(const MeasuredViews& pool, const std::vector<std::size_t>& order,
                          const CoverageNeed& needs) {
  std::vector<double> unmet = needs.need;
  std::vector<char> covered(needs.group.size(), 0);
  auto met = [&] {
    return std::all_of(unmet.begin(), unmet.end(), [](double u) { return u <= 0; });
  };
  for (std::size_t k = 0; k < order.size(); ++k) {
    if (met()) return k;
    for (int i : pool.samples[order[k]])
      if (needs.group[i] >= 0 && !covered[i]) {
        covered[i] = 1;
        --unmet[needs.group[i]];
      }
  }
  return order.size();
}

// What each pose of the pool costs under planner.objective cycle_time
// (docs/planning.md, "Objective"), seconds: its time standing (viewSeconds) and half the
// generic moves to its two nearest views of the greedy cover `greedy`, the share of the
// motion a view takes in a tour through views spaced as the greedy cover's.
std::vector<double> cycleCosts(const Placement& at, const MeasuredViews& pool,
                               const std::vector<std::size_t>& greedy) {
  std::vector<View> near;
  for (std::size_t v : greedy) near.push_back(pool.views[v]);
  const CycleSettings& cycle = at.spec.spec.cycle;
  const double standing = viewSeconds(at.scanner(), cycle);
  std::vector<double> costs;
  constexpr std::size_t kRows = 4096;  // poses whose moves are found at once
  for (std::size_t first = 0; first < pool.size(); first += kRows) {
    const auto rows =
        std::span<const View>(pool.views).subspan(first, std::min(kRows, pool.size() - first));
    const Eigen::MatrixXd mm = directCosts(at.simulator, rows, near);
    for (Eigen::Index i = 0; i < mm.rows(); ++i) {
      // The two shortest moves, the pose's own view aside: a trapezoid's time rises with
      // its length, so they are the two quickest.
      double nearest[2] = {-1, -1};
      for (std::size_t j = 0; j < greedy.size(); ++j) {
        const double d = mm(i, static_cast<Eigen::Index>(j));
        if (greedy[j] == first + static_cast<std::size_t>(i)) continue;
        if (nearest[0] < 0 || d < nearest[0]) {
          nearest[1] = nearest[0];
          nearest[0] = d;
        } else if (nearest[1] < 0 || d < nearest[1]) {
          nearest[1] = d;
        }
      }
      double moves = 0;
      for (const double d : nearest)
        if (d >= 0) moves += trapezoidSeconds(d, cycle.speed, cycle.acceleration);
      costs.push_back(standing + moves / 2);
    }
  }
  return costs;
}

// The selection to coverage targets below 1, or by cycle time: the cheapest views after
// the `pinned` ones that meet every group's share (minimumPartialCover), CBC starting from
// the first `prefix` views of the greedy cover `greedy`, which meet them, when they are
// the better start. Pool indices, the pinned ones first; the cover's result.
std::pair<std::vector<std::size_t>, SetCoverResult> partialCover(
    const Placement& at, const MeasuredViews& pool, std::size_t pinned,
    const std::vector<PlannedSample>& samples, const SelectionAim& aim,
    const std::vector<std::size_t>& greedy, std::size_t prefix) {
  std::vector<int> start;
  for (std::size_t k = pinned; k < prefix; ++k)
    start.push_back(static_cast<int>(greedy[k] - pinned));
  const std::vector<double> costs(aim.costs.begin() + static_cast<long>(pinned), aim.costs.end());
  const SetCoverResult cover =
      minimumPartialCover(unpinnedSets(pool, pinned), costs, aim.needs.group, aim.needs.need,
                          selectionLimits(at), start);
  std::vector<std::size_t> chosen(pinned);
  std::iota(chosen.begin(), chosen.end(), 0);
  for (int c : cover.chosen) chosen.push_back(static_cast<std::size_t>(c) + pinned);
  return {greedyCover(at, pool, chosen, pinned, samples), cover};
}

}  // namespace

CoverageNeed coverageNeed(const Placement& at, const MeasuredViews& pool, std::size_t pinned,
                          const std::vector<PlannedSample>& samples) {
  const CoverageGroups groups(at);
  std::vector<char> coverable(samples.size(), 0), measured(samples.size(), 0);
  for (std::size_t v = 0; v < pool.size(); ++v)
    for (int i : pool.samples[v]) {
      coverable[i] = 1;
      measured[i] = measured[i] || v < pinned;
    }
  CoverageNeed result{std::vector<int>(samples.size(), -1), std::vector<double>(groups.size(), 0)};
  std::vector<double> total(groups.size(), 0), already(groups.size(), 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const int g = groups.of(samples[i].sample);
    if (g < 0 || (!coverable[i] && !at.isDone(i))) continue;
    ++total[g];
    if (measured[i] || at.isDone(i))
      ++already[g];
    else
      result.group[i] = g;
  }
  for (std::size_t g = 0; g < groups.size(); ++g)
    result.need[g] = std::max(
        0.0, std::ceil(groups.share(g, at.settings().coverage) * total[g] - 1e-9) - already[g]);
  return result;
}

std::vector<char> keptViews(const Placement& at, const MeasuredViews& pool,
                            const std::vector<std::size_t>& chosen, std::size_t pinned,
                            std::size_t samples, const std::function<bool(std::size_t)>& needed,
                            const std::function<void(std::size_t)>& dropped) {
  std::vector<int> times_measured(samples, 0);
  for (std::size_t v : chosen)
    for (int i : pool.samples[v]) ++times_measured[i];
  std::vector<char> kept(chosen.size(), 1);
  for (std::size_t k = chosen.size(); k-- > pinned;) {
    const std::vector<int>& mine = pool.samples[chosen[k]];
    if ((needed && needed(k)) || !std::all_of(mine.begin(), mine.end(), [&](int i) {
          return times_measured[i] > 1 || at.isDone(i);
        }))
      continue;
    kept[k] = 0;
    for (int i : mine) --times_measured[i];
    if (dropped) dropped(k);
  }
  return kept;
}

namespace {

// The bound on the views of a selection over `pool` that meets `aim`: the pinned views and
// the LP bound of the set cover of the required samples, or of the partial cover of the
// targets.
double viewsBound(const Placement& at, const MeasuredViews& pool, std::size_t pinned,
                  std::size_t samples, const SelectionAim& aim) {
  const std::vector<std::vector<int>> sets = unpinnedSets(pool, pinned);
  return static_cast<double>(pinned) +
         (at.settings().everySample()
              ? setCoverLowerBound(sets, requiredSamples(at, pool, pinned, samples))
              : partialCoverLowerBound(sets, aim.needs.group, aim.needs.need));
}

// What a pose that registers to nothing costs the selection under registration by
// reference points, against 1 for one that sees enough of the markers: it stands for a view
// and for the markers that must be placed for it.
constexpr double kUnframedCost = 2;

}  // namespace

Selection selectViews(const Placement& at, const MeasuredViews& pool, std::size_t pinned,
                      const std::vector<PlannedSample>& samples,
                      const std::optional<std::vector<Marker>>& registering,
                      const std::vector<char>& framed, const Progress& progress) {
  std::vector<std::size_t> all(pool.size());
  std::iota(all.begin(), all.end(), 0);
  const std::vector<std::size_t> greedy = greedyCover(at, pool, all, pinned, samples);
  const bool full = at.settings().everySample();
  const bool by_time = at.settings().objective == Objective::CycleTime;
  const bool weighted = by_time || !framed.empty();  // poses cost other than one each
  SelectionAim aim{coverageNeed(at, pool, pinned, samples),
                   by_time ? cycleCosts(at, pool, greedy) : std::vector<double>(pool.size(), 1.0)};
  for (std::size_t v = 0; v < framed.size(); ++v)
    if (!framed[v]) aim.costs[v] *= kUnframedCost;
  Selection selection;
  PlanBound& bound = selection.bound;
  // Against the greedy cover's shortest prefix meeting the targets; the bound on views,
  // whatever the cost.
  bound.greedy_views = full ? greedy.size() : prefixMeeting(pool, greedy, aim.needs);
  if (registering && framed.empty()) {
    // The cover and the bound are independent: made side by side.
    tbb::parallel_invoke(
        [&] {
          selection.views = connectedCover(at, pool, pinned, samples, aim, *registering, progress);
        },
        [&] { bound.lower_bound = viewsBound(at, pool, pinned, samples.size(), aim); });
  }
  if (selection.views.empty() && full && !weighted) {
    const auto [exact, cover] = exactCover(at, pool, pinned, greedy, samples.size(), progress);
    const std::vector<std::size_t> chosen =
        withoutRedundant(at, pool, exact, pinned, samples.size());
    selection.views = greedyCover(at, pool, chosen, pinned, samples);  // by marginal coverage
    bound.lower_bound = static_cast<double>(pinned) + cover.lower_bound;
    bound.time_capped = cover.time_capped;
  } else if (selection.views.empty()) {
    const auto [chosen, cover] =
        partialCover(at, pool, pinned, samples, aim, greedy, bound.greedy_views);
    selection.views = chosen;
    bound.lower_bound = weighted ? viewsBound(at, pool, pinned, samples.size(), aim)
                                 : static_cast<double>(pinned) + cover.lower_bound;
    bound.time_capped = cover.time_capped;
  }
  bound.views = selection.views.size();
  bound.pool = pool.size();
  bound.proven_optimal = bound.lower_bound >= static_cast<double>(bound.views);
  return selection;
}

void applySelection(const MeasuredViews& pool, const std::vector<std::size_t>& selected,
                    Plan& plan) {
  std::map<int, int> id_of;  // pool index + 1 -> id in the plan
  for (std::size_t k = 0; k < selected.size(); ++k)
    id_of[static_cast<int>(selected[k]) + 1] = static_cast<int>(k) + 1;
  for (Sweep& sweep : plan.sweeps) {
    std::vector<int> kept;
    for (int v : sweep.views)
      if (id_of.count(v)) kept.push_back(id_of[v]);
    sweep.views = kept;
  }
  for (PlannedSample& s : plan.samples) s.measured_by.clear();
  for (std::size_t k = 0; k < selected.size(); ++k) {
    View view = pool.views[selected[k]];
    const std::vector<int>& measured = pool.samples[selected[k]];
    if (view.task.empty()) {  // a candidate: the task of most of the samples it measures
      std::map<TaskType, int> tasks;
      for (int i : measured) ++tasks[plan.samples[i].sample.task];
      view.task =
          std::string(toString(std::max_element(tasks.begin(), tasks.end(), [](auto& a, auto& b) {
                                 return a.second < b.second;
                               })->first));
    }
    view.id = static_cast<int>(k) + 1;
    plan.views.push_back(view);
    for (int i : measured) plan.samples[i].measured_by.push_back(view.id);
  }
}

}  // namespace scanplan::detail
