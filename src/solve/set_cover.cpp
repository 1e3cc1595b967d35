#include <scanplan/solve/set_cover.h>

#include <CbcEventHandler.hpp>
#include <CbcModel.hpp>
#include <CbcSolver.hpp>
#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>

#include <fcntl.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <condition_variable>
#include <cstdio>
#include <limits>
#include <memory>
#include <mutex>
#include <numeric>
#include <optional>
#include <string>
#include <thread>

namespace scanplan {

namespace {

using Clock = std::chrono::steady_clock;

constexpr int kLpIterations = 100000;     // simplex iterations of an LP relaxation
constexpr std::size_t kPricedSets = 200;  // sets added to an LP at each pricing

double secondsSince(Clock::time_point began) {
  return std::chrono::duration<double>(Clock::now() - began).count();
}

// CLP's sprint, its choice for the LPs of partial covers (far wider than tall), prints
// to the standard output whatever the log level (Clp 1.17). While such a solve runs, the
// standard output goes to /dev/null: the first solve to start sends it there, the last to
// end brings it back. The standard error (progress, errors) is untouched.
class StdoutSilenced {
 public:
  StdoutSilenced() {
    const std::lock_guard lock(mutex());
    if (depth()++ > 0) return;
    std::fflush(stdout);
    saved() = dup(STDOUT_FILENO);
    if (const int null = open("/dev/null", O_WRONLY); null >= 0) {
      dup2(null, STDOUT_FILENO);
      close(null);
    }
  }
  ~StdoutSilenced() {
    const std::lock_guard lock(mutex());
    if (--depth() > 0) return;
    std::fflush(stdout);
    if (saved() >= 0) {
      dup2(saved(), STDOUT_FILENO);
      close(saved());
    }
  }
  StdoutSilenced(const StdoutSilenced&) = delete;
  StdoutSilenced& operator=(const StdoutSilenced&) = delete;

 private:
  static std::mutex& mutex() {
    static std::mutex m;
    return m;
  }
  static int& depth() {
    static int d = 0;
    return d;
  }
  static int& saved() {
    static int fd = -1;
    return fd;
  }
};

// A set cover instance reduced by dominance (Beasley's reductions): a set whose required
// elements another set also holds is dropped, and so is an element whose sets include all
// sets of another element (covering that one covers it). The minimum is unchanged.
struct Reduced {
  std::vector<std::vector<int>> columns{};  // per kept set: its rows
  std::vector<int> set_of{};                // per kept set: its index among the given sets
  std::vector<int> kept_as{};  // per given set: a kept set holding all it covers, or -1
  int rows = 0;
};

bool includes(const std::vector<int>& big, const std::vector<int>& small) {
  return std::includes(big.begin(), big.end(), small.begin(), small.end());
}

// The sets as sorted lists of rows, one row per required element some set holds; the
// element of each row into `elements`.
std::vector<std::vector<int>> requiredRows(const std::vector<std::vector<int>>& sets,
                                           const std::vector<char>& required, int& rows,
                                           std::vector<int>* elements = nullptr) {
  std::vector<int> row_of(required.size(), -1);
  rows = 0;
  for (const auto& set : sets)
    for (int e : set)
      if (required[e] && row_of[e] < 0) {
        row_of[e] = rows++;
        if (elements) elements->push_back(e);
      }
  std::vector<std::vector<int>> columns(sets.size());
  for (std::size_t s = 0; s < sets.size(); ++s) {
    for (int e : sets[s])
      if (row_of[e] >= 0) columns[s].push_back(row_of[e]);
    std::sort(columns[s].begin(), columns[s].end());
    columns[s].erase(std::unique(columns[s].begin(), columns[s].end()), columns[s].end());
  }
  return columns;
}

// Sets by size, largest first (the first on ties); each kept unless a kept set includes it.
// With `costs`, by cost first, cheapest first: a set is dropped only for one that includes
// it and costs no more, which leaves the cheapest cover's cost unchanged.
void dropDominatedSets(const std::vector<std::vector<int>>& columns, int rows, Reduced& out,
                       const std::vector<double>* costs = nullptr) {
  std::vector<int> order(columns.size());
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) {
    if (costs && (*costs)[a] != (*costs)[b]) return (*costs)[a] < (*costs)[b];
    return columns[a].size() > columns[b].size();
  });
  out.kept_as.assign(columns.size(), -1);
  std::vector<std::vector<int>> kept_with_row(rows);  // kept sets (reduced index) per row
  for (int s : order) {
    if (columns[s].empty()) continue;
    int rarest = columns[s].front();
    for (int r : columns[s])
      if (kept_with_row[r].size() < kept_with_row[rarest].size()) rarest = r;
    for (int k : kept_with_row[rarest])
      if (includes(out.columns[k], columns[s])) {
        out.kept_as[s] = k;
        break;
      }
    if (out.kept_as[s] >= 0) continue;
    out.kept_as[s] = static_cast<int>(out.columns.size());
    for (int r : columns[s]) kept_with_row[r].push_back(out.kept_as[s]);
    out.columns.push_back(columns[s]);
    out.set_of.push_back(s);
  }
}

