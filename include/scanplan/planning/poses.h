#pragma once
// Every scanner pose the planner and its bridging try, and the test a pose must pass
// to be used (docs/design.md, Poses). World frame, mm; a pose is the scanner frame S in the
// world (sensor.h).

#include <scanplan/core/view.h>
#include <scanplan/planning/sweep_tiles.h>
#include <scanplan/sampling/sampling.h>
#include <scanplan/scanner/simulation.h>
#include <scanplan/scanner/visibility.h>

#include <vector>

namespace scanplan {

struct Cell;
class CellCollisions;

// The scanner pose with the camera at `camera` looking at `target`, its baseline (+X)
// as close as possible to `baseline_hint` (projected orthogonal to the view axis; any
// perpendicular when the hint is parallel to it). Precondition: camera != target.
Pose lookAt(const Vec3& camera, const Vec3& target, const Vec3& baseline_hint = Vec3::UnitX());

// The robot a pose must suit: none, or a cell whose robot must reach the pose, with its
// arm kept clear of the part by `collisions` when given.
struct CellCheck {
  const Cell* cell = nullptr;
  const CellCollisions* collisions = nullptr;
};

// True when the scanner body at `view` (Scanner::body_margin, body_depth) stays clear of
// the part, the fixtures and the working plane (neither crossing a face nor inside the
// part's material), and the cell's robot, if any, reaches it.
bool poseIsValid(const Simulator& simulator, const View& view, const CellCheck& cell = {});

// A unit baseline direction perpendicular to the view axis and horizontal (world +X when
// the axis is vertical): the rotation about the axis tried first.
Vec3 horizontalBaseline(const Vec3& axis);

// Poses with the camera at the standoff from `target` along `direction` (unit, from the
// target to the camera), with `rotations` rotations about the view axis, the first with a
// horizontal baseline.
std::vector<View> aimedPoses(const Scanner& scanner, const Vec3& target, const Vec3& direction,
                             int rotations);

// The directions a cluster is looked at from: its mean normal, then, unless `normal_only`,
// up to four directions of its Combined Visibility Map that the most members see, those
// tilted from the mean normal within [tilt_min, tilt_max] degrees first, then the least
// tilted. Empty when no member sees any direction. `status` receives each member's
// Visibility (untouched with `normal_only`).
struct ClusterDirections {
  double tilt_min = 30, tilt_max = 50;  // preferred tilt band, degrees
  VisibilityOptions visibility;
};
std::vector<Vec3> clusterDirections(const Simulator& simulator, const std::vector<Sample>& members,
                                    const Vec3& mean_normal, bool normal_only,
                                    const ClusterDirections& options,
                                    std::vector<Visibility>& status);

// The visibility maps the planner uses for `scanner`: grid step `step` degrees, the cone
// the camera and the projector both keep, reaching to the standoff.
VisibilityOptions plannerVisibility(const Scanner& scanner, double step, bool working_plane);

// The target shift of tilted positioning: `view` moved across its axis (orientation and
// standoff kept) towards the mean of `nearby`, in quarter steps up to half the field of
// view, as long as it stays valid, measures every point of `members` it measured, and
// measures more of `nearby`. `view` itself when no step does better.
View shiftedTarget(const Simulator& simulator, const View& view,
                   const std::vector<SurfacePoint>& members,
                   const std::vector<SurfacePoint>& nearby, const CellCheck& cell = {});

// The pose of a sweep tile: along its normal at the standoff, the field of view's width
// across the tile.
View tilePose(const Scanner& scanner, const SweepTile& tile);

// Poses aimed at one point from every direction of `grid` within the camera's glancing
// cone, at the standoff, with `rotations` rotations about the axis.
std::vector<View> densePoses(const Scanner& scanner, const SurfacePoint& point,
                             const VisibilityMap& grid, int rotations);

// Poses aimed at one anchor point in rings around its normal: along the normal, then
// tilted by each of `tilts` (degrees; those beyond `cone` left out) towards 6 sides for
// the first ring and 8 for the others, each with `rotations` rotations about the axis.
std::vector<View> ringPoses(const Scanner& scanner, const SurfacePoint& anchor,
                            const std::vector<double>& tilts, double cone, int rotations);

// `view` with its target (and camera) moved by `shift` (world, mm), orientation kept.
View shiftedPose(const View& view, const Vec3& shift);

// `view` moved by `shift` in its own camera frame (mm), orientation kept.
View shiftedInView(const View& view, const Vec3& shift);

// A place in the scanner's measuring volume, camera frame (mm): `x` and `y` shares of the
// field's width and height across the axis, `z` a share of the depth of field along it.
Vec3 placeInVolume(const Scanner& scanner, double x, double y, double z);

// Bridging poses aimed at `target`: along its normal and tilted by 30 degrees towards
// eight sides (to see the walls around it), each with two rotations about the view axis.
std::vector<View> posesAround(const Scanner& scanner, const SurfacePoint& target);

// The pose aimed at `target` at the standoff with the orientation `rotation`.
View orientedPose(const Scanner& scanner, const Vec3& target, const Eigen::Matrix3d& rotation);

// The pose aimed at the point `t` of the way from a's target to b's, its orientation
// `turn` of the way from a's to b's, at the standoff.
View poseBetween(const View& a, const View& b, double t, double turn, double standoff);

}  // namespace scanplan
