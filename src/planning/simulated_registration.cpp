#include "planning/simulated_registration.h"

#include <Eigen/Geometry>

#include <algorithm>

namespace scanplan::detail {
namespace {

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
    : slots_(errors.size()),
      links_(errors.size()),
      chains_(chainsOf(errors)),
      sigma_(marker_sigma) {
  for (std::size_t v = 0; v < errors.size(); ++v) slots_[v] = errors[v].slot;
  if (!plan.registration || plan.registration->views.size() != errors.size()) return;
  const std::vector<std::size_t> orientation = viewOrientations(plan);
  std::vector<std::pair<const Eigen::MatrixXd*, std::size_t>> by_factor;  // group of a factor
  for (std::size_t v = 0; v < errors.size(); ++v) {
    const ViewRegistration& r = plan.registration->views[v];
    Link& link = links_[v];
    const std::vector<Vec3> positions = markerPositions(plan, orientation[v], v);
    for (int m : r.markers)
      if (m >= 0 && static_cast<std::size_t>(m) < positions.size())
        link.seen[m] = positions[static_cast<std::size_t>(m)];
    if (!errors[v].placed) continue;
    if (errors[v].adjusted && errors[v].parent) {  // placed by its group's fit
      const auto same = std::find_if(by_factor.begin(), by_factor.end(), [&](const auto& f) {
        return f.first == errors[v].adjusted.get();
      });
      std::size_t group = groups_.size();
      if (same != by_factor.end()) {
        group = same->second;
      } else {
        by_factor.push_back({errors[v].adjusted.get(), group});
        groups_.push_back({{*errors[v].parent}, 0, {}, errors[v].adjusted});
      }
      groups_[group].views.push_back(v);
    } else if (r.method == RegistrationMethod::ReferencePoints) {
      link.kind = Kind::Known;
    } else if (r.method == RegistrationMethod::Icp || r.method == RegistrationMethod::Robot ||
               r.method == RegistrationMethod::Markers) {  // markers: a link across setups
      link.kind = Kind::Drawn;
      link.root = squareRoot(errors[v].link);
      link.bias = errors[v].bias;
    }
  }
  for (Group& group : groups_) indexMarkers(group);
}

void SimulatedRegistration::indexMarkers(Group& group) const {
  std::map<int, std::size_t> count;  // views of the group seeing each marker
  for (std::size_t v : group.views)
    for (const auto& [m, at] : links_[v].seen) ++count[m];
  std::map<int, std::size_t> index;
  for (const auto& [m, c] : count)
    if (c >= 2) index.emplace(m, index.size());
  group.markers = index.size();
  for (std::size_t v : group.views) {
    group.seen.emplace_back();
    for (const auto& [m, at] : links_[v].seen)
      if (const auto found = index.find(m); found != index.end())
        group.seen.back().push_back({found->second, m});
  }
}

std::vector<Pose> SimulatedRegistration::start(const Group& group, const Measured& measured) const {
  // Each marker's centres pull the views that see it towards their mean: the gradient of
  // the fit's squares at the nominal poses, then the normal equations' solution through
  // the group's covariance (sigma² times their inverse).
  std::vector<Vec3> mean(group.markers, Vec3::Zero());
  std::vector<double> count(group.markers, 0);
  for (std::size_t i = 0; i < group.views.size(); ++i)
    for (const auto& [k, m] : group.seen[i]) {
      mean[k] += measured[group.views[i]].at(m) - links_[group.views[i]].seen.at(m);
      ++count[k];
    }
  for (std::size_t k = 0; k < group.markers; ++k) mean[k] /= count[k];
  Eigen::VectorXd pull = Eigen::VectorXd::Zero(group.factor->rows());
  for (std::size_t i = 1; i < group.views.size(); ++i) {
    const std::size_t v = group.views[i];
    for (const auto& [k, m] : group.seen[i])
      pull.segment<6>(static_cast<Eigen::Index>(6 * slots_[v])) +=
          motionAt(links_[v].seen.at(m)).transpose() *
          (mean[k] - (measured[v].at(m) - links_[v].seen.at(m)));
  }
  const Eigen::MatrixXd& f = *group.factor;
  const Eigen::VectorXd twists = f * (f.transpose() * pull) / (sigma_ * sigma_);
  std::vector<Pose> pose(group.views.size(), Pose::Identity());
  for (std::size_t i = 1; i < group.views.size(); ++i)
    pose[i] = poseOf(twists.segment<6>(static_cast<Eigen::Index>(6 * slots_[group.views[i]])));
  return pose;
}

// From the first-order start, block coordinate descent on the group's least squares:
// each marker's position the mean of where the views put its centre, then each view's
// pose the rigid fit of its centres onto those positions, until no centre moves by 1e-7 mm
// (at most kMostRounds rounds).
void SimulatedRegistration::adjust(const Group& group, const Measured& measured,
                                   std::vector<Pose>& own) const {
  constexpr int kMostRounds = 200;
  std::vector<Pose> pose = start(group, measured);  // the root's stays
  for (int round = 0; round < kMostRounds; ++round) {
    std::vector<Vec3> sum(group.markers, Vec3::Zero());
    std::vector<double> count(group.markers, 0);
    for (std::size_t i = 0; i < group.views.size(); ++i)
      for (const auto& [k, m] : group.seen[i]) {
        sum[k] += pose[i] * measured[group.views[i]].at(m);
        ++count[k];
      }
    double moved = 0;
    for (std::size_t i = 1; i < group.views.size(); ++i) {
      std::vector<Vec3> mine, mean;
      for (const auto& [k, m] : group.seen[i]) {
        mine.push_back(measured[group.views[i]].at(m));
        mean.push_back(sum[k] / count[k]);
      }
      if (mine.size() < 3) continue;
      const Pose fitted = rigidFit(mine, mean);
      for (const Vec3& p : mine) moved = std::max(moved, (fitted * p - pose[i] * p).norm());
      pose[i] = fitted;
    }
    if (moved < 1e-7) break;
  }
  for (std::size_t i = 1; i < group.views.size(); ++i) own[group.views[i]] = pose[i];
}

std::vector<Pose> SimulatedRegistration::draw(std::mt19937_64& random,
                                              const std::vector<std::optional<Pose>>& links) const {
  std::normal_distribution<double> normal;
  const std::size_t n = links_.size();
  Measured measured(n);
  std::vector<Pose> own(n, Pose::Identity());
  for (std::size_t v = 0; v < n; ++v) {
    for (const auto& [m, at] : links_[v].seen) {
      const Vec3 noise(normal(random), normal(random), normal(random));
      measured[v][m] = at + sigma_ * noise;
    }
    Twist z;
    for (int i = 0; i < 6; ++i) z[i] = normal(random);
    if (links_[v].kind == Kind::Drawn)
      own[v] =
          v < links.size() && links[v] ? *links[v] : poseOf(links_[v].bias + links_[v].root * z);
    if (links_[v].kind == Kind::Known) {
      std::vector<Vec3> mine, known;
      for (const auto& [m, at] : links_[v].seen) {
        mine.push_back(measured[v].at(m));
        known.push_back(at);
      }
      if (mine.size() >= 3) own[v] = rigidFit(mine, known);
    }
  }
  for (const Group& group : groups_) adjust(group, measured, own);
  std::vector<Pose> placed(n, Pose::Identity());
  for (std::size_t v : chains_.order) {
    const std::optional<std::size_t>& parent = chains_.parents[v];
    placed[v] = parent ? placed[*parent] * own[v] : own[v];
  }
  return placed;
}

}  // namespace scanplan::detail