// Rows by number of sets, fewest first; a row is dropped when the sets of a kept row are
// all among its own. Renumbers the remaining rows.
void dropDominatedRows(Reduced& out, int rows) {
  std::vector<std::vector<int>> sets_of(rows);  // sorted, as sets are visited in order
  for (std::size_t c = 0; c < out.columns.size(); ++c)
    for (int r : out.columns[c]) sets_of[r].push_back(static_cast<int>(c));
  std::vector<int> order(rows);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return sets_of[a].size() < sets_of[b].size(); });
  std::vector<std::vector<int>> kept_by_first(out.columns.size());  // kept rows by first set
  std::vector<int> new_row(rows, -1);
  out.rows = 0;
  for (int r : order) {
    bool dominated = false;
    for (int c : sets_of[r]) {
      for (int k : kept_by_first[c])
        if ((dominated = includes(sets_of[r], sets_of[k]))) break;
      if (dominated) break;
    }
    if (dominated) continue;
    new_row[r] = out.rows++;
    kept_by_first[sets_of[r].front()].push_back(r);
  }
  for (std::vector<int>& column : out.columns) {
    std::vector<int> kept;
    for (int r : column)
      if (new_row[r] >= 0) kept.push_back(new_row[r]);
    std::sort(kept.begin(), kept.end());
    column = kept;
  }
}

Reduced reduce(const std::vector<std::vector<int>>& sets, const std::vector<char>& required) {
  int rows = 0;
  const std::vector<std::vector<int>> columns = requiredRows(sets, required, rows);
  Reduced out;
  dropDominatedSets(columns, rows, out);
  dropDominatedRows(out, rows);
  return out;
}

// A cover rounded from the LP optimum `x`: sets by decreasing x take the rows they add,
// each row then covered by the set of largest x that holds it, and the sets whose rows
// all others cover dropped (smallest x first).
std::vector<int> roundedCover(const Reduced& reduced, const double* x) {
  const int columns = static_cast<int>(reduced.columns.size());
  std::vector<int> order(columns);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](int a, int b) { return x[a] > x[b]; });
  std::vector<int> times(reduced.rows, 0), chosen;
  for (int c : order) {
    const auto& rows = reduced.columns[c];
    if (std::any_of(rows.begin(), rows.end(), [&](int r) { return times[r] == 0; })) {
      chosen.push_back(c);
      for (int r : rows) ++times[r];
    }
  }
  for (std::size_t k = chosen.size(); k-- > 0;) {
    const auto& rows = reduced.columns[chosen[k]];
    if (std::all_of(rows.begin(), rows.end(), [&](int r) { return times[r] > 1; })) {
      for (int r : rows) --times[r];
      chosen.erase(chosen.begin() + static_cast<std::ptrdiff_t>(k));
    }
  }
  return chosen;
}

// The LP relaxation of the reduced instance: min sum x, every row covered (`demand[r]`
// times, once without), 0 <= x <= 1.
void loadRelaxation(const Reduced& reduced, OsiClpSolverInterface& solver,
                    const std::vector<double>& demand = {}) {
  std::vector<int> indices, starts, lengths;  // column-ordered: one column per kept set
  for (const auto& column : reduced.columns) {
    starts.push_back(static_cast<int>(indices.size()));
    indices.insert(indices.end(), column.begin(), column.end());
    lengths.push_back(static_cast<int>(column.size()));
  }
  starts.push_back(static_cast<int>(indices.size()));  // past the last: never empty
  const int columns = static_cast<int>(reduced.columns.size());
  const std::vector<double> ones(indices.size(), 1.0);
  const CoinPackedMatrix matrix(true, reduced.rows, columns,
                                static_cast<CoinBigIndex>(indices.size()), ones.data(),
                                indices.data(), starts.data(), lengths.data());
  const std::vector<double> column_lower(columns, 0.0), column_upper(columns, 1.0),
      objective(columns, 1.0), row_upper(reduced.rows, std::numeric_limits<double>::infinity());
  const std::vector<double> row_lower =
      demand.empty() ? std::vector<double>(reduced.rows, 1.0) : demand;
  solver.loadProblem(matrix, column_lower.data(), column_upper.data(), objective.data(),
                     row_lower.data(), row_upper.data());
  solver.messageHandler()->setLogLevel(0);
  solver.getModelPtr()->setLogLevel(0);
}

