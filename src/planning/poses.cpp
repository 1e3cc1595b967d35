// Every pose generator of the planner and the registration, and the pose validity test.

#include <scanplan/planning/poses.h>
#include <scanplan/robot/cell.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numeric>

namespace scanplan {

Pose lookAt(const Vec3& camera, const Vec3& target, const Vec3& baseline_hint) {
  const Vec3 z = (target - camera).normalized();
  Vec3 x = baseline_hint - baseline_hint.dot(z) * z;
  if (x.norm() < 1e-9) x = z.unitOrthogonal();
  x.normalize();
  Pose pose = Pose::Identity();
  pose.linear() << x, z.cross(x), z;
  pose.translation() = camera;
  return pose;
}

namespace {

// The corners of the scanner body (Scanner::body) in S, bit 0 x, bit 1 y, bit 2 z.
std::array<Vec3, 8> bodyCorners(const Scanner& scanner) {
  const Box body = scanner.body();
  std::array<Vec3, 8> corners;
  for (int i = 0; i < 8; ++i)
    corners[i] = Vec3(i & 1 ? body.max.x() : body.min.x(), i & 2 ? body.max.y() : body.min.y(),
                      i & 4 ? body.max.z() : body.min.z());
  return corners;
}

std::size_t measuredCount(const Simulator& simulator, const View& view,
                          const std::vector<SurfacePoint>& points) {
  const std::vector<Loss> losses = simulator.measure(view, points);
  return static_cast<std::size_t>(std::count(losses.begin(), losses.end(), Loss::Measured));
}

}  // namespace

bool poseIsValid(const Simulator& simulator, const View& view, const CellCheck& cell) {
  const auto corners = bodyCorners(simulator.scanner());
  std::array<Vec3, 8> world;
  for (int i = 0; i < 8; ++i) world[i] = view.camera_to_world * corners[i];
  if (simulator.options().working_plane)
    for (const Vec3& c : world)
      if (c.z() < 0) return false;
  // The body's 12 edges and 4 space diagonals must not cross the part or a fixture.
  std::vector<Ray> segments;
  for (int i = 0; i < 8; ++i)
    for (int bit : {1, 2, 4})
      if (!(i & bit)) segments.push_back(Ray{world[i], world[i | bit] - world[i], 0, 1});
  for (int i = 0; i < 4; ++i) segments.push_back(Ray{world[i], world[7 - i] - world[i], 0, 1});
  const auto blocked = simulator.occluded(segments);
  if (std::any_of(blocked.begin(), blocked.end(), [](bool b) { return b; })) return false;
  // A body wholly inside the part's material crosses none of its faces.
  if (simulator.insideSolid(view.camera())) return false;
  return !cell.cell || reachView(*cell.cell, view, {}, 0, cell.collisions).reachable();
}

Vec3 horizontalBaseline(const Vec3& axis) {
  const Vec3 horizontal = Vec3::UnitZ().cross(axis);
  return horizontal.norm() < 1e-6 ? Vec3::UnitX() : Vec3(horizontal.normalized());
}

std::vector<View> aimedPoses(const Scanner& scanner, const Vec3& target, const Vec3& direction,
                             int rotations) {
  const Vec3 camera = target + scanner.standoff * direction;
  const Vec3 axis = -direction;
  const Vec3 horizontal = horizontalBaseline(axis);
  std::vector<View> views;
  for (int r = 0; r < rotations; ++r) {
    View view;
    view.camera_to_world =
        lookAt(camera, target, Eigen::AngleAxisd(2 * M_PI * r / rotations, axis) * horizontal);
    view.target = target;
    views.push_back(view);
  }
  return views;
}

VisibilityOptions plannerVisibility(const Scanner& scanner, double step, bool working_plane) {
  VisibilityOptions options;
  options.step = step;
  options.cone =
      std::min(scanner.max_camera_angle, scanner.max_projector_angle + scanner.triangulation_angle);
  options.reach = scanner.standoff;
  options.working_plane = working_plane;
  return options;
}

std::vector<Vec3> clusterDirections(const Simulator& simulator, const std::vector<Sample>& members,
                                    const Vec3& mean_normal, bool normal_only,
                                    const ClusterDirections& options,
                                    std::vector<Visibility>& status) {
  std::vector<Vec3> directions = {mean_normal};
  if (normal_only) return directions;
  const VisibilityMap cvm =
      combinedVisibilityMap(simulator, surfacePoints(members), options.visibility, &status);
  const std::uint32_t top = cvm.max();
  if (top == 0) return {};
  // The cells with the most visible samples, in the preferred tilt band first, then
  // closest to the mean normal.
  std::vector<std::pair<double, int>> ranked;
  for (int c = 0; c < cvm.cells(); ++c) {
    if (cvm.counts[c] < top) continue;
    const double tilt =
        degrees(std::acos(std::clamp(cvm.direction(c).dot(mean_normal), -1.0, 1.0)));
    const bool in_band = tilt >= options.tilt_min && tilt <= options.tilt_max;
    ranked.push_back({(in_band ? 0 : 1000) + tilt, c});
  }
  std::sort(ranked.begin(), ranked.end());
  for (std::size_t k = 0; k < ranked.size() && k < 4; ++k)
    directions.push_back(cvm.direction(ranked[k].second));
  return directions;
}

View shiftedTarget(const Simulator& simulator, const View& view,
                   const std::vector<SurfacePoint>& members,
                   const std::vector<SurfacePoint>& nearby, const CellCheck& cell) {
  if (nearby.empty()) return view;
  const Scanner& scanner = simulator.scanner();
  const double reach = 0.5 * std::min(scanner.fov_width, scanner.fov_height);
  Vec3 pull = Vec3::Zero();
  for (const SurfacePoint& p : nearby) pull += p.position;
  pull = pull / static_cast<double>(nearby.size()) - view.target;
  // Move only across the view axis: the standoff stays.
  pull -= pull.dot(view.axis()) * view.axis();
  const std::size_t members_measured = measuredCount(simulator, view, members);
  std::size_t best_nearby = measuredCount(simulator, view, nearby);
  View best = view;
  for (double fraction : {0.25, 0.5, 0.75, 1.0}) {
    View moved = view;
    const Vec3 shift = fraction * pull;
    if (shift.norm() > reach) break;
    moved.camera_to_world.translation() += shift;
    moved.target += shift;
    if (!poseIsValid(simulator, moved, cell)) continue;
    if (measuredCount(simulator, moved, members) < members_measured) break;
    const std::size_t count = measuredCount(simulator, moved, nearby);
    if (count > best_nearby) {
      best_nearby = count;
      best = moved;
    }
  }
  return best;
}

View tilePose(const Scanner& scanner, const SweepTile& tile) {
  View view;
  view.camera_to_world =
      lookAt(tile.centre + scanner.standoff * tile.normal, tile.centre, tile.across);
  view.target = tile.centre;
  return view;
}

std::vector<View> densePoses(const Scanner& scanner, const SurfacePoint& point,
                             const VisibilityMap& grid, int rotations) {
  std::vector<View> views;
  for (int c = 0; c < grid.cells(); ++c) {
    const Vec3 d = grid.direction(c);
    if (d.dot(point.normal) < std::cos(radians(scanner.max_camera_angle))) continue;
    const std::vector<View> around = aimedPoses(scanner, point.position, d, rotations);
    views.insert(views.end(), around.begin(), around.end());
  }
  return views;
}

std::vector<View> ringPoses(const Scanner& scanner, const SurfacePoint& anchor,
                            const std::vector<double>& tilts, double cone, int rotations) {
  const Vec3 n = anchor.normal;
  const Vec3 u = horizontalBaseline(n), w = n.cross(u);
  std::vector<View> poses = aimedPoses(scanner, anchor.position, n, rotations);
  int sides = 6;
  for (double tilt : tilts) {
    if (tilt <= 0 || tilt > cone) continue;
    for (int k = 0; k < sides; ++k) {
      const double azimuth = 2 * M_PI * k / sides;
      const Vec3 d = std::cos(radians(tilt)) * n +
                     std::sin(radians(tilt)) * (std::cos(azimuth) * u + std::sin(azimuth) * w);
      const std::vector<View> around =
          aimedPoses(scanner, anchor.position, d.normalized(), rotations);
      poses.insert(poses.end(), around.begin(), around.end());
    }
    sides = 8;
  }
  return poses;
}

View shiftedPose(const View& view, const Vec3& shift) {
  View moved = view;
  moved.camera_to_world.translation() += shift;
  moved.target += shift;
  return moved;
}

View shiftedInView(const View& view, const Vec3& shift) {
  return shiftedPose(view, view.camera_to_world.linear() * shift);
}

Vec3 placeInVolume(const Scanner& scanner, double x, double y, double z) {
  return {x * scanner.fov_width, y * scanner.fov_height, z * scanner.depth_of_field};
}

std::vector<View> posesAround(const Scanner& scanner, const SurfacePoint& target) {
  const Vec3 n = target.normal, u = n.unitOrthogonal(), w = n.cross(u);
  std::vector<Vec3> directions{n};
  for (int k = 0; k < 8; ++k)
    directions.push_back(std::cos(radians(30)) * n +
                         std::sin(radians(30)) *
                             (std::cos(k * M_PI / 4) * u + std::sin(k * M_PI / 4) * w));
  std::vector<View> poses;
  for (const Vec3& d : directions)
    for (const Vec3& hint : {u, w}) {
      View view;
      view.camera_to_world =
          lookAt(target.position + scanner.standoff * d.normalized(), target.position, hint);
      view.target = target.position;
      poses.push_back(view);
    }
  return poses;
}

View orientedPose(const Scanner& scanner, const Vec3& target, const Eigen::Matrix3d& rotation) {
  View view;
  view.camera_to_world.linear() = rotation;
  view.camera_to_world.translation() = target - scanner.standoff * rotation.col(2);
  view.target = target;
  return view;
}

View poseBetween(const View& a, const View& b, double t, double turn, double standoff) {
  const Eigen::Quaterniond qa(a.camera_to_world.linear()), qb(b.camera_to_world.linear());
  View view;
  view.target = (1 - t) * a.target + t * b.target;
  view.camera_to_world.linear() = qa.slerp(turn, qb).toRotationMatrix();
  view.camera_to_world.translation() =
      view.target - standoff * view.camera_to_world.linear().col(2);
  return view;
}

}  // namespace scanplan
