// The dense part of the candidate pool (docs/planning.md): poses in rings around anchor
// samples spread over the targets, and shifted poses.

#include "planning/stages.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace scanplan::detail {
namespace {

// Up to `count` samples (not done elsewhere) spread over the targets: decimated (sampling.h)
// with a like normal within 60°, the radius starting at a twelfth of the field of view
// and grown until few enough remain.
std::vector<SurfacePoint> anchorSamples(const Placement& at, std::size_t count) {
  if (count == 0) return {};
  std::vector<Sample> targets;
  for (std::size_t i = 0; i < at.points.size(); ++i)
    if (!at.isDone(i)) {
      Sample sample;
      sample.position = at.points[i].position;
      sample.normal = at.points[i].normal;
      sample.face = at.points[i].face;
      targets.push_back(sample);
    }
  const Scanner& scanner = at.scanner();
  double radius = std::min(scanner.fov_width, scanner.fov_height) / 12;
  for (;;) {
    const std::vector<Sample> anchors = decimate(targets, radius, 60);
    if (anchors.size() <= count) {
      std::vector<SurfacePoint> points;
      for (const Sample& s : anchors) points.push_back({s.position, s.normal, s.face});
      return points;
    }
    radius *= 1.3;
  }
}

// The poses of one anchor: in rings around its normal within the cone camera and projector
// both keep, and the normal poses shifted a third of the field of view to four sides.
std::vector<View> anchorPoses(const Placement& at, const SurfacePoint& anchor) {
  const Scanner& scanner = at.scanner();
  const double cone = plannerVisibility(scanner, at.settings().vm_step, true).cone;
  const int rotations = at.settings().pool_rotations;
  std::vector<View> poses = ringPoses(scanner, anchor, {20, 40}, cone - 5, rotations);
  const double step = std::min(scanner.fov_width, scanner.fov_height) / 3;
  for (int r = 0; r < rotations; ++r) {
    const Eigen::Matrix3d axes = poses[r].camera_to_world.linear();
    for (const Vec3& shift : {Vec3(step * axes.col(0)), Vec3(-step * axes.col(0)),
                              Vec3(step * axes.col(1)), Vec3(-step * axes.col(1))})
      poses.push_back(shiftedPose(poses[r], shift));
  }
  return poses;
}

}  // namespace

std::vector<View> densePool(const Placement& at, const Progress& progress) {
  const auto anchors = anchorSamples(at, static_cast<std::size_t>(at.settings().anchors));
  report(progress, "dense poses at " + std::to_string(anchors.size()) + " anchors", 0);
  std::vector<View> poses;
  for (const SurfacePoint& anchor : anchors) {
    const std::vector<View> mine = anchorPoses(at, anchor);
    poses.insert(poses.end(), mine.begin(), mine.end());
  }
  std::vector<char> valid(poses.size());
  tbb::parallel_for(std::size_t{0}, poses.size(), [&](std::size_t k) {
    valid[k] = poseIsValid(at.simulator, poses[k], at.cell);
  });
  std::vector<View> kept;
  for (std::size_t k = 0; k < poses.size(); ++k)
    if (valid[k]) kept.push_back(poses[k]);
  return kept;
}

}  // namespace scanplan::detail