// The share of the node limit searched, as each node CBC ends: the nodes of the search
// itself, not of the searches its heuristics run on sub-problems.
class NodesSearched : public CbcEventHandler {
 public:
  NodesSearched(std::shared_ptr<std::atomic<double>> share, int nodes)
      : share_(std::move(share)), nodes_(nodes) {}
  CbcAction event(CbcEvent which) override {
    if (which == node && model_ && !model_->parentModel() && nodes_ > 0)
      share_->store(std::min(1.0, model_->getNodeCount() / static_cast<double>(nodes_)));
    return noAction;
  }
  CbcEventHandler* clone() const override { return new NodesSearched(*this); }

 private:
  std::shared_ptr<std::atomic<double>> share_;
  int nodes_;
};

// Shows `share` every tenth of a second while it lives, from another thread, and once more
// at its end: CBC raises no event while it works at the root (its cuts and heuristics),
// which can take seconds.
class SharesShown {
 public:
  SharesShown(const SetCoverProgress& shown, std::shared_ptr<const std::atomic<double>> share)
      : shown_(shown), share_(std::move(share)) {
    if (!shown_) return;
    ticker_ = std::jthread([this](std::stop_token stop) {
      std::unique_lock lock(mutex_);
      while (!stop.stop_requested()) {
        wake_.wait_for(lock, stop, std::chrono::milliseconds(100), [] { return false; });
        if (!stop.stop_requested()) shown_(share_->load());
      }
    });
  }
  ~SharesShown() {
    if (!shown_) return;
    ticker_.request_stop();
    ticker_.join();
    shown_(share_->load());
  }
  SharesShown(const SharesShown&) = delete;
  SharesShown& operator=(const SharesShown&) = delete;

 private:
  const SetCoverProgress& shown_;
  std::shared_ptr<const std::atomic<double>> share_;
  std::mutex mutex_;
  std::condition_variable_any wake_;
  std::jthread ticker_;  // last: started after the rest
};

// The objective of `x` in `solver`.
double objectiveOf(const OsiClpSolverInterface& solver, const double* x) {
  const double* costs = solver.getObjCoefficients();
  double sum = 0;
  for (int c = 0; c < solver.getNumCols(); ++c) sum += costs[c] * x[c];
  return sum;
}

// CBC's own solver (cuts and primal heuristics, as its command line runs them, without
// strong branching: over the few nodes a plan's search is given, its look-ahead at each
// node costs more than it finds, docs/planning.md) on the integer program of `solver`,
// from the feasible solution `start` (every column), within `limits`: the first `sets`
// columns at 1 in the best solution found (the start's unless one costs less), and whether
// it is proven least, the bound (rounded up when `integral`) and whether the time cap
// stopped it, into `result`.
std::vector<int> branchAndBound(const OsiClpSolverInterface& solver, std::vector<double> start,
                                int sets, const SolveLimits& limits, bool integral,
                                SetCoverResult& result, const SetCoverProgress& progress = {}) {
  const int columns = solver.getNumCols();
  CbcModel model(solver);
  CbcSolverUsefulData data;
  CbcMain0(model, data);
  model.setLogLevel(0);
  model.messageHandler()->setLogLevel(0);
  model.solver()->messageHandler()->setLogLevel(0);
  const auto share = std::make_shared<std::atomic<double>>(0.0);
  NodesSearched searched(share, limits.nodes);
  model.passInEventHandler(&searched);
  const SharesShown shown(progress, share);
  const double start_cost = objectiveOf(solver, start.data());
  model.setBestSolution(start.data(), columns, start_cost, true);
  const std::string time = std::to_string(limits.seconds), nodes = std::to_string(limits.nodes);
  const char* argv[] = {"scanplan", "-log",       "0",     "-slog",       "0",
                        "-sec",     time.c_str(), "-maxN", nodes.c_str(), "-strong",
                        "0",        "-solve",     "-quit"};
  CbcMain1(static_cast<int>(std::size(argv)), argv, model, nullptr, data);
  const double* best = model.bestSolution();
  const double* chosen_x =
      best && objectiveOf(solver, best) <= start_cost + 1e-9 ? best : start.data();
  std::vector<int> chosen;
  for (int c = 0; c < sets; ++c)
    if (chosen_x[c] > 0.5) chosen.push_back(c);
  result.optimal = model.isProvenOptimal();
  result.time_capped = result.time_capped || model.isSecondsLimitReached();
  const double bound = model.getBestPossibleObjValue();
  result.lower_bound = std::max(result.lp_bound, integral ? std::ceil(bound - 1e-6) : bound);
  return chosen;
}

