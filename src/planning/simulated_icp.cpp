#include "planning/simulated_icp.h"

#include "registration/rigid_fit.h"

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <random>

namespace scanplan::detail {
namespace {

constexpr std::size_t kLeastPoints = 100;  // fewer overlapping points: not registered
// A point's correspondence is the nearest point of the faces of this many designed points
// nearest it, as a dense fixed cloud's nearest point; its residual lies along the normal
// there (point to plane).
constexpr std::size_t kCandidates = 6;
// The coarse stages step on every fourth point until a step moves the cloud by less than
// kCoarseEnd mm; the last on every point, until a step moves it by less than kConverged mm;
// each stage at most kMostSteps steps.
constexpr std::size_t kCoarseStride = 4;
constexpr double kCoarseEnd = 0.01;
constexpr double kConverged = 1e-6;
constexpr int kMostSteps = 30;

// A unit vector in a random direction.
Vec3 direction(std::mt19937_64& random) {
  std::normal_distribution<double> normal;
  Vec3 d(normal(random), normal(random), normal(random));
  return d.normalized();
}

// The motion of `twist` about `centre`.
Pose about(const Twist& twist, const Vec3& centre) {
  return Eigen::Translation3d(centre) * poseOf(twist) * Eigen::Translation3d(-centre);
}

}  // namespace

// Every designed point with its face, in one tree.
struct SimulatedIcp::Designed {
  std::vector<Vec3> points;
  std::vector<int> faces;
  PointCloudAdaptor adaptor{points};
  std::unique_ptr<PointTree> tree;
};

SimulatedIcp::SimulatedIcp(const Nominal& nominal, const RegistrationOptions& options,
                           double spacing)
    : nominal_(nominal),
      designed_(std::make_unique<Designed>()),
      options_(options),
      spacing_(spacing) {
  for (const auto& [id, face] : nominal.faces()) {
    designed_->points.insert(designed_->points.end(), face.points.begin(), face.points.end());
    designed_->faces.insert(designed_->faces.end(), face.points.size(), id);
  }
  designed_->tree = std::make_unique<PointTree>(3, designed_->adaptor,
                                                nanoflann::KDTreeSingleIndexAdaptorParams(16));
  designed_->tree->buildIndex();
}

SimulatedIcp::~SimulatedIcp() = default;

SimulatedIcp::Step SimulatedIcp::step(const std::vector<Vec3>& moved,
                                      const std::vector<double>& noise, const Pose& pose,
                                      const Vec3& centre, const FixedSurface& surface,
                                      double cutoff) const {
  TwistCovariance normal = TwistCovariance::Zero();
  Twist pull = Twist::Zero();
  Step result;
  for (std::size_t i = 0; i < moved.size(); ++i) {
    const Vec3 p = pose * moved[i];
    std::array<unsigned, kCandidates> index{};
    std::array<double, kCandidates> squared{};
    const std::size_t found =
        designed_->tree->knnSearch(p.data(), kCandidates, index.data(), squared.data());
    std::optional<SurfacePoint> best;
    for (std::size_t k = 0; k < found; ++k) {
      const int face = designed_->faces[index[k]];
      if (std::find_if(index.begin(), index.begin() + static_cast<std::ptrdiff_t>(k),
                       [&](unsigned j) { return designed_->faces[j] == face; }) !=
          index.begin() + static_cast<std::ptrdiff_t>(k))
        continue;  // that face's surface is done
      const SurfacePoint on = nominal_.closest(face, p);
      if (!best || (p - on.position).norm() < (p - best->position).norm()) best = on;
    }
    if (!best || (p - best->position).norm() > cutoff) continue;
    const Vec3 &at = best->position, &n = best->normal;
    const double distance = n.dot(p - at);
    const SurfaceOffset offset = surface(at, n);
    const double residual = distance - (offset.shift + offset.sigma * noise[i]);
    const Eigen::Matrix<double, 1, 6> row = alongNormal(p - centre, n);
    normal += row.transpose() * row;
    pull -= row.transpose() * residual;
    ++result.used;
  }
  if (result.used < kLeastPoints / kCoarseStride) return result;
  result.twist = heldInverse(normal) * pull;
  return result;
}

std::optional<Pose> SimulatedIcp::link(const std::vector<Vec3>& moved, const FixedSurface& surface,
                                       std::uint64_t seed) const {
  if (moved.size() < kLeastPoints || designed_->points.empty()) return std::nullopt;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : moved) centre += p;
  centre /= static_cast<double>(moved.size());
  double radius = 0;
  for (const Vec3& p : moved) radius = std::max(radius, (p - centre).norm());

  // The start: the robot's placement, off by the registration's perturbation.
  std::mt19937_64 random(seed);
  const Vec3 axis = direction(random), shift = direction(random);
  Pose pose = Pose::Identity();
  pose.linear() = Eigen::AngleAxisd(radians(options_.perturbation_angle), axis).toRotationMatrix();
  pose.translation() = centre - pose.linear() * centre + options_.perturbation * shift;
  std::normal_distribution<double> unit;
  std::vector<double> noise(moved.size());
  for (double& z : noise) z = unit(random);

  // Coarse to fine, as the registration's ICP (registration/icp.cpp): correspondences
  // within twice the start's largest displacement, then within that displacement (at least
  // twice the fine distance), on every fourth point; then within twice the fine distance,
  // a spacing and a half, on every point.
  const double largest = options_.perturbation + radians(options_.perturbation_angle) * radius;
  const double fine = 1.5 * spacing_;
  std::vector<Vec3> coarse;
  std::vector<double> coarse_noise;
  for (std::size_t i = 0; i < moved.size(); i += kCoarseStride) {
    coarse.push_back(moved[i]);
    coarse_noise.push_back(noise[i]);
  }
  for (const double cutoff : {2 * largest, std::max(largest, 2 * fine), 2 * fine}) {
    const bool last = cutoff == 2 * fine;
    for (int k = 0; k < kMostSteps; ++k) {
      const Vec3 now = pose * centre;  // the twists are about the cloud's centre
      const Step s = last ? step(moved, noise, pose, now, surface, cutoff)
                          : step(coarse, coarse_noise, pose, now, surface, cutoff);
      if (s.used == 0 || s.twist.isZero()) break;
      pose = about(s.twist, now) * pose;
      const double moved_by = s.twist.tail<3>().norm() + s.twist.head<3>().norm() * radius;
      if (moved_by < (last ? kConverged : kCoarseEnd)) break;
    }
  }
  return pose;
}

}  // namespace scanplan::detail
