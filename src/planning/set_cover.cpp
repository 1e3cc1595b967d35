#include <scanplan/planning/set_cover.h>

#include <CbcModel.hpp>
#include <ClpSimplex.hpp>
#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>

namespace scanplan {

SetCoverResult minimumSetCover(const std::vector<std::vector<int>>& sets,
                               const std::vector<char>& required, double time_limit_seconds,
                               const std::vector<int>& start, int max_nodes) {
  const auto began = std::chrono::steady_clock::now();
  SetCoverResult result;
  // One row per required element that some set covers.
  std::vector<int> row_of(required.size(), -1);
  int rows = 0;
  for (const auto& set : sets)
    for (int e : set)
      if (required[e] && row_of[e] < 0) row_of[e] = rows++;
  if (rows == 0 || sets.empty()) return result;

  // Column-ordered, built in one go: one column per set.
  std::vector<int> indices, starts, lengths;
  for (const auto& set : sets) {
    starts.push_back(static_cast<int>(indices.size()));
    for (int e : set)
      if (row_of[e] >= 0) indices.push_back(row_of[e]);
    lengths.push_back(static_cast<int>(indices.size()) - starts.back());
  }
  const std::vector<double> ones(indices.size(), 1.0);
  const CoinPackedMatrix matrix(true, rows, static_cast<int>(sets.size()),
                                static_cast<CoinBigIndex>(indices.size()), ones.data(),
                                indices.data(), starts.data(), lengths.data());
  const int columns = static_cast<int>(sets.size());
  std::vector<double> column_lower(columns, 0.0), column_upper(columns, 1.0),
      objective(columns, 1.0);
  std::vector<double> row_lower(rows, 1.0),
      row_upper(rows, std::numeric_limits<double>::infinity());
  OsiClpSolverInterface solver;
  solver.loadProblem(matrix, column_lower.data(), column_upper.data(), objective.data(),
                     row_lower.data(), row_upper.data());
  solver.messageHandler()->setLogLevel(0);
  // The LP relaxation, in at most half the time; without it, the start is the answer.
  solver.getModelPtr()->setMaximumSeconds(time_limit_seconds / 2);
  solver.getModelPtr()->setMaximumIterations(100000);
  solver.initialSolve();
  if (!solver.isProvenOptimal()) {
    result.chosen = start;
    result.seconds =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
    return result;
  }
  result.lp_bound = std::ceil(solver.getObjValue() - 1e-6);
  for (int c = 0; c < columns; ++c) solver.setInteger(c);
  const double left =
      time_limit_seconds -
      std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();

  CbcModel model(solver);
  model.setLogLevel(0);
  model.messageHandler()->setLogLevel(0);
  model.setMaximumSeconds(std::max(left, 0.0));
  model.setMaximumNodes(max_nodes);
  if (!start.empty()) {
    std::vector<double> x(columns, 0.0);
    for (int c : start) x[c] = 1.0;
    model.setBestSolution(x.data(), columns, static_cast<double>(start.size()), true);
  }
  model.branchAndBound();
  if (const double* best = model.bestSolution())
    for (int c = 0; c < columns; ++c)
      if (best[c] > 0.5) result.chosen.push_back(c);
  if (!start.empty() && (result.chosen.empty() || result.chosen.size() > start.size()))
    result.chosen = start;
  result.optimal = model.isProvenOptimal();
  result.lower_bound = std::max(result.lp_bound, std::ceil(model.getBestPossibleObjValue() - 1e-6));
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - began).count();
  return result;
}

}  // namespace scanplan
