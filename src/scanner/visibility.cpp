#include <scanplan/scanner/visibility.h>

#include <tbb/parallel_for.h>

#include <algorithm>
#include <cmath>

namespace scanplan {

VisibilityMap::VisibilityMap(double step_degrees)
    : step(step_degrees),
      azimuths(static_cast<int>(std::lround(360 / step_degrees))),
      elevations(static_cast<int>(std::lround(180 / step_degrees))),
      counts(static_cast<std::size_t>(azimuths) * elevations, 0) {}

Vec3 VisibilityMap::direction(int cell) const {
  const int a = cell / elevations, e = cell % elevations;
  const double azimuth = (a + 0.5) * 2 * M_PI / azimuths;
  const double elevation = -M_PI / 2 + (e + 0.5) * M_PI / elevations;
  return Vec3(std::cos(elevation) * std::cos(azimuth), std::cos(elevation) * std::sin(azimuth),
              std::sin(elevation));
}

int VisibilityMap::cellOf(const Vec3& d) const {
  const Vec3 u = d.normalized();
  double azimuth = std::atan2(u.y(), u.x());
  if (azimuth < 0) azimuth += 2 * M_PI;
  const double elevation = std::asin(std::clamp(u.z(), -1.0, 1.0));
  const int a = std::min(azimuths - 1, static_cast<int>(azimuth / (2 * M_PI) * azimuths));
  const int e =
      std::min(elevations - 1, static_cast<int>((elevation + M_PI / 2) / M_PI * elevations));
  return a * elevations + e;
}

std::uint32_t VisibilityMap::max() const {
  return counts.empty() ? 0 : *std::max_element(counts.begin(), counts.end());
}

VisibilityMap combinedVisibilityMap(const Simulator& simulator,
                                    const std::vector<SurfacePoint>& members,
                                    const VisibilityOptions& options,
                                    std::vector<Visibility>* status) {
  VisibilityMap map(options.step);
  std::vector<Vec3> directions(map.cells());
  for (int c = 0; c < map.cells(); ++c) directions[c] = map.direction(c);
  const double min_dot = std::cos(radians(options.cone));
  const double offset = simulator.surfaceOffset();

  // Rays of every member along every direction inside its cone, cast in one batch.
  std::vector<Ray> rays;
  std::vector<std::pair<int, int>> owner;  // (member index, cell)
  std::vector<char> below(members.size(), 0);
  for (std::size_t m = 0; m < members.size(); ++m) {
    const SurfacePoint& s = members[m];
    for (int c = 0; c < map.cells(); ++c) {
      if (s.normal.dot(directions[c]) < min_dot) continue;
      if (options.working_plane && s.position.z() + options.reach * directions[c].z() < 0) {
        below[m] = 1;
        continue;
      }
      rays.push_back(Ray{s.position + offset * s.normal, directions[c], 0, options.reach});
      owner.emplace_back(static_cast<int>(m), c);
    }
  }
  const std::vector<bool> blocked = simulator.occluded(rays);
  std::vector<char> free(members.size(), 0);
  for (std::size_t r = 0; r < rays.size(); ++r) {
    if (blocked[r]) continue;
    ++map.counts[owner[r].second];
    free[owner[r].first] = 1;
  }
  if (status) {
    status->resize(members.size());
    for (std::size_t m = 0; m < members.size(); ++m)
      (*status)[m] = free[m]    ? Visibility::Free
                     : below[m] ? Visibility::BelowWorkingPlane
                                : Visibility::OccludedByPart;
  }
  return map;
}

}  // namespace scanplan
