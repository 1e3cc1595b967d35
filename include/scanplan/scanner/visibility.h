#pragma once
// Visibility maps (docs/design.md §5): per sample, the directions on an azimuth x elevation
// grid from which a camera at the standoff sees it without occlusion, within the
// glancing cone; the Combined Visibility Map of a cluster counts, per direction, the
// samples that see it.

#include <scanplan/scanner/simulation.h>

#include <cstdint>
#include <vector>

namespace scanplan {

// A grid over the sphere of directions (world frame): azimuth in [0°, 360°) about +Z,
// elevation in [-90°, 90°] from the XY plane, `step` degrees; cell (a, e) holds the
// direction at the centre of its azimuth and elevation intervals.
struct VisibilityMap {
  double step = 5;  // degrees
  int azimuths = 72, elevations = 36;
  std::vector<std::uint32_t> counts;  // per cell, azimuth-major: samples seeing along it

  VisibilityMap() = default;
  explicit VisibilityMap(double step_degrees);
  int cells() const { return azimuths * elevations; }
  Vec3 direction(int cell) const;  // unit
  int cellOf(const Vec3& direction) const;
  std::uint32_t max() const;
};

struct VisibilityOptions {
  double step = 5;            // grid step, degrees
  double cone = 60;           // largest angle between a sample's normal and a direction, degrees
  double reach = 400;         // how far along a direction occluders count, mm (the standoff)
  bool working_plane = true;  // directions whose camera would lie below z = 0 are blocked
};

// How a sample's own map turned out: some free direction, or none, and why.
enum class Visibility { Free, OccludedByPart, BelowWorkingPlane };

// The Combined Visibility Map of `members` (world frame), by batched parallel ray casting
// against the simulator's scene. `status`, when given, receives each member's Visibility.
VisibilityMap combinedVisibilityMap(const Simulator& simulator,
                                    const std::vector<SurfacePoint>& members,
                                    const VisibilityOptions& options,
                                    std::vector<Visibility>* status = nullptr);

}  // namespace scanplan