// The columns `chosen` at 1, the others at 0.
std::vector<double> indicator(const std::vector<int>& chosen, int columns) {
  std::vector<double> x(columns, 0.0);
  for (int c : chosen) x[c] = 1.0;
  return x;
}

// The core of an instance whose LP `solver` has solved, its first `sets` columns the sets:
// the kCoreSets sets of least reduced cost (the first on ties), those of reduced cost at
// most kCoreReducedCost, those the LP uses and those of `start`; and the least reduced
// cost of the others (infinity when none is left out).
std::pair<std::vector<int>, double> lpCore(const OsiClpSolverInterface& solver, int sets,
                                           const std::vector<int>& start) {
  const double* reduced_cost = solver.getReducedCost();
  const double* x = solver.getColSolution();
  std::vector<int> order(sets);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(),
                   [&](int a, int b) { return reduced_cost[a] < reduced_cost[b]; });
  std::vector<char> in(sets, 0);
  for (int k = 0; k < std::min(sets, kCoreSets); ++k) in[order[k]] = 1;
  for (int c : start) in[c] = 1;
  std::vector<int> core;
  double least_out = std::numeric_limits<double>::infinity();
  for (int c = 0; c < sets; ++c) {
    if (in[c] || x[c] > 1e-9 || reduced_cost[c] <= kCoreReducedCost)
      core.push_back(c);
    else
      least_out = std::min(least_out, reduced_cost[c]);
  }
  return {core, least_out};
}

// Solves the LP loaded into `solver` within kLpIterations simplex iterations: whether it
// found the optimum.
bool solveRelaxation(OsiClpSolverInterface& solver) {
  solver.getModelPtr()->setMaximumIterations(kLpIterations);
  solver.initialSolve();
  return solver.isProvenOptimal();
}

// The root LP's iteration limit lifted for the search: a node LP stopped by it would be
// taken as infeasible, and the search would cut off covers it has not seen.
void liftIterationLimit(OsiClpSolverInterface& solver) {
  solver.getModelPtr()->setMaximumIterations(std::numeric_limits<int>::max());
}

// `result`'s bound, CBC's over the core, as a bound on the whole instance: a solution using
// a set outside the core costs at least the LP optimum `lp` plus `least_out` (rounded up
// when `integral`); whether the solution of cost `found` is proven least by it.
void boundWholeInstance(double lp, double least_out, bool integral, double found,
                        SetCoverResult& result) {
  const double outside = integral ? std::ceil(lp + least_out - 1e-6) : lp + least_out;
  result.lower_bound = std::max(result.lp_bound, std::min(result.lower_bound, outside));
  result.optimal = found <= result.lower_bound + 1e-9;
}

// The columns `chosen` of the core `core` as columns of the whole, sorted.
std::vector<int> ofWhole(std::vector<int> chosen, const std::vector<int>& core) {
  for (int& c : chosen) c = core[c];
  std::sort(chosen.begin(), chosen.end());
  return chosen;
}

// Per column of the whole (`columns` of them), its place in the core, or -1.
std::vector<int> placesIn(const std::vector<int>& core, std::size_t columns) {
  std::vector<int> place(columns, -1);
  for (std::size_t k = 0; k < core.size(); ++k) place[core[k]] = static_cast<int>(k);
  return place;
}

// The fewest sets of the core `core` of `reduced` covering every row, by CBC within
// `limits` from the cover `start` (sets of the core): sets of the whole, and CBC's bound
// over the core into `result`.
std::vector<int> coreCover(const Reduced& reduced, const std::vector<int>& core,
                           const std::vector<int>& start, const SolveLimits& limits,
                           const SetCoverProgress& progress, SetCoverResult& result) {
  Reduced sub;
  sub.rows = reduced.rows;
  for (int c : core) sub.columns.push_back(reduced.columns[c]);
  OsiClpSolverInterface solver;
  loadRelaxation(sub, solver);
  if (!solveRelaxation(solver)) return start;
  liftIterationLimit(solver);
  const std::vector<int> place = placesIn(core, reduced.columns.size());
  std::vector<int> in_core;
  for (int c : start) in_core.push_back(place[c]);
  for (int c = 0; c < solver.getNumCols(); ++c) solver.setInteger(c);
  return ofWhole(branchAndBound(solver, indicator(in_core, solver.getNumCols()),
                                solver.getNumCols(), limits, true, result, progress),
                 core);
}

