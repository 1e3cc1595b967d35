// The selection of the plan's views from the candidate pool (docs/planning.md), and the
// exact set cover that bounds it.

#include "planning/stages.h"

#include <scanplan/planning/set_cover.h>

#include <algorithm>
#include <map>
#include <numeric>

namespace scanplan::detail {

MeasuredViews candidatePool(const Placement& at, MeasuredViews added,
                            const std::vector<View>& candidates) {
  // The added views' coverage is known; only the other candidates are simulated.
  std::vector<std::vector<int>> measured = measuredBy(at.simulator, candidates, at.points);
  for (std::size_t k = 0; k < candidates.size(); ++k)
    added.add(candidates[k], std::move(measured[k]));
  return added;
}

namespace {

// Greedy set cover over the views of `pool` listed in `among`, starting from the `pinned`
// first views of the pool: each step takes the view whose samples not yet covered are
// most ((priority, other) with `priority_first`), the first on ties. Samples done in an
// earlier placement count as covered.
std::vector<std::size_t> greedyCover(const Placement& at, const MeasuredViews& pool,
                                     const std::vector<std::size_t>& among, std::size_t pinned,
                                     const std::vector<PlannedSample>& samples,
                                     bool priority_first) {
  std::vector<char> covered(samples.size(), 0), used(pool.size(), 0);
  for (std::size_t i = 0; i < covered.size(); ++i) covered[i] = at.isDone(i);
  std::vector<std::size_t> chosen;
  auto choose = [&](std::size_t v) {
    used[v] = 1;
    chosen.push_back(v);
    for (int i : pool.samples[v]) covered[i] = 1;
  };
  for (std::size_t v = 0; v < pinned; ++v) choose(v);
  for (;;) {
    std::size_t best = pool.size();
    std::pair<std::size_t, std::size_t> best_gain{0, 0};
    for (std::size_t v : among) {
      if (used[v]) continue;
      std::pair<std::size_t, std::size_t> gain{0, 0};
      for (int i : pool.samples[v])
        if (!covered[i]) (samples[i].sample.role == Role::Priority ? gain.first : gain.second)++;
      if (!priority_first) gain = {gain.first + gain.second, 0};
      if (gain > best_gain) {
        best_gain = gain;
        best = v;
      }
    }
    if (best == pool.size()) return chosen;
    choose(best);
  }
}

// `chosen` without the views (after the pinned ones, last first) whose samples all other
// chosen views also measure.
std::vector<std::size_t> withoutRedundant(const Placement& at, const MeasuredViews& pool,
                                          std::vector<std::size_t> chosen, std::size_t pinned,
                                          std::size_t samples) {
  std::vector<int> times_measured(samples, 0);
  for (std::size_t v : chosen)
    for (int i : pool.samples[v]) ++times_measured[i];
  for (std::size_t k = chosen.size(); k-- > pinned;) {
    const std::vector<int>& mine = pool.samples[chosen[k]];
    if (std::all_of(mine.begin(), mine.end(),
                    [&](int i) { return times_measured[i] > 1 || at.isDone(i); })) {
      for (int i : mine) --times_measured[i];
      chosen.erase(chosen.begin() + static_cast<std::ptrdiff_t>(k));
    }
  }
  return chosen;
}

}  // namespace

std::vector<std::size_t> selectViews(const Placement& at, const MeasuredViews& pool,
                                     std::size_t pinned,
                                     const std::vector<PlannedSample>& samples) {
  std::vector<std::size_t> all(pool.size());
  std::iota(all.begin(), all.end(), 0);
  const std::vector<std::size_t> chosen = greedyCover(at, pool, all, pinned, samples, false);
  const std::vector<std::size_t> kept = withoutRedundant(at, pool, chosen, pinned, samples.size());
  return greedyCover(at, pool, kept, pinned, samples, true);
}

void applySelection(const MeasuredViews& pool, const std::vector<std::size_t>& selected,
                    Plan& plan) {
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

PlanBound boundOf(const MeasuredViews& pool, const std::vector<PlannedSample>& samples,
                  double time_limit) {
  std::vector<char> required(samples.size());
  for (std::size_t i = 0; i < samples.size(); ++i) required[i] = !samples[i].measured_by.empty();
  const SetCoverResult cover = minimumSetCover(pool.samples, required, time_limit);
  PlanBound bound;
  bound.candidates = pool.size();
  bound.ilp_views = cover.chosen.size();
  bound.lower_bound = cover.lower_bound;
  bound.optimal = cover.optimal;
  bound.seconds = cover.seconds;
  return bound;
}

}  // namespace scanplan::detail
