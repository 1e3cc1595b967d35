#include "planning/simulated_icp.h"

#include "registration/icp.h"
#include "registration/rigid_fit.h"

#include <scanplan/scanner/simulation.h>

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <random>

namespace scanplan::detail {
namespace {

// A point's correspondence is the nearest point of the faces of this many designed points
// nearest it (and its own), as a dense fixed cloud's nearest point; its residual lies along
// the normal there (point to plane).
constexpr std::size_t kCandidates = 6;
// The coarse stages step on every kIcpCoarseStride-th point until a step moves the cloud by
// less than kCoarseEnd mm; the last on every point, until a step moves it by less than
// kConverged mm; each stage at most kMostSteps steps.
constexpr double kCoarseEnd = 0.01;
constexpr double kConverged = 1e-6;
constexpr int kMostSteps = 30;
// A point of a face's exact surface lies on the face where it is within twice the mesh's
// chordal tolerance, and this, of the face's triangles.
constexpr double kNominalGap = 0.1;

// The motion of `twist` about `centre`.
Pose about(const Twist& twist, const Vec3& centre) {
  return Eigen::Translation3d(centre) * poseOf(twist) * Eigen::Translation3d(-centre);
}

}  // namespace

// Every designed point with its face and its face's curvature there, in one tree.
struct SimulatedIcp::Designed {
  std::vector<Vec3> points;
  std::vector<int> faces;
  std::vector<double> curvatures;
  PointCloudAdaptor adaptor{points};
  std::unique_ptr<PointTree> tree;
};

SurfaceOffset fixedPoints(const Scanner& scanner, const View& fixed, const View& moved,
                          const Vec3& at, const Vec3& normal) {
  const PointQuality there = pointQuality(scanner, fixed, at, normal);
  return {0,
          there.along_normal *
              std::sqrt(pointQuality(scanner, moved, at, normal).density / there.density),
          1 / there.density};
}

SimulatedIcp::SimulatedIcp(const Nominal& nominal, const RegistrationOptions& options,
                           double chordal)
    : nominal_(nominal),
      bounds_(2 * chordal + kNominalGap),
      designed_(std::make_unique<Designed>()),
      options_(options) {
  for (const auto& [id, face] : nominal.faces()) {
    designed_->points.insert(designed_->points.end(), face.points.begin(), face.points.end());
    designed_->faces.insert(designed_->faces.end(), face.points.size(), id);
    for (const Vec3& p : face.points) designed_->curvatures.push_back(nominal.curvature(id, p));
  }
  designed_->tree = std::make_unique<PointTree>(3, designed_->adaptor,
                                                nanoflann::KDTreeSingleIndexAdaptorParams(16));
  designed_->tree->buildIndex();
}

SimulatedIcp::~SimulatedIcp() = default;

std::optional<SurfacePoint> SimulatedIcp::correspondence(const Vec3& p, int own) const {
  std::array<unsigned, kCandidates> index{};
  std::array<double, kCandidates> squared{};
  const std::size_t found =
      designed_->tree->knnSearch(p.data(), kCandidates, index.data(), squared.data());
  std::optional<SurfacePoint> best;
  std::array<int, kCandidates + 1> seen{};
  std::size_t seen_count = 0;
  const auto consider = [&](int candidate) {
    const auto end = seen.begin() + static_cast<std::ptrdiff_t>(seen_count);
    if (std::find(seen.begin(), end, candidate) != end || !nominal_.face(candidate)) return;
    seen[seen_count++] = candidate;
    std::optional<SurfacePoint> on = nominal_.onExact(candidate, p);
    const bool exact = on.has_value();
    if (!exact) on = nominal_.onTriangles(candidate, p);
    if (!on || (best && (p - on->position).norm() >= (p - best->position).norm())) return;
    // Not where the exact surface runs on past the face's edges.
    if (exact && !nominal_.withinBounds(candidate, on->position, bounds_)) return;
    best = on;
  };
  consider(own);
  for (std::size_t k = 0; k < found; ++k) consider(designed_->faces[index[k]]);
  return best;
}

double SimulatedIcp::footprintCurvature(const Vec3& p, int own, double spacing) const {
  const double radius = spacing / std::sqrt(std::numbers::pi);
  Neighbours near;
  designed_->tree->radiusSearch(p.data(), radius * radius, near, nanoflann::SearchParams());
  if (near.empty()) return nominal_.curvature(own, p);
  double sum = 0;
  for (const auto& [k, squared] : near) sum += designed_->curvatures[k];
  return sum / static_cast<double>(near.size());
}

SimulatedIcp::Step SimulatedIcp::step(const std::vector<Moved>& moved, const Pose& pose,
                                      const Vec3& centre, const FixedSurface& surface,
                                      double cutoff) const {
  TwistCovariance normal = TwistCovariance::Zero();
  Twist pull = Twist::Zero();
  Step result;
  for (const Moved& m : moved) {
    const Vec3 p = pose * m.at.position;
    const std::optional<SurfacePoint> best = correspondence(p, m.at.face);
    if (!best) continue;
    const Vec3 &at = best->position, &n = best->normal;
    const double distance = n.dot(p - at);
    if (std::abs(distance) > cutoff) continue;
    const SurfaceOffset offset = surface(at, n);
    const double shift = offset.shift + samplingShift(m.curvature, offset.area);
    const double residual = distance - (shift + offset.sigma * m.noise);
    const double tukey = kTukey * cutoff;
    if (std::abs(residual) >= tukey) continue;
    const double weight =
        (1 - residual * residual / (tukey * tukey)) * (1 - residual * residual / (tukey * tukey));
    const Eigen::Matrix<double, 1, 6> row = alongNormal(p - centre, n);
    normal += weight * row.transpose() * row;
    pull -= weight * row.transpose() * residual;
    ++result.used;
  }
  if (result.used < kIcpLeastPoints / kIcpCoarseStride) return result;
  result.twist = heldInverse(normal) * pull;
  return result;
}

std::optional<Pose> SimulatedIcp::link(const std::vector<SurfacePoint>& moved,
                                       const FixedSurface& surface, double spacing,
                                       std::uint64_t seed) const {
  if (moved.size() < kIcpLeastPoints || designed_->points.empty()) return std::nullopt;
  Vec3 centre = Vec3::Zero();
  for (const SurfacePoint& p : moved) centre += p.position;
  centre /= static_cast<double>(moved.size());
  double radius = 0;
  for (const SurfacePoint& p : moved) radius = std::max(radius, (p.position - centre).norm());

  // The start: the robot's placement, off by the registration's perturbation.
  std::mt19937_64 random(seed);
  Pose pose = perturbation(centre, options_.perturbation, options_.perturbation_angle, random);
  std::normal_distribution<double> unit;
  std::vector<Moved> points;
  for (const SurfacePoint& p : moved)
    points.push_back({p, unit(random), footprintCurvature(p.position, p.face, spacing)});

  // Coarse to fine, as the registration's ICP (registration/icp.cpp): correspondences
  // within twice the start's largest displacement, then within that displacement (at least
  // twice the fine distance), on every fourth point; then within twice the fine distance,
  // a spacing and a half, on every point.
  const double largest = options_.perturbation + radians(options_.perturbation_angle) * radius;
  const double fine = 1.5 * spacing;
  std::vector<Moved> coarse;
  for (std::size_t i = 0; i < points.size(); i += kIcpCoarseStride) coarse.push_back(points[i]);
  const std::array<double, 3> cutoffs{2 * largest, std::max(largest, 2 * fine), 2 * fine};
  for (std::size_t stage = 0; stage < cutoffs.size(); ++stage) {
    const double cutoff = cutoffs[stage];
    const bool last = stage + 1 == cutoffs.size();
    for (int k = 0; k < kMostSteps; ++k) {
      const Vec3 now = pose * centre;  // the twists are about the cloud's centre
      const Step s = step(last ? points : coarse, pose, now, surface, cutoff);
      if (s.used == 0 || s.twist.isZero()) break;
      pose = about(s.twist, now) * pose;
      const double moved_by = s.twist.tail<3>().norm() + s.twist.head<3>().norm() * radius;
      if (moved_by < (last ? kConverged : kCoarseEnd)) break;
    }
  }
  return pose;
}

}  // namespace scanplan::detail