// The sets whose columns pricing adds to an LP relaxation (relaxationByPricing): each set's
// rows and the coefficient a set has in each of its rows (cost 1 each, between 0 and 1).
struct Priced {
  const std::vector<std::vector<int>>& columns;
  int rows = 0;
  double coefficient = 1;
};

// Per row, the set holding it that holds the most rows (the first on ties): together they
// hold every row some set holds.
std::vector<int> largestPerRow(const Priced& lp) {
  std::vector<int> largest(lp.rows, -1);
  for (std::size_t c = 0; c < lp.columns.size(); ++c)
    for (int r : lp.columns[c])
      if (largest[r] < 0 || lp.columns[c].size() > lp.columns[largest[r]].size())
        largest[r] = static_cast<int>(c);
  return largest;
}

// The sets not `in` the LP whose reduced cost against the rows' duals `dual` is negative,
// most negative first, at most kPricedSets.
std::vector<int> pricedSets(const Priced& lp, const std::vector<char>& in, const double* dual) {
  constexpr double kNegative = -1e-7;  // CLP's dual feasibility tolerance
  std::vector<std::pair<double, int>> entering;
  for (std::size_t c = 0; c < lp.columns.size(); ++c) {
    if (in[c]) continue;
    double cost = 1;
    for (int r : lp.columns[c]) cost -= lp.coefficient * dual[r];
    if (cost < kNegative) entering.push_back({cost, static_cast<int>(c)});
  }
  std::stable_sort(entering.begin(), entering.end(),
                   [](auto& a, auto& b) { return a.first < b.first; });
  entering.resize(std::min(entering.size(), kPricedSets));
  std::vector<int> result;
  for (const auto& [cost, c] : entering) result.push_back(c);
  return result;
}

// The sets `added` of `lp` not yet `in` the LP of `solver`, added as its columns.
void addSets(const Priced& lp, const std::vector<int>& added, std::vector<char>& in,
             OsiClpSolverInterface& solver) {
  for (int c : added) {
    if (c < 0 || in[c]) continue;
    in[c] = 1;
    const std::vector<int>& rows = lp.columns[c];
    const std::vector<double> values(rows.size(), lp.coefficient);
    solver.addCol(static_cast<int>(rows.size()), rows.data(), values.data(), 0.0, 1.0, 1.0);
  }
}

// The optimum of the LP relaxation loaded into `solver` without the sets of `lp`, by
// pricing: solved with the sets largestPerRow names, then again with the sets of negative
// reduced cost added (pricedSets), until no set has one. The optimum is the whole LP's,
// over a small share of its sets; none when kLpIterations simplex iterations in all do not
// reach it.
std::optional<double> relaxationByPricing(const Priced& lp, OsiClpSolverInterface& solver) {
  std::vector<char> in(lp.columns.size(), 0);
  addSets(lp, largestPerRow(lp), in, solver);
  if (!solveRelaxation(solver)) return std::nullopt;
  solver.setHintParam(OsiDoDualInResolve, false, OsiHintDo);  // new sets: primal simplex
  int iterations = solver.getIterationCount();
  for (;;) {
    const std::vector<int> entering = pricedSets(lp, in, solver.getRowPrice());
    if (entering.empty()) return solver.getObjValue();
    addSets(lp, entering, in, solver);
    solver.getModelPtr()->setMaximumIterations(kLpIterations - iterations);
    solver.resolve();
    iterations += solver.getIterationCount();
    if (!solver.isProvenOptimal()) return std::nullopt;
  }
}

}  // namespace

SetCoverResult minimumSetCover(const std::vector<std::vector<int>>& sets,
                               const std::vector<char>& required, const SolveLimits& limits,
                               const std::vector<int>& given_start,
                               const SetCoverProgress& progress) {
  const auto began = Clock::now();
  SetCoverResult result;
  const Reduced reduced = reduce(sets, required);
  if (reduced.rows == 0) return result;
  // The start in the reduced sets: each set replaced by a kept one that includes it.
  std::vector<int> start;
  for (int s : given_start)
    if (reduced.kept_as[s] >= 0) start.push_back(reduced.kept_as[s]);
  std::sort(start.begin(), start.end());
  start.erase(std::unique(start.begin(), start.end()), start.end());

  OsiClpSolverInterface solver;
  loadRelaxation(reduced, solver);
  if (solveRelaxation(solver)) {
    const double lp = solver.getObjValue();
    result.lp_bound = std::ceil(lp - 1e-6);
    if (std::vector<int> rounded = roundedCover(reduced, solver.getColSolution());
        start.empty() || rounded.size() < start.size())
      start = rounded;
    const auto [core, least_out] = lpCore(solver, solver.getNumCols(), start);
    start = coreCover(reduced, core, start, limits, progress, result);
    boundWholeInstance(lp, least_out, true, static_cast<double>(start.size()), result);
  }
  // Without the LP's answer and without a start: still a cover, each row by the first set
  // that holds it, the redundant ones dropped.
  if (start.empty())
    start = roundedCover(reduced, std::vector<double>(reduced.columns.size(), 1).data());
  for (int& c : start) c = reduced.set_of[c];
  std::sort(start.begin(), start.end());
  result.chosen = start;
  result.seconds = secondsSince(began);
  return result;
}

