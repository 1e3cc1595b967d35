#include "planning/simulated_registration.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <iterator>

namespace scanplan::detail {
namespace {

// The rigid motion of a small twist: a turn by w, then a shift by t.
Pose poseOf(const Twist& twist) {
  Pose pose = Pose::Identity();
  const Vec3 w = twist.head<3>();
  if (w.norm() > 0) pose.linear() = Eigen::AngleAxisd(w.norm(), w.normalized()).toRotationMatrix();
  pose.translation() = twist.tail<3>();
  return pose;
}

// The rigid motion that best maps `from` onto `to` (least squares, point to point).
Pose rigidFit(const std::vector<Vec3>& from, const std::vector<Vec3>& to) {
  Eigen::Matrix3Xd a(3, from.size()), b(3, to.size());
  for (std::size_t i = 0; i < from.size(); ++i) {
    a.col(static_cast<Eigen::Index>(i)) = from[i];
    b.col(static_cast<Eigen::Index>(i)) = to[i];
  }
  return Pose(Eigen::umeyama(a, b, false));
}

}  // namespace

SimulatedRegistration::SimulatedRegistration(const Plan& plan, const std::vector<ViewError>& errors,
                                             double marker_sigma)
    : links_(errors.size()), chains_(chainsOf(errors)), sigma_(marker_sigma) {
  if (!plan.registration || plan.registration->views.size() != errors.size()) return;
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  for (std::size_t v = 0; v < errors.size(); ++v) {
    const ViewRegistration& r = plan.registration->views[v];
    Link& link = links_[v];
    const std::vector<Vec3> positions = markerPositions(plan, orientation[v], v);
    for (int m : r.markers)
      if (m >= 0 && static_cast<std::size_t>(m) < positions.size())
        link.seen[m] = positions[static_cast<std::size_t>(m)];
    if (!errors[v].placed) continue;
    const std::optional<std::size_t>& parent = chains_.parents[v];
    if (r.method == RegistrationMethod::ReferencePoints) {
      link.kind = Kind::Known;
      for (const auto& [m, at] : link.seen) link.fitted.push_back(m);
    } else if (r.method == RegistrationMethod::Markers && parent) {
      link.kind = Kind::Markers;
      std::vector<int> theirs = plan.registration->views[*parent].markers;
      std::sort(theirs.begin(), theirs.end());
      for (const auto& [m, at] : link.seen)
        if (std::binary_search(theirs.begin(), theirs.end(), m)) link.fitted.push_back(m);
    } else if (r.method == RegistrationMethod::Icp || r.method == RegistrationMethod::Robot) {
      link.kind = Kind::Drawn;
      link.root = squareRoot(errors[v].link);
    }
  }
}

std::vector<Pose> SimulatedRegistration::draw(std::mt19937_64& random) const {
  std::normal_distribution<double> normal;
  const std::size_t n = links_.size();
  std::vector<std::map<int, Vec3>> measured(n);  // per view, the centres as it measures them
  std::vector<Pose> own(n, Pose::Identity());
  for (std::size_t v = 0; v < n; ++v) {
    for (const auto& [m, at] : links_[v].seen) {
      const Vec3 noise(normal(random), normal(random), normal(random));
      measured[v][m] = at + sigma_ * noise;
    }
    Twist z;
    for (int i = 0; i < 6; ++i) z[i] = normal(random);
    if (links_[v].kind == Kind::Drawn) own[v] = poseOf(links_[v].root * z);
  }
  std::vector<Pose> placed(n, Pose::Identity());
  for (std::size_t v : chains_.order) {
    const Link& link = links_[v];
    const std::optional<std::size_t>& parent = chains_.parents[v];
    std::vector<Vec3> mine, theirs;
    for (int m : link.fitted) {
      mine.push_back(measured[v].at(m));
      theirs.push_back(link.kind == Kind::Known ? link.seen.at(m) : measured[*parent].at(m));
    }
    if ((link.kind == Kind::Markers || link.kind == Kind::Known) && mine.size() >= 3)
      own[v] = rigidFit(mine, theirs);
    placed[v] = parent ? placed[*parent] * own[v] : own[v];
  }
  return placed;
}

}  // namespace scanplan::detail
