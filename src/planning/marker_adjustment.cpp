#include "planning/marker_adjustment.h"

#include <Eigen/Cholesky>

#include <map>

namespace scanplan::detail {

std::vector<MarkerGroup> markerGroups(const Plan& plan,
                                      const std::vector<std::optional<std::size_t>>& parents,
                                      const std::vector<char>& placed) {
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  // Whether `v` joins the group of the view it registers to: by markers, in the same
  // setup (a link across setups, by the part's markers, stays a link of its own).
  const auto joins = [&](std::size_t v) {
    return plan.registration->views[v].method == RegistrationMethod::Markers && parents[v] &&
           orientation[*parents[v]] == orientation[v];
  };
  std::map<std::size_t, MarkerGroup> by_root;
  for (std::size_t v = 0; v < parents.size(); ++v) {
    if (!joins(v) || !placed[v]) continue;
    std::size_t root = *parents[v];
    for (std::size_t hops = 0; joins(root) && hops <= parents.size(); ++hops) root = *parents[root];
    MarkerGroup& group = by_root[root];
    group.root = root;
    group.members.push_back(v);
  }
  std::vector<MarkerGroup> groups;
  for (auto& [root, group] : by_root) groups.push_back(std::move(group));
  return groups;
}

Eigen::MatrixXd adjustedCovariance(const Plan& plan, const MarkerGroup& group, double sigma) {
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  // Per marker, the group's views that see it: their slot (-1: the root) and the motion
  // at the marker's centre as each sees it.
  std::map<int, std::vector<std::pair<int, Eigen::Matrix<double, 3, 6>>>> seen;
  const auto observe = [&](std::size_t v, int slot) {
    const std::vector<Vec3> positions = markerPositions(plan, orientation[v], v);
    for (int m : plan.registration->views[v].markers)
      if (m >= 0 && static_cast<std::size_t>(m) < positions.size())
        seen[m].push_back({slot, motionAt(positions[static_cast<std::size_t>(m)])});
  };
  observe(group.root, -1);
  for (std::size_t i = 0; i < group.members.size(); ++i)
    observe(group.members[i], static_cast<int>(i));
  // The normal matrix of the members' twists, the markers' positions eliminated: each
  // marker seen by k views pulls each of them towards the mean of the k.
  const auto n = static_cast<Eigen::Index>(6 * group.members.size());
  Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(n, n);
  for (const auto& [marker, views] : seen) {
    const double k = static_cast<double>(views.size());
    if (views.size() < 2) continue;
    for (const auto& [a, ja] : views) {
      if (a < 0) continue;
      normal.block<6, 6>(6 * a, 6 * a) += ja.transpose() * ja;
      for (const auto& [b, jb] : views)
        if (b >= 0) normal.block<6, 6>(6 * a, 6 * b) -= ja.transpose() * jb / k;
    }
  }
  normal.diagonal().array() += 1e-12 * (normal.trace() / static_cast<double>(n) + 1);
  return sigma * sigma * Eigen::LLT<Eigen::MatrixXd>(normal).solve(Eigen::MatrixXd::Identity(n, n));
}

}  // namespace scanplan::detail