double setCoverLowerBound(const std::vector<std::vector<int>>& sets,
                          const std::vector<char>& required) {
  const Reduced reduced = reduce(sets, required);
  if (reduced.rows == 0) return 0;
  OsiClpSolverInterface solver;
  loadRelaxation(Reduced{.rows = reduced.rows}, solver);  // the rows alone
  const std::optional<double> lp =
      relaxationByPricing({.columns = reduced.columns, .rows = reduced.rows}, solver);
  return lp ? std::ceil(*lp - 1e-6) : 0;
}

SetCoverResult minimumMulticover(const std::vector<std::vector<int>>& sets,
                                 const std::vector<int>& demand, const SolveLimits& limits) {
  const auto began = Clock::now();
  SetCoverResult result;
  // Each element's demand, capped by the sets holding it; no reduction (with demands above
  // one, a set inside another may still be needed).
  std::vector<char> required(demand.size(), 0);
  for (std::size_t e = 0; e < demand.size(); ++e) required[e] = demand[e] > 0;
  Reduced all;
  std::vector<int> elements;
  all.columns = requiredRows(sets, required, all.rows, &elements);
  if (all.rows == 0) return result;
  std::vector<double> need(all.rows, 0);
  for (const auto& column : all.columns)
    for (int r : column) ++need[r];
  for (int r = 0; r < all.rows; ++r) need[r] = std::min<double>(need[r], demand[elements[r]]);
  // A greedy start: the set meeting the most unmet demand, until none is left.
  std::vector<double> unmet = need;
  std::vector<char> used(all.columns.size(), 0);
  std::vector<int> start;
  for (;;) {
    int best = -1, best_gain = 0;
    for (std::size_t c = 0; c < all.columns.size(); ++c) {
      if (used[c]) continue;
      int gain = 0;
      for (int r : all.columns[c]) gain += unmet[r] > 0;
      if (gain > best_gain) {
        best_gain = gain;
        best = static_cast<int>(c);
      }
    }
    if (best < 0) break;
    used[best] = 1;
    start.push_back(best);
    for (int r : all.columns[best]) --unmet[r];
  }
  OsiClpSolverInterface solver;
  loadRelaxation(all, solver, need);
  solver.initialSolve();
  if (solver.isProvenOptimal()) {
    result.lp_bound = std::ceil(solver.getObjValue() - 1e-6);
    for (int c = 0; c < solver.getNumCols(); ++c) solver.setInteger(c);
    start = branchAndBound(solver, indicator(start, solver.getNumCols()), solver.getNumCols(),
                           limits, true, result);
  }
  std::sort(start.begin(), start.end());
  result.chosen = start;
  result.seconds = secondsSince(began);
  return result;
}

