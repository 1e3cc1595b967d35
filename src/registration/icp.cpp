// Verification of a registration pair by real ICP (Open3D) between simulated clouds.

#include "registration/icp_stage.h"

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

// The two nearest points within a distance: a nanoflann result set that prunes the search
// by the second best distance found so far, starting from the limit.
struct TwoNearestWithin {
  double best, second;  // squared
  unsigned index = 0;
  bool found = false;
  std::size_t size() const { return found ? 1 : 0; }
  bool full() const { return true; }
  bool addPoint(double squared, unsigned i) {
    if (found && i == index) return true;  // the point the search started from, met again
    if (squared < best) {
      second = best;
      best = squared;
      index = i;
      found = true;
    } else if (squared < second) {
      second = squared;
    }
    return true;
  }
  double worstDist() const { return second; }
};

// Each source point's nearest fixed point within `distance`; the result's fitness and
// inlier RMSE as Open3D computes them. `found`, per source point, what its last search
// found: a point whose nearest then is nearer now than every other fixed point can be
// (others - moved) keeps it without a search; a search starts from it, which bounds where
// the nearest lies. The nearest is the same as a search from scratch finds.
registration::RegistrationResult match(const detail::IndexedCloud& fixed,
                                       const open3d::geometry::PointCloud& source, double distance,
                                       std::vector<detail::Found>& found) {
  constexpr double kMargin = 1e-9;  // mm: rounding never keeps a nearest that is not
  const double limit = distance * distance;
  registration::RegistrationResult result;
  double squares = 0;
  const auto take = [&](std::size_t i, int j, double squared) {
    result.correspondence_set_.emplace_back(static_cast<int>(i), j);
    squares += squared;
  };
  const auto points = static_cast<int>(fixed.cloud.points.size());
  for (std::size_t i = 0; i < source.points_.size(); ++i) {
    const double* point = source.points_[i].data();
    detail::Found& last = found[i];
    TwoNearestWithin nearest{limit, limit};
    if (last.nearest >= 0) {
      const auto j = static_cast<unsigned>(last.nearest);
      const double squared = fixed.tree.distance.evalMetric(point, j, 3);
      if (std::sqrt(squared) + kMargin <= last.others - last.moved) {
        if (squared < limit) take(i, last.nearest, squared);
        continue;
      }
    }
    // The search starts from the fixed point found last, or else from the one the source
    // point before found (the clouds' points lie row by row), and from those beside it.
    const int from = last.nearest >= 0 ? last.nearest : i > 0 ? found[i - 1].nearest : -1;
    if (from >= 0)
      for (int j = std::max(from - 1, 0); j <= std::min(from + 1, points - 1); ++j)
        nearest.addPoint(fixed.tree.distance.evalMetric(point, static_cast<unsigned>(j), 3),
                         static_cast<unsigned>(j));
    fixed.tree.findNeighbors(nearest, point, nanoflann::SearchParams());
    last = {nearest.found ? static_cast<int>(nearest.index) : -1, std::sqrt(nearest.second), 0};
    if (nearest.found) take(i, last.nearest, nearest.best);
  }
  const std::size_t n = result.correspondence_set_.size();
  result.fitness_ = static_cast<double>(n) / static_cast<double>(source.points_.size());
  result.inlier_rmse_ = n ? std::sqrt(squares / static_cast<double>(n)) : 0;
  return result;
}

// Moves `source` by `update`, adding each point's displacement to what it has `found`.
void moveBy(const Eigen::Matrix4d& update, open3d::geometry::PointCloud& source,
            std::vector<detail::Found>& found) {
  const Eigen::Matrix3d rotation = update.topLeftCorner<3, 3>();
  const Vec3 shift = update.topRightCorner<3, 1>();
  for (std::size_t i = 0; i < source.points_.size(); ++i) {
    const Vec3& p = source.points_[i];
    found[i].moved += (rotation * p + shift - p).norm();
  }
  source.Transform(update);
}

// What the `coarse` cloud's points `found`, for the same points of the whole `source`
// (every kIcpCoarseStride-th), with how far apart the two stand added to their motion.
std::vector<detail::Found> onTheWhole(const std::vector<detail::Found>& found,
                                      const open3d::geometry::PointCloud& coarse,
                                      const open3d::geometry::PointCloud& source) {
  std::vector<detail::Found> whole(source.points_.size());
  for (std::size_t k = 0; k < found.size(); ++k) {
    const std::size_t i = k * detail::kIcpCoarseStride;
    whole[i] = found[k];
    whole[i].moved += (source.points_[i] - coarse.points_[k]).norm();
  }
  return whole;
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

registration::RegistrationResult icpStage(const IndexedCloud& fixed,
                                          const open3d::geometry::PointCloud& target,
                                          open3d::geometry::PointCloud& source, double distance,
                                          Eigen::Matrix4d& transformation,
                                          std::vector<Found>& found) {
  const registration::TransformationEstimationPointToPlane estimation(
      std::make_shared<registration::TukeyLoss>(kTukey * distance));
  registration::RegistrationResult result = match(fixed, source, distance, found);
  for (int iteration = 0; iteration < 30; ++iteration) {
    const Eigen::Matrix4d update =
        estimation.ComputeTransformation(source, target, result.correspondence_set_);
    transformation = update * transformation;
    moveBy(update, source, found);
    const registration::RegistrationResult before = std::move(result);
    result = match(fixed, source, distance, found);
    if (std::abs(before.fitness_ - result.fitness_) < 1e-4 &&
        std::abs(before.inlier_rmse_ - result.inlier_rmse_) < 1e-4)
      break;
  }
  return result;
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
  // What each point's searches found carries from stage to stage.
  std::vector<Found> found(coarse.points_.size());
  for (const double distance : {2 * largest, std::max(largest, 2 * fine), 2 * fine})
    icpStage(indexed, target, coarse, distance, estimate, found);
  source.Transform(estimate);
  std::vector<Found> on_whole = onTheWhole(found, coarse, source);
  result = icpStage(indexed, target, source, fine, estimate, on_whole);
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
