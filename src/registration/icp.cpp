// Verification of a registration pair by real ICP (Open3D) between simulated clouds.

#include "registration/icp.h"

#include <open3d/geometry/PointCloud.h>
#include <open3d/pipelines/registration/Registration.h>
#include <open3d/pipelines/registration/RobustKernel.h>
#include <open3d/pipelines/registration/TransformationEstimation.h>

#include <omp.h>

#include <algorithm>
#include <cmath>
#include <random>

namespace scanplan {
namespace {

namespace registration = open3d::pipelines::registration;

// The `points` within `margin` of the box around `to`.
std::vector<Vec3> near(const std::vector<Vec3>& points, const std::vector<Vec3>& to,
                       double margin) {
  Box box;
  for (const Vec3& p : to) box.add(p);
  box.min.array() -= margin;
  box.max.array() += margin;
  std::vector<Vec3> result;
  for (const Vec3& p : points)
    if ((p.array() >= box.min.array()).all() && (p.array() <= box.max.array()).all())
      result.push_back(p);
  return result;
}

// Open3D's ICP splits its sums over OpenMP threads, which makes
// their results depend on the load. Checks run in parallel over pairs (oneTBB) instead:
// each keeps its own sums on the thread that runs it, and gives the same result every run.
void oneThread() { omp_set_num_threads(1); }

// The nearest point within a distance: a nanoflann result set that prunes the search
// by the best distance found so far, starting from the limit.
struct NearestWithin {
  double best;  // squared
  unsigned index = 0;
  bool found = false;
  std::size_t size() const { return found ? 1 : 0; }
  bool full() const { return true; }
  bool addPoint(double squared, unsigned i) {
    if (squared < best) {
      best = squared;
      index = i;
      found = true;
    }
    return true;
  }
  double worstDist() const { return best; }
};

// Each source point's nearest fixed point within `distance`; the result's fitness and
// inlier RMSE as Open3D computes them. `before`, the correspondences of the source's last
// match: a point's fixed point then bounds where its nearest lies now, which the search
// starts from. The nearest is the same, found sooner.
registration::RegistrationResult match(const detail::IndexedCloud& fixed,
                                       const open3d::geometry::PointCloud& source, double distance,
                                       const registration::CorrespondenceSet& before = {}) {
  std::vector<int> partner(source.points_.size(), -1);
  for (const Eigen::Vector2i& c : before) partner[static_cast<std::size_t>(c[0])] = c[1];
  registration::RegistrationResult result;
  double squares = 0;
  for (std::size_t i = 0; i < source.points_.size(); ++i) {
    const double* point = source.points_[i].data();
    NearestWithin nearest{distance * distance};
    if (partner[i] >= 0) {
      const auto j = static_cast<unsigned>(partner[i]);
      const double squared = fixed.tree.distance.evalMetric(point, j, 3);
      if (squared < nearest.best) nearest = {squared, j, true};
    }
    fixed.tree.findNeighbors(nearest, point, nanoflann::SearchParams());
    if (!nearest.found) continue;
    result.correspondence_set_.emplace_back(static_cast<int>(i), static_cast<int>(nearest.index));
    squares += nearest.best;
  }
  const std::size_t n = result.correspondence_set_.size();
  result.fitness_ = static_cast<double>(n) / static_cast<double>(source.points_.size());
  result.inlier_rmse_ = n ? std::sqrt(squares / static_cast<double>(n)) : 0;
  return result;
}

// Open3D's RegistrationICP, point to plane with Tukey's weights, at most 30 iterations,
// stopping when fitness and RMSE change by less than 1e-4 (0.1 µm of RMSE); but against
// the fixed cloud's tree made once, instead of again at every call. `source` is moved along, and
// the motion is added to `transformation`.
registration::RegistrationResult icp(const detail::IndexedCloud& fixed,
                                     const open3d::geometry::PointCloud& target,
                                     open3d::geometry::PointCloud& source, double distance,
                                     Eigen::Matrix4d& transformation) {
  const registration::TransformationEstimationPointToPlane estimation(
      std::make_shared<registration::TukeyLoss>(detail::kTukey * distance));
  registration::RegistrationResult result = match(fixed, source, distance);
  for (int iteration = 0; iteration < 30; ++iteration) {
    const Eigen::Matrix4d update =
        estimation.ComputeTransformation(source, target, result.correspondence_set_);
    transformation = update * transformation;
    source.Transform(update);
    const registration::RegistrationResult before = std::move(result);
    result = match(fixed, source, distance, before.correspondence_set_);
    if (std::abs(before.fitness_ - result.fitness_) < 1e-4 &&
        std::abs(before.inlier_rmse_ - result.inlier_rmse_) < 1e-4)
      break;
  }
  return result;
}

}  // namespace

namespace detail {

Pose perturbation(const Vec3& centre, double distance, double angle, std::mt19937_64& random) {
  std::normal_distribution<double> normal(0.0, 1.0);
  auto direction = [&] {
    Vec3 d(normal(random), normal(random), normal(random));
    return Vec3(d.normalized());
  };
  Pose motion = Pose::Identity();
  const Vec3 axis = direction(), shift = direction();
  motion.linear() = Eigen::AngleAxisd(radians(angle), axis).toRotationMatrix();
  motion.translation() = centre - motion.linear() * centre + distance * shift;
  return motion;
}

IndexedCloud::IndexedCloud(IcpCloud made)
    : cloud(std::move(made)), tree(3, adaptor, nanoflann::KDTreeSingleIndexAdaptorParams(16)) {
  tree.buildIndex();
}

}  // namespace detail

double icpCloudSpacing(const RegistrationOptions& options, const Scanner& scanner) {
  return options.cloud_spacing > 0 ? options.cloud_spacing : scanner.fov_height / 150;
}

IcpCloud icpCloud(const Simulator& simulator, const View& view,
                  const RegistrationOptions& options) {
  const double spacing = icpCloudSpacing(options, simulator.scanner());
  IcpCloud cloud;
  cloud.id = view.id;
  PointCloud simulated = simulator.cloud(view, options.seed, spacing);
  cloud.points = std::move(simulated.points);
  cloud.normals = std::move(simulated.normals);
  return cloud;
}

IcpCheck checkIcp(const Simulator& simulator, const View& fixed, const View& moved,
                  const RegistrationOptions& options) {
  return checkIcp(simulator, icpCloud(simulator, fixed, options),
                  icpCloud(simulator, moved, options), options);
}

IcpCheck checkIcp(const Simulator& simulator, const IcpCloud& fixed, const IcpCloud& moved,
                  const RegistrationOptions& options) {
  return detail::checkIcp(simulator, detail::IndexedCloud(fixed), moved, options);
}

IcpCheck detail::checkIcp(const Simulator& simulator, const IndexedCloud& indexed,
                          const IcpCloud& moved, const RegistrationOptions& options) {
  oneThread();
  const IcpCloud& fixed = indexed.cloud;
  const Scanner& scanner = simulator.scanner();
  const double spacing = icpCloudSpacing(options, simulator.scanner());
  IcpCheck check;
  check.points = moved.points.size();
  if (fixed.points.size() < detail::kIcpLeastPoints ||
      moved.points.size() < detail::kIcpLeastPoints)
    return check;

  open3d::geometry::PointCloud target, source;
  target.points_ = fixed.points;
  target.normals_ = fixed.normals;
  Vec3 centre = Vec3::Zero();
  for (const Vec3& p : moved.points) centre += p;
  centre /= static_cast<double>(moved.points.size());
  double radius = 0;
  for (const Vec3& p : moved.points) radius = std::max(radius, (p - centre).norm());
  const double largest = options.perturbation + radians(options.perturbation_angle) * radius;
  // Only points that can find a correspondence take part: those within the widest search
  // distance, plus the perturbation, of the fixed cloud's box.
  source.points_ = near(moved.points, fixed.points, 3 * largest);
  if (source.points_.size() < detail::kIcpLeastPoints) return check;
  std::mt19937_64 random(options.seed * 7919 + static_cast<std::uint64_t>(fixed.id) * 131 +
                         static_cast<std::uint64_t>(moved.id));
  const Eigen::Matrix4d start =
      perturbation(centre, options.perturbation, options.perturbation_angle, random).matrix();
  source.Transform(start);

  // Point-to-plane against the fixed cloud's surface normals, which a scanner's dense
  // cloud gives to within its noise. Coarse to fine: correspondences first within twice
  // the largest displacement the perturbation causes, then down to one and a half point
  // spacings (plus noise), where points past the edge of the overlap no longer pull.
  const double fine = 1.5 * spacing + 3 * scanner.noise_sigma;
  Eigen::Matrix4d estimate = Eigen::Matrix4d::Identity();
  registration::RegistrationResult result;
  open3d::geometry::PointCloud coarse;
  for (std::size_t i = 0; i < source.points_.size(); i += detail::kIcpCoarseStride)
    coarse.points_.push_back(source.points_[i]);
  for (const double distance : {2 * largest, std::max(largest, 2 * fine), 2 * fine})
    icp(indexed, target, coarse, distance, estimate);
  source.Transform(estimate);
  result = icp(indexed, target, source, fine, estimate);
  // Where the registered cloud ends up against where it belongs.
  const Pose residual(estimate * start);
  double squares = 0, largest_error = 0;
  for (const Vec3& p : moved.points) {
    const double e = (residual * p - p).norm();
    squares += e * e;
    largest_error = std::max(largest_error, e);
  }
  check.error = std::sqrt(squares / static_cast<double>(moved.points.size()));
  check.max_error = largest_error;
  check.rotation = degrees(Eigen::AngleAxisd(residual.linear()).angle());
  check.fitness = result.fitness_;
  check.rmse = result.inlier_rmse_;
  check.passed = check.error <= options.tolerance;
  return check;
}

}  // namespace scanplan