namespace {

// The partial cover as rows of element indices: per set its rows, per row its group; the
// need of each group capped by the rows it has.
struct PartialInstance {
  std::vector<std::vector<int>> columns{};
  std::vector<int> group_of;  // per row
  std::vector<double> need;   // per group
};

PartialInstance partialInstance(const std::vector<std::vector<int>>& sets,
                                const std::vector<int>& group, const std::vector<double>& need) {
  std::vector<char> counted(group.size(), 0);
  for (std::size_t e = 0; e < group.size(); ++e)
    counted[e] = group[e] >= 0 && group[e] < static_cast<int>(need.size());
  PartialInstance instance;
  std::vector<int> elements;
  int rows = 0;
  instance.columns = requiredRows(sets, counted, rows, &elements);
  std::vector<double> held(need.size(), 0);
  for (int e : elements) {
    instance.group_of.push_back(group[e]);
    ++held[group[e]];
  }
  for (std::size_t g = 0; g < need.size(); ++g)
    instance.need.push_back(std::min(std::ceil(need[g] - 1e-9), held[g]));
  return instance;
}

// Greedy: the set meeting the most unmet need per cost, until every group has its need.
std::vector<int> greedyPartial(const PartialInstance& p, const std::vector<double>& costs) {
  std::vector<double> unmet = p.need;
  std::vector<char> covered(p.group_of.size(), 0), used(p.columns.size(), 0);
  std::vector<int> chosen;
  std::vector<double> gain(unmet.size());  // per group, of the set weighed
  for (;;) {
    int best = -1;
    double best_rate = 0;
    for (std::size_t c = 0; c < p.columns.size(); ++c) {
      if (used[c]) continue;
      std::fill(gain.begin(), gain.end(), 0.0);
      for (int r : p.columns[c])
        if (!covered[r]) ++gain[p.group_of[r]];
      double useful = 0;
      for (std::size_t g = 0; g < gain.size(); ++g) useful += std::min(gain[g], unmet[g]);
      const double rate = useful / std::max(costs[c], 1e-12);
      if (useful > 0 && rate > best_rate) {
        best_rate = rate;
        best = static_cast<int>(c);
      }
    }
    if (best < 0) return chosen;
    used[best] = 1;
    chosen.push_back(best);
    for (int r : p.columns[best])
      if (!covered[r]) {
        covered[r] = 1;
        unmet[p.group_of[r]] = std::max(unmet[p.group_of[r]] - 1, 0.0);
      }
  }
}

// Whether the sets `chosen` meet every group's need.
bool meetsNeed(const PartialInstance& p, const std::vector<int>& chosen) {
  std::vector<char> covered(p.group_of.size(), 0);
  for (int c : chosen)
    for (int r : p.columns[c]) covered[r] = 1;
  std::vector<int> got(p.need.size(), 0);  // rows covered per group
  for (std::size_t r = 0; r < covered.size(); ++r) got[p.group_of[r]] += covered[r];
  for (std::size_t g = 0; g < got.size(); ++g)
    if (got[g] < p.need[g]) return false;
  return true;
}

double cost(const std::vector<double>& costs, const std::vector<int>& chosen) {
  double sum = 0;
  for (int c : chosen) sum += costs[c];
  return sum;
}

// The LP of the partial cover: a column per set (cost c_s) and per row (its y, cost 0);
// y_r - sum_{s holds r} x_s <= 0 per row, sum_{r in g} y_r >= need_g per group.
void loadPartial(const PartialInstance& p, const std::vector<double>& costs,
                 OsiClpSolverInterface& solver) {
  const int sets = static_cast<int>(p.columns.size()), rows = static_cast<int>(p.group_of.size());
  const int groups = static_cast<int>(p.need.size());
  std::vector<int> indices, starts, lengths;
  std::vector<double> values;
  for (const auto& column : p.columns) {
    starts.push_back(static_cast<int>(indices.size()));
    indices.insert(indices.end(), column.begin(), column.end());
    values.insert(values.end(), column.size(), -1.0);
    lengths.push_back(static_cast<int>(column.size()));
  }
  for (int r = 0; r < rows; ++r) {
    starts.push_back(static_cast<int>(indices.size()));
    indices.insert(indices.end(), {r, rows + p.group_of[r]});
    values.insert(values.end(), {1.0, 1.0});
    lengths.push_back(2);
  }
  const CoinPackedMatrix matrix(true, rows + groups, sets + rows,
                                static_cast<CoinBigIndex>(indices.size()), values.data(),
                                indices.data(), starts.data(), lengths.data());
  const double infinity = std::numeric_limits<double>::infinity();
  std::vector<double> objective(costs.begin(), costs.end());
  objective.resize(sets + rows, 0.0);
  const std::vector<double> column_lower(sets + rows, 0.0), column_upper(sets + rows, 1.0);
  std::vector<double> row_lower(rows, -infinity), row_upper(rows, 0.0);
  row_lower.insert(row_lower.end(), p.need.begin(), p.need.end());
  row_upper.insert(row_upper.end(), groups, infinity);
  solver.loadProblem(matrix, column_lower.data(), column_upper.data(), objective.data(),
                     row_lower.data(), row_upper.data());
  solver.messageHandler()->setLogLevel(0);
  solver.getModelPtr()->setLogLevel(0);
}

// The cheapest sets of the core `core` of `p` meeting every need, by CBC within `limits`
// from the sets `start` (all in the core), which meet them: sets of the whole, and CBC's
// bound over the core into `result`.
std::vector<int> corePartialCover(const PartialInstance& p, const std::vector<double>& costs,
                                  const std::vector<int>& core, const std::vector<int>& start,
                                  const SolveLimits& limits, bool integral,
                                  SetCoverResult& result) {
  PartialInstance sub{{}, p.group_of, p.need};
  std::vector<double> sub_costs;
  for (int c : core) {
    sub.columns.push_back(p.columns[c]);
    sub_costs.push_back(costs[c]);
  }
  OsiClpSolverInterface solver;
  loadPartial(sub, sub_costs, solver);
  if (!solveRelaxation(solver)) return start;
  liftIterationLimit(solver);
  const int columns = static_cast<int>(core.size());
  for (int c = 0; c < columns; ++c) solver.setInteger(c);
  const std::vector<int> place = placesIn(core, p.columns.size());
  std::vector<double> x(solver.getNumCols(), 0.0);
  for (int c : start) {
    x[place[c]] = 1.0;
    for (int r : p.columns[c]) x[columns + r] = 1.0;  // each row the start covers counts
  }
  return ofWhole(branchAndBound(solver, x, columns, limits, integral, result), core);
}

// minimumPartialCover on an instance without dominated sets: the greedy start, or `start`
// when it meets every need and costs less; the LP's bound; CBC over the LP's core within
// `limits`, its bound raised to the whole instance, into `result`. The sets chosen.
std::vector<int> reducedPartialCover(const PartialInstance& p, const std::vector<double>& costs,
                                     const SolveLimits& limits, const std::vector<int>& start,
                                     SetCoverResult& result) {
  std::vector<int> chosen = greedyPartial(p, costs);
  if (meetsNeed(p, start) && cost(costs, start) < cost(costs, chosen)) chosen = start;
  const bool integral = std::all_of(costs.begin(), costs.end(), [](double c) { return c == 1; });
  if (p.group_of.empty() || chosen.empty()) return chosen;
  const StdoutSilenced quiet;
  OsiClpSolverInterface solver;
  loadPartial(p, costs, solver);
  if (!solveRelaxation(solver)) return chosen;
  const double lp = solver.getObjValue();
  result.lp_bound = integral ? std::ceil(lp - 1e-6) : lp;
  const auto [core, least_out] = lpCore(solver, static_cast<int>(p.columns.size()), chosen);
  chosen = corePartialCover(p, costs, core, chosen, limits, integral, result);
  boundWholeInstance(lp, least_out, integral, cost(costs, chosen), result);
  return chosen;
}

}  // namespace

