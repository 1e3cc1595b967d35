// The dense part of the candidate pool (docs/planning.md): poses in rings around anchor
// samples spread over the targets, and shifted poses.

#include "planning/stages.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>

namespace scanplan::detail {
namespace {

// Up to `count` samples (not done elsewhere) spread over the targets: a greedy pick in
// sample order of those farther than a radius from every sample picked with a like normal
// (within 60°), the radius grown until few enough remain.
std::vector<int> anchorSamples(const Placement& at, std::size_t count) {
  if (count == 0) return {};
  const Scanner& scanner = at.scanner();
  double radius = std::min(scanner.fov_width, scanner.fov_height) / 4;
  const double min_dot = std::cos(radians(60));
  for (;;) {
    std::map<std::array<long, 3>, std::vector<int>> grid;
    std::vector<int> anchors;
    auto cellOf = [&](const Vec3& p) {
      return std::array<long, 3>{std::lround(std::floor(p.x() / radius)),
                                 std::lround(std::floor(p.y() / radius)),
                                 std::lround(std::floor(p.z() / radius))};
    };
    for (std::size_t i = 0; i < at.points.size() && anchors.size() <= count; ++i) {
      if (at.isDone(i)) continue;
      const SurfacePoint& p = at.points[i];
      const auto cell = cellOf(p.position);
      bool near = false;
      for (long dx = -1; dx <= 1 && !near; ++dx)
        for (long dy = -1; dy <= 1 && !near; ++dy)
          for (long dz = -1; dz <= 1 && !near; ++dz) {
            auto found = grid.find({cell[0] + dx, cell[1] + dy, cell[2] + dz});
            if (found == grid.end()) continue;
            for (int k : found->second)
              if ((at.points[k].position - p.position).norm() < radius &&
                  at.points[k].normal.dot(p.normal) > min_dot) {
                near = true;
                break;
              }
          }
      if (near) continue;
      grid[cell].push_back(static_cast<int>(i));
      anchors.push_back(static_cast<int>(i));
    }
    if (anchors.size() <= count) return anchors;
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
  for (int i : anchors) {
    const std::vector<View> mine = anchorPoses(at, at.points[i]);
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
