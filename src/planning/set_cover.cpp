#include <scanplan/planning/set_cover.h>

#include <CbcModel.hpp>
#include <CoinPackedMatrix.hpp>
#include <OsiClpSolverInterface.hpp>

#include <chrono>
#include <cmath>
#include <limits>

namespace scanplan {

SetCoverResult minimumSetCover(const std::vector<std::vector<int>>& sets,
                               const std::vector<char>& required, double time_limit_seconds) {
  const auto start = std::chrono::steady_clock::now();
  SetCoverResult result;
  // One row per required element that some set covers.
  std::vector<int> row_of(required.size(), -1);
  int rows = 0;
  for (const auto& set : sets)
    for (int e : set)
      if (required[e] && row_of[e] < 0) row_of[e] = rows++;
  if (rows == 0 || sets.empty()) return result;

  CoinPackedMatrix matrix(true, 0, 0);  // column-ordered
  matrix.setDimensions(rows, 0);
  for (const auto& set : sets) {
    std::vector<int> indices;
    for (int e : set)
      if (row_of[e] >= 0) indices.push_back(row_of[e]);
    std::vector<double> ones(indices.size(), 1.0);
    matrix.appendCol(static_cast<int>(indices.size()), indices.data(), ones.data());
  }
  const int columns = static_cast<int>(sets.size());
  std::vector<double> column_lower(columns, 0.0), column_upper(columns, 1.0),
      objective(columns, 1.0);
  std::vector<double> row_lower(rows, 1.0),
      row_upper(rows, std::numeric_limits<double>::infinity());
  OsiClpSolverInterface solver;
  solver.loadProblem(matrix, column_lower.data(), column_upper.data(), objective.data(),
                     row_lower.data(), row_upper.data());
  for (int c = 0; c < columns; ++c) solver.setInteger(c);
  solver.messageHandler()->setLogLevel(0);

  CbcModel model(solver);
  model.setLogLevel(0);
  model.messageHandler()->setLogLevel(0);
  model.setMaximumSeconds(time_limit_seconds);
  model.branchAndBound();
  if (const double* best = model.bestSolution())
    for (int c = 0; c < columns; ++c)
      if (best[c] > 0.5) result.chosen.push_back(c);
  result.optimal = model.isProvenOptimal();
  result.lower_bound = std::ceil(model.getBestPossibleObjValue() - 1e-6);
  result.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

}  // namespace scanplan