double partialCoverLowerBound(const std::vector<std::vector<int>>& sets,
                              const std::vector<int>& group, const std::vector<double>& need) {
  PartialInstance p = partialInstance(sets, group, need);
  if (p.group_of.empty()) return 0;
  // At unit costs a set another includes adds nothing to the LP: dropped.
  Reduced kept;
  dropDominatedSets(p.columns, static_cast<int>(p.group_of.size()), kept);
  p.columns = std::move(kept.columns);
  OsiClpSolverInterface solver;  // the rows' and groups' constraints, no set yet
  loadPartial(PartialInstance{.group_of = p.group_of, .need = p.need}, {}, solver);
  const StdoutSilenced quiet;
  // The sets' columns have -1 in the rows they hold (loadPartial).
  const std::optional<double> lp = relaxationByPricing(
      {.columns = p.columns, .rows = static_cast<int>(p.group_of.size()), .coefficient = -1},
      solver);
  return lp ? std::ceil(*lp - 1e-6) : 0;
}

SetCoverResult minimumPartialCover(const std::vector<std::vector<int>>& sets,
                                   const std::vector<double>& costs, const std::vector<int>& group,
                                   const std::vector<double>& need, const SolveLimits& limits,
                                   const std::vector<int>& start) {
  const auto began = Clock::now();
  SetCoverResult result;
  PartialInstance p = partialInstance(sets, group, need);
  // Sets that a set costing no more includes are dropped; `start`'s replaced by those.
  Reduced kept;
  dropDominatedSets(p.columns, static_cast<int>(p.group_of.size()), kept, &costs);
  p.columns = std::move(kept.columns);
  std::vector<double> kept_costs;
  for (int s : kept.set_of) kept_costs.push_back(costs[s]);
  std::vector<int> kept_start;
  for (int s : start)
    if (kept.kept_as[s] >= 0) kept_start.push_back(kept.kept_as[s]);
  std::sort(kept_start.begin(), kept_start.end());
  kept_start.erase(std::unique(kept_start.begin(), kept_start.end()), kept_start.end());
  std::vector<int> chosen = reducedPartialCover(p, kept_costs, limits, kept_start, result);
  for (int& c : chosen) c = kept.set_of[c];
  std::sort(chosen.begin(), chosen.end());
  result.chosen = chosen;
  result.seconds = secondsSince(began);
  return result;
}

}  // namespace scanplan
