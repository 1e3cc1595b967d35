#pragma once
// Exact minimum set cover as an integer program, solved with COIN-OR CBC: the optimality
// check of the view planner.

#include <functional>
#include <vector>

namespace scanplan {

struct SetCoverResult {
  std::vector<int> chosen;  // indices of the sets in the best cover found
  bool optimal = false;     // CBC proved it minimal within the time limit
  double lower_bound = 0;   // CBC's best bound on the minimum (== chosen.size() if optimal)
  double lp_bound = 0;      // the LP relaxation's optimum, rounded up: a lower bound too
  double seconds = 0;
};

// Called with the share of its time limit a solve has used, in [0, 1).
using SetCoverProgress = std::function<void(double)>;

// The fewest of `sets` (each a list of element indices in [0, elements)) that together
// cover every element `required` marks; elements no set contains are ignored.
// min sum x_s  s.t.  sum_{s contains e} x_s >= 1 for each required e,  x_s in {0, 1}.
// The instance is reduced by dominance first (dominated sets and elements dropped).
// `start`, when given, is a cover CBC starts from (indices of sets), unless the LP optimum
// rounds to a smaller one; the result is never larger than it, and is a cover even when the
// time runs out before the LP is solved. CBC runs its cuts and
// heuristics; the search stops after `max_nodes` branch-and-bound nodes (the LP after
// 100,000 simplex iterations), so that the result is the same on every run, or at
// `time_limit_seconds`, a cap that makes it depend on the machine when it is reached.
// `progress`, when given, is called every tenth of a second with the share of the time
// limit gone by (from another thread).
SetCoverResult minimumSetCover(const std::vector<std::vector<int>>& sets,
                               const std::vector<char>& required, double time_limit_seconds,
                               const std::vector<int>& start = {}, int max_nodes = 1000000,
                               const SetCoverProgress& progress = {});

// The optimum of minimumSetCover's LP relaxation (after the same reduction), rounded up: a
// lower bound on its minimum; 0 when the LP is not solved within `time_limit_seconds`.
double setCoverLowerBound(const std::vector<std::vector<int>>& sets,
                          const std::vector<char>& required, double time_limit_seconds);

// The fewest of `sets` such that each element e is in at least demand[e] of them (fewer
// when fewer sets hold it), as minimumSetCover but without the reduction: a greedy start,
// the LP relaxation's bound, CBC within `time_limit_seconds`.
SetCoverResult minimumMulticover(const std::vector<std::vector<int>>& sets,
                                 const std::vector<int>& demand, double time_limit_seconds);

// The cheapest of `sets` such that, in each group g, at least need[g] of the elements
// group[e] = g assigns to it are covered (group[e] < 0: an element that does not count;
// a need beyond the elements some set holds is capped there). costs[s] is each set's
// cost (all 1: the fewest sets).
//   min sum c_s x_s  s.t.  y_e <= sum_{s contains e} x_s,  sum_{e in g} y_e >= need_g,
//   x_s in {0, 1},  0 <= y_e <= 1.
// A greedy start (the most unmet need per cost, or `start` when it meets every need and
// costs less), the LP relaxation's bound (rounded up with unit costs), then CBC for at most
// `max_nodes` nodes or `time_limit_seconds`; the result never costs more than the start.
SetCoverResult minimumPartialCover(const std::vector<std::vector<int>>& sets,
                                   const std::vector<double>& costs, const std::vector<int>& group,
                                   const std::vector<double>& need, double time_limit_seconds,
                                   int max_nodes = 1000000, const std::vector<int>& start = {});

// The optimum of minimumPartialCover's LP relaxation with unit costs, rounded up: a lower
// bound on the fewest sets meeting the needs; 0 when the LP is not solved within 100,000
// simplex iterations (a count, so that the bound is the same on every machine).
double partialCoverLowerBound(const std::vector<std::vector<int>>& sets,
                              const std::vector<int>& group, const std::vector<double>& need);

}  // namespace scanplan
