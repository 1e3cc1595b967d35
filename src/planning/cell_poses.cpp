// Joints for the views of a plan: per view the inverse-kinematics solutions (and their
// other turns of wide joints), then the path through them with the least joint travel
// time: a shortest path over layers of solutions, one layer per view in visiting order.

#include <scanplan/planning/cell_poses.h>
#include <scanplan/robot/motion.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <map>

namespace scanplan {
namespace {

// `poses` with, for joints whose range exceeds a turn, each other turn the limits allow:
// the same flange pose reached with a joint 360° further, which may travel less.
std::vector<CellPose> withOtherTurns(const RobotModel& robot, std::vector<CellPose> poses) {
  for (int j = 0; j < 6; ++j) {
    const std::size_t n = poses.size();
    for (std::size_t i = 0; i < n; ++i)
      for (double turn : {-2 * M_PI, 2 * M_PI}) {
        CellPose other = poses[i];
        other.joints[j] += turn;
        if (other.joints[j] >= robot.lower[j] && other.joints[j] <= robot.upper[j])
          poses.push_back(other);
      }
  }
  return poses;
}

// Solutions of a view that are one pose with wide joints at other turns: the same table
// angle, each joint's values a whole number of turns apart. Per joint, the values it takes.
struct Turned {
  CellPose first;
  std::array<std::vector<double>, 6> turns;
  std::size_t count = 0;  // solutions in it
  // Every combination of the joints' turns is a solution of it, as withOtherTurns makes
  // them: a joint's turn can then be chosen apart from the others'.
  bool everyCombination() const {
    std::size_t combinations = 1;
    for (const std::vector<double>& t : turns) combinations *= t.size();
    return combinations == count;
  }
};

bool turnsOf(const CellPose& a, const CellPose& b) {
  if (a.table_angle != b.table_angle) return false;
  for (int j = 0; j < 6; ++j)
    if (std::abs(std::remainder(a.joints[j] - b.joints[j], 2 * M_PI)) > 1e-9) return false;
  return true;
}

std::vector<Turned> turned(const std::vector<CellPose>& solutions) {
  std::vector<Turned> result;
  for (const CellPose& s : solutions) {
    auto it = std::find_if(result.begin(), result.end(),
                           [&](const Turned& t) { return turnsOf(t.first, s); });
    if (it == result.end()) it = result.insert(result.end(), Turned{s, {}, 0});
    ++it->count;
    for (int j = 0; j < 6; ++j)
      if (std::find(it->turns[j].begin(), it->turns[j].end(), s.joints[j]) == it->turns[j].end())
        it->turns[j].push_back(s.joints[j]);
  }
  return result;
}

// The least move time from a solution of `a` to one of `b`. The time is the slowest
// joint's (or the table's), each growing with its own travel, so with every combination of
// turns present the least is each joint's least travel over its turns.
double leastMoveTime(const Cell& cell, const Turned& a, const Turned& b) {
  CellPose from{a.first.table_angle, {}}, to{b.first.table_angle, {}};
  for (int j = 0; j < 6; ++j) {
    double least = std::numeric_limits<double>::infinity();
    for (double x : a.turns[j])
      for (double y : b.turns[j]) least = std::min(least, std::abs(y - x));
    to.joints[j] = least;
  }
  return moveTime(cell, from, to);
}

// The least move time between the solutions of two views.
double leastMoveTime(const Cell& cell, const std::vector<CellPose>& a,
                     const std::vector<Turned>& turned_a, const std::vector<CellPose>& b,
                     const std::vector<Turned>& turned_b) {
  const auto complete = [](const std::vector<Turned>& t) {
    return std::all_of(t.begin(), t.end(), [](const Turned& x) { return x.everyCombination(); });
  };
  double best = std::numeric_limits<double>::infinity();
  if (complete(turned_a) && complete(turned_b)) {
    for (const Turned& x : turned_a)
      for (const Turned& y : turned_b) best = std::min(best, leastMoveTime(cell, x, y));
  } else {
    for (const CellPose& x : a)
      for (const CellPose& y : b) best = std::min(best, moveTime(cell, x, y));
  }
  return best;
}

}  // namespace

double unwindingTime(const Cell& cell, const CellPose& pose) {
  const RobotModel robot = workingRange(cell);
  CellPose unwound = pose;
  for (int j = 0; j < 6; ++j)
    for (const double turn : {-2 * M_PI, 2 * M_PI}) {
      const double other = unwound.joints[j] + turn;
      if (std::abs(other) < std::abs(unwound.joints[j]) && other >= robot.lower[j] &&
          other <= robot.upper[j])
        unwound.joints[j] = other;
    }
  return moveTime(cell, unwound, pose);
}

std::vector<int> visitingOrder(const Plan& plan) {
  std::vector<int> order;
  if (plan.sequence) order = plan.sequence->views;
  for (const View& v : plan.views)
    if (std::find(order.begin(), order.end(), v.id) == order.end()) order.push_back(v.id);
  return order;
}

CellSolutions cellSolutions(const Cell& cell, const std::vector<View>& views,
                            const CellCollisions* collisions) {
  CellSolutions solutions(views.size());
  for (std::size_t i = 0; i < views.size(); ++i)
    solutions[i] =
        withOtherTurns(workingRange(cell), reachView(cell, views[i], {}, 0, collisions).poses);
  return solutions;
}

std::vector<std::optional<CellPose>> cellPoses(const Cell& cell, const std::vector<View>& views,
                                               const std::vector<int>& order,
                                               const CellCollisions* collisions) {
  return cellPoses(cell, views, order, cellSolutions(cell, views, collisions));
}

std::vector<std::optional<CellPose>> cellPoses(const Cell& cell, const std::vector<View>& views,
                                               const std::vector<int>& order,
                                               const CellSolutions& solutions) {
  std::map<int, std::size_t> index;
  for (std::size_t i = 0; i < views.size(); ++i) index[views[i].id] = i;
  // Layers of solutions, views the cell takes only, in visiting order.
  std::vector<std::size_t> visited;
  std::vector<const std::vector<CellPose>*> layers;
  for (int id : order) {
    auto it = index.find(id);
    if (it == index.end() || solutions[it->second].empty()) continue;
    visited.push_back(it->second);
    layers.push_back(&solutions[it->second]);
  }
  std::vector<std::optional<CellPose>> result(views.size());
  if (layers.empty()) return result;
  // cost[k][s]: least time to reach solution s of layer k, the wide joints wound there from
  // their turn nearest 0 included; from[k][s]: its predecessor.
  std::vector<std::vector<double>> cost(layers.size());
  std::vector<std::vector<std::size_t>> from(layers.size());
  for (const CellPose& pose : *layers[0]) cost[0].push_back(unwindingTime(cell, pose));
  from[0].assign(layers[0]->size(), 0);
  for (std::size_t k = 1; k < layers.size(); ++k) {
    cost[k].assign(layers[k]->size(), std::numeric_limits<double>::infinity());
    from[k].assign(layers[k]->size(), 0);
    for (std::size_t s = 0; s < layers[k]->size(); ++s)
      for (std::size_t p = 0; p < layers[k - 1]->size(); ++p) {
        const double c = cost[k - 1][p] + moveTime(cell, (*layers[k - 1])[p], (*layers[k])[s]);
        if (c < cost[k][s]) {
          cost[k][s] = c;
          from[k][s] = p;
        }
      }
  }
  // The last solution pays for unwinding too.
  std::vector<double> total = cost.back();
  for (std::size_t t = 0; t < total.size(); ++t)
    total[t] += unwindingTime(cell, (*layers.back())[t]);
  std::size_t s =
      static_cast<std::size_t>(std::min_element(total.begin(), total.end()) - total.begin());
  for (std::size_t k = layers.size(); k-- > 0;) {
    result[visited[k]] = (*layers[k])[s];
    s = from[k][s];
  }
  return result;
}

Eigen::MatrixXd jointTravelTimes(const Cell& cell, const CellSolutions& solutions) {
  constexpr double kUnreached = 1000;
  std::vector<std::vector<Turned>> turns;
  for (const std::vector<CellPose>& s : solutions) turns.push_back(turned(s));
  const auto n = static_cast<Eigen::Index>(solutions.size());
  Eigen::MatrixXd times = Eigen::MatrixXd::Zero(n, n);
  for (std::size_t i = 0; i < solutions.size(); ++i)
    for (std::size_t j = i + 1; j < solutions.size(); ++j) {
      const double best =
          std::min(kUnreached, leastMoveTime(cell, solutions[i], turns[i], solutions[j], turns[j]));
      const auto a = static_cast<Eigen::Index>(i), b = static_cast<Eigen::Index>(j);
      times(a, b) = times(b, a) = best;
    }
  return times;
}

}  // namespace scanplan
