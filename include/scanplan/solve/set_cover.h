#pragma once
// Exact minimum set cover as an integer program, solved with COIN-OR CBC: the optimality
// check of the view planner.

#include <functional>
#include <vector>

namespace scanplan {

// What a solve may spend. The nodes decide the result, which is then the same on every
// machine; the seconds are a cap for safety: a solve they stop first depends on the
// machine's speed and load, and says so (SetCoverResult::time_capped).
struct SolveLimits {
  int nodes = 1000000;  // CBC's branch-and-bound nodes
  double seconds = 3600;
};

struct SetCoverResult {
  std::vector<int> chosen;   // indices of the sets in the best cover found
  bool optimal = false;      // proven minimal
  double lower_bound = 0;    // a bound on the minimum (== chosen.size() if optimal)
  double lp_bound = 0;       // the LP relaxation's optimum, rounded up: a lower bound too
  bool time_capped = false;  // SolveLimits::seconds stopped the search before its nodes
  double seconds = 0;
};

// Called with the share of its node limit a solve has searched, in [0, 1].
using SetCoverProgress = std::function<void(double)>;

// The core CBC searches (minimumSetCover): the sets of LP reduced cost at most
// kCoreReducedCost, and at least the kCoreSets of least reduced cost.
constexpr double kCoreReducedCost = 0.1;
constexpr int kCoreSets = 1000;

// The fewest of `sets` (each a list of element indices in [0, elements)) that together
// cover every element `required` marks; elements no set contains are ignored.
// min sum x_s  s.t.  sum_{s contains e} x_s >= 1 for each required e,  x_s in {0, 1}.
// The instance is reduced by dominance first (dominated sets and elements dropped), and
// its LP relaxation solved (at most 100,000 simplex iterations). `start`, when given, is a
// cover to start from (indices of sets), unless the LP optimum rounds to a smaller one; the
// result is never larger than it. CBC, with its cuts and heuristics, then searches the
// core of the instance, the sets of least LP reduced cost (kCoreReducedCost, kCoreSets;
// and those of the start and the LP's support), within `limits`: the whole of a small
// instance. A cover using a set
// outside the core costs at least the LP optimum plus that set's reduced cost, which
// bounds the whole instance with the core's bound. `progress`, when given, is called
// with the share of the nodes searched.
SetCoverResult minimumSetCover(const std::vector<std::vector<int>>& sets,
                               const std::vector<char>& required, const SolveLimits& limits = {},
                               const std::vector<int>& start = {},
                               const SetCoverProgress& progress = {});

// The optimum of minimumSetCover's LP relaxation (after the same reduction), rounded up: a
// lower bound on its minimum; 0 when the LP is not solved within 100,000 simplex
// iterations in all. Solved by pricing (over a few sets first, adding those of negative
// reduced cost until none is left), which reaches the same optimum over far fewer sets.
double setCoverLowerBound(const std::vector<std::vector<int>>& sets,
                          const std::vector<char>& required);

// The fewest of `sets` such that each element e is in at least demand[e] of them (fewer
// when fewer sets hold it), as minimumSetCover but without the reduction: a greedy start,
// the LP relaxation's bound, CBC within `limits`.
SetCoverResult minimumMulticover(const std::vector<std::vector<int>>& sets,
                                 const std::vector<int>& demand, const SolveLimits& limits = {});

// The cheapest of `sets` such that, in each group g, at least need[g] of the elements
// group[e] = g assigns to it are covered (group[e] < 0: an element that does not count;
// a need beyond the elements some set holds is capped there). costs[s] is each set's
// cost (all 1: the fewest sets).
//   min sum c_s x_s  s.t.  y_e <= sum_{s contains e} x_s,  sum_{e in g} y_e >= need_g,
//   x_s in {0, 1},  0 <= y_e <= 1.
// Sets that another costing no more includes are dropped first (the least cost is
// unchanged). A greedy start (the most unmet need per cost, or `start` when it meets every
// need and costs less), the LP relaxation's bound (rounded up with unit costs), then CBC
// within `limits`; the result never costs more than the start.
SetCoverResult minimumPartialCover(const std::vector<std::vector<int>>& sets,
                                   const std::vector<double>& costs, const std::vector<int>& group,
                                   const std::vector<double>& need, const SolveLimits& limits = {},
                                   const std::vector<int>& start = {});

// The optimum of minimumPartialCover's LP relaxation with unit costs, rounded up: a lower
// bound on the fewest sets meeting the needs; 0 when the LP is not solved within 100,000
// simplex iterations in all (a count, so that the bound is the same on every machine).
// Solved by pricing, as setCoverLowerBound.
double partialCoverLowerBound(const std::vector<std::vector<int>>& sets,
                              const std::vector<int>& group, const std::vector<double>& need);

}  // namespace scanplan
