#include <scanplan/cad/raycast.h>
#include <scanplan/core/atomic_file.h>
#include <scanplan/core/errors.h>
#include <scanplan/scanner/simulation.h>

#include "core/kd_tree.h"

#include <tbb/blocked_range.h>
#include <tbb/parallel_for.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <numeric>
#include <optional>
#include <random>
#include <span>

namespace scanplan {

std::string_view toString(Loss loss) {
  switch (loss) {
    case Loss::Measured: return "measured";
    case Loss::OutsideVolume: return "outside_volume";
    case Loss::CameraAngle: return "camera_angle";
    case Loss::ProjectorAngle: return "projector_angle";
    case Loss::Reflection: return "reflection";
    case Loss::UnderMarker: return "under_marker";
    case Loss::CameraOccluded: return "camera_occluded";
    case Loss::ProjectorOccluded: return "projector_occluded";
  }
  return "unknown";
}

bool spotCovers(const CoveredSpot& spot, const SurfacePoint& point) {
  return point.face > 0 &&
         (point.position - spot.centre).squaredNorm() <= spot.radius * spot.radius &&
         std::abs((point.position - spot.centre).dot(spot.normal)) <= spot.radius / 2 &&
         point.normal.dot(spot.normal) > 0.5;
}

std::vector<char> underSpots(const std::vector<CoveredSpot>& spots,
                             std::span<const SurfacePoint> points) {
  std::vector<char> under(points.size(), 0);
  if (spots.empty()) return under;
  std::vector<Vec3> centres;
  for (const CoveredSpot& spot : spots) centres.push_back(spot.centre);
  const detail::PointCloudAdaptor cloud{centres};
  const detail::PointTree tree(3, cloud);
  for (std::size_t i = 0; i < points.size(); ++i) {
    unsigned nearest = 0;
    double squared = 0;
    tree.knnSearch(points[i].position.data(), 1, &nearest, &squared);
    under[i] = spotCovers(spots[nearest], points[i]);
  }
  return under;
}

namespace {

// f(i) for i in [0, n), in parallel in blocks: each test is light, and views are often
// measured in parallel already.
template <typename F>
void forEach(std::size_t n, const F& f) {
  tbb::parallel_for(tbb::blocked_range<std::size_t>(0, n, 512), [&](const auto& range) {
    for (std::size_t i = range.begin(); i != range.end(); ++i) f(i);
  });
}

// An angle, radians, with its cosine and sine.
struct Angle {
  double value, cos, sin;
};

Angle angleOf(double degrees) {
  const double value = radians(degrees);
  return {value, std::cos(value), std::sin(value)};
}

// The directions within `spread` radians of the unit `axis`: the whole sphere by default.
struct NormalCone {
  Vec3 axis = Vec3::UnitZ();
  double spread = std::numbers::pi, cos_spread = -1, sin_spread = 0;
};

// What the measurement test reads of the scanner, the same for every view: the measuring
// volume, the angle limits and the eyes' places in the scanner's frame.
struct Volume {
  static constexpr std::size_t kMostCameras = 2;

  double z_min, z_max, half_width, half_height, standoff;  // volume in S, mm
  Angle camera_limit, projector_limit;  // the largest angles a normal may turn from either
  double cos_reflection;
  Vec3 projector_in_scanner;
  std::array<Vec3, kMostCameras> cameras_in_scanner;  // the view's own first
  std::size_t camera_count;

  explicit Volume(const Scanner& s)
      : z_min(s.standoff - s.depth_of_field / 2),
        z_max(s.standoff + s.depth_of_field / 2),
        half_width(s.fov_width / 2),
        half_height(s.fov_height / 2),
        standoff(s.standoff),
        camera_limit(angleOf(s.max_camera_angle)),
        projector_limit(angleOf(s.max_projector_angle)),
        cos_reflection(std::cos(radians(s.reflection_cone))),
        projector_in_scanner(s.projectorInScanner()),
        camera_count(0) {
    for (const Vec3& c : s.camerasInScanner()) cameras_in_scanner.at(camera_count++) = c;
  }
};

// The parts of the measurement test that need no ray, for one view.
struct ViewGeometry : Volume {
  Pose world_to_camera;
  Vec3 projector;
  std::array<Vec3, kMostCameras> cameras;  // every camera's centre, the view's own first

  ViewGeometry(const View& view, const Volume& volume)
      : Volume(volume),
        world_to_camera(view.camera_to_world.inverse()),
        projector(view.camera_to_world * projector_in_scanner) {
    for (std::size_t c = 0; c < camera_count; ++c)
      cameras[c] = view.camera_to_world * cameras_in_scanner[c];
  }

  std::span<const Vec3> eyes() const { return {cameras.data(), camera_count}; }

  bool inVolume(const Vec3& p) const {
    Vec3 q = world_to_camera * p;
    double scale = q.z() / standoff;  // the field grows linearly with depth
    return q.z() >= z_min && q.z() <= z_max && std::abs(q.x()) <= half_width * scale &&
           std::abs(q.y()) <= half_height * scale;
  }

  // False when no point of the ball (centre, radius) can lie in the measuring volume.
  bool mayReachVolume(const Vec3& centre, double radius) const {
    const Vec3 q = world_to_camera * centre;
    if (q.z() + radius < z_min || q.z() - radius > z_max) return false;
    const double scale = std::min(q.z() + radius, z_max) / standoff;  // widest depth in reach
    return std::abs(q.x()) - radius <= half_width * scale &&
           std::abs(q.y()) - radius <= half_height * scale;
  }

  // False when every point of the ball (centre, radius) whose normal lies within `cone`
  // fails the angle tests: from every camera, or from the projector. A normal turns from
  // the direction to an eye by at least the cone axis' angle to the ball's centre, less the
  // cone's spread and the ball's angular radius from that eye.
  bool mayFace(const Vec3& centre, double radius, const NormalCone& cone) const {
    return within(projector, centre, radius, cone, projector_limit) &&
           std::ranges::any_of(eyes(), [&](const Vec3& eye) {
             return within(eye, centre, radius, cone, camera_limit);
           });
  }

  // Whether a normal of `cone` at a point of the ball may turn from `eye` by `limit` or
  // less: the angle from the axis to the eye at most limit + spread + the ball's angular
  // radius, compared by cosines.
  static bool within(const Vec3& eye, const Vec3& centre, double radius, const NormalCone& cone,
                     const Angle& limit) {
    constexpr double kSlack = 1e-6;  // of a cosine: rounding never drops a point that passes
    const double widest = limit.value + cone.spread;
    if (widest >= std::numbers::pi) return true;
    const Vec3 to_eye = eye - centre;
    const double distance = to_eye.norm();
    if (distance <= radius) return true;
    const double sin_ball = radius / distance, cos_ball = std::sqrt(1 - sin_ball * sin_ball);
    const double cos_widest = limit.cos * cone.cos_spread - limit.sin * cone.sin_spread;
    const double sin_widest = limit.sin * cone.cos_spread + limit.cos * cone.sin_spread;
    // With the ball's radius the widest angle reaches pi: every direction is within it.
    if (widest >= std::numbers::pi / 2 && sin_ball >= sin_widest) return true;
    const double cos_reach = cos_widest * cos_ball - sin_widest * sin_ball;
    return cone.axis.dot(to_eye) >= (cos_reach - kSlack) * distance;
  }

  // Volume, glancing angles and specular reflection, seen from the camera at `eye`, in the
  // order of Loss.
  Loss test(const Vec3& p, const Vec3& n, bool specular, const Vec3& eye) const {
    if (!inVolume(p)) return Loss::OutsideVolume;
    const Vec3 to_camera = (eye - p).normalized();
    if (n.dot(to_camera) < camera_limit.cos) return Loss::CameraAngle;
    const Vec3 to_projector = (projector - p).normalized();
    if (n.dot(to_projector) < projector_limit.cos) return Loss::ProjectorAngle;
    if (specular) {
      // Mirror direction of the projector's light leaving p.
      const Vec3 reflected = 2 * n.dot(to_projector) * n - to_projector;
      if (reflected.dot(to_camera) > cos_reflection) return Loss::Reflection;
    }
    return Loss::Measured;
  }
};

// Points grouped in cubic cells of a given size, each with a bounding ball, so that a view
// tests only the points of cells that reach its measuring volume (view-frustum culling).
// The cells lie in blocks of kSpan³ cells, each with a ball holding its points, so that a
// view walks only the cells of blocks that reach its volume.
// With `by_normal`, the points of a cell are grouped further by face and by the axis their
// normals lean most towards, each group with a ball and a cone holding its normals, so
// that where only measured points count a view tests only those whose normals may face it.
class Cells {
 public:
  Cells(std::span<const SurfacePoint> points, double size, bool by_normal) {
    std::map<std::array<long, 6>, std::vector<std::size_t>> members;  // by block, then cell
    for (std::size_t i = 0; i < points.size(); ++i) {
      const Vec3& p = points[i].position;
      std::array<long, 6> key{};
      for (int a = 0; a < 3; ++a) {
        key[a + 3] = std::lround(std::floor(p[a] / size));
        key[a] = floorDivided(key[a + 3], kSpan);
      }
      members[key].push_back(i);
    }
    cells_.reserve(members.size());
    const std::array<long, 6>* block = nullptr;
    for (const auto& [key, in_cell] : members) {
      if (!block || !std::equal(key.begin(), key.begin() + 3, block->begin()))
        blocks_.push_back({{}, cells_.size(), cells_.size()});
      block = &key;
      addCell(points, in_cell, by_normal);
      blocks_.back().last = cells_.size();
    }
    for (Block& b : blocks_) b.ball = ballOf(points, blockMembers(b));
  }

  // The points of the groups that may reach the view's measuring volume.
  std::vector<std::size_t> reaching(const ViewGeometry& geometry) const {
    return culled(geometry, false);
  }

  // Those of them whose normals may face the view (ViewGeometry::mayFace): the others could
  // only be lost to the cameras' or the projector's angle.
  std::vector<std::size_t> facing(const ViewGeometry& geometry) const {
    return culled(geometry, true);
  }

 private:
  struct Ball {
    Vec3 centre = Vec3::Zero();
    double radius = 0;
  };
  // Members and groups lie in runs of one array each, so that the views' culling walks
  // memory in order.
  struct Group {
    Ball ball;
    NormalCone normals;       // holding every member's normal
    std::size_t first, last;  // its members: members_[first, last)
  };
  struct Cell {
    Ball ball;
    std::size_t first, last;  // its groups: groups_[first, last)
  };
  struct Block {
    Ball ball;
    std::size_t first, last;  // its cells: cells_[first, last)
  };

  // The cells a block spans along each axis.
  static constexpr long kSpan = 4;

  // A group of fewer points has no cone of its own: culling them costs about what testing
  // them does.
  static constexpr std::size_t kConedLeast = 8;

  // The cell of `members`; with `by_normal`, its groups with cones (addConedGroups) and
  // the rest of its points together, without.
  void addCell(std::span<const SurfacePoint> points, const std::vector<std::size_t>& members,
               bool by_normal) {
    Cell cell{ballOf(points, members), groups_.size(), groups_.size()};
    const std::vector<std::size_t> rest = by_normal ? addConedGroups(points, members) : members;
    if (!rest.empty())
      addGroup(groups_.size() == cell.first ? cell.ball : ballOf(points, rest), {}, rest);
    cell.last = groups_.size();
    cells_.push_back(cell);
  }

  // Adds the groups of `members` by face and by the axis their normals lean most towards
  // that hold kConedLeast points or more, each with its cone; returns the other points.
  std::vector<std::size_t> addConedGroups(std::span<const SurfacePoint> points,
                                          const std::vector<std::size_t>& members) {
    std::map<std::pair<int, int>, std::vector<std::size_t>> groups;
    for (std::size_t i : members) groups[{points[i].face, leaning(points[i].normal)}].push_back(i);
    std::vector<std::size_t> rest;
    for (const auto& [key, group] : groups) {
      if (group.size() < kConedLeast)
        rest.insert(rest.end(), group.begin(), group.end());
      else
        addGroup(ballOf(points, group), coneOf(points, group), group);
    }
    return rest;
  }

  void addGroup(const Ball& ball, const NormalCone& normals,
                const std::vector<std::size_t>& members) {
    groups_.push_back({ball, normals, members_.size(), members_.size() + members.size()});
    members_.insert(members_.end(), members.begin(), members.end());
  }

  // The axis (0 to 5: +x, -x, +y, -y, +z, -z) the normal leans most towards.
  static int leaning(const Vec3& normal) {
    Eigen::Index axis = 0;
    normal.cwiseAbs().maxCoeff(&axis);
    return 2 * static_cast<int>(axis) + (normal[axis] < 0 ? 1 : 0);
  }

  static Ball ballOf(std::span<const SurfacePoint> points, std::span<const std::size_t> members) {
    Box box;
    for (std::size_t i : members) box.add(points[i].position);
    Ball ball{box.center(), 0};
    for (std::size_t i : members)
      ball.radius = std::max(ball.radius, (points[i].position - ball.centre).norm());
    return ball;
  }

  static long floorDivided(long a, long b) { return a / b - (a % b < 0 ? 1 : 0); }

  // The members of the block's cells, which lie in one run of members_.
  std::span<const std::size_t> blockMembers(const Block& block) const {
    const std::size_t first = groups_[cells_[block.first].first].first;
    const std::size_t last = groups_[cells_[block.last - 1].last - 1].last;
    return {members_.data() + first, last - first};
  }

  // The cone around the members' mean normal holding all of them. Unit normals leaning
  // towards one axis do not cancel out; any other (zero, not a number) leaves it the whole
  // sphere.
  static NormalCone coneOf(std::span<const SurfacePoint> points,
                           const std::vector<std::size_t>& members) {
    NormalCone whole, cone;
    Vec3 sum = Vec3::Zero();
    for (std::size_t i : members) sum += points[i].normal;
    if (!(sum.norm() > 0) || !sum.allFinite()) return whole;
    cone.axis = sum.normalized();
    cone.spread = 0;
    for (std::size_t i : members) {
      const double angle = std::acos(std::clamp(cone.axis.dot(points[i].normal), -1.0, 1.0));
      if (std::isnan(angle)) return whole;
      cone.spread = std::max(cone.spread, angle);
    }
    cone.cos_spread = std::cos(cone.spread);
    cone.sin_spread = std::sin(cone.spread);
    return cone;
  }

  std::vector<std::size_t> culled(const ViewGeometry& geometry, bool facing) const {
    std::vector<std::size_t> near;
    for (const Block& block : blocks_) {
      if (!geometry.mayReachVolume(block.ball.centre, block.ball.radius)) continue;
      for (std::size_t c = block.first; c < block.last; ++c)
        addCulled(geometry, facing, cells_[c], near);
    }
    return near;
  }

  // Adds the members of the cell's groups that may reach the view's measuring volume (and,
  // with `facing`, may face the view) to `near`.
  void addCulled(const ViewGeometry& geometry, bool facing, const Cell& cell,
                 std::vector<std::size_t>& near) const {
    if (!geometry.mayReachVolume(cell.ball.centre, cell.ball.radius)) return;
    const bool one = cell.last - cell.first == 1;  // with the cell's ball
    for (std::size_t k = cell.first; k < cell.last; ++k) {
      const Group& g = groups_[k];
      if (!one && !geometry.mayReachVolume(g.ball.centre, g.ball.radius)) continue;
      if (facing && !geometry.mayFace(g.ball.centre, g.ball.radius, g.normals)) continue;
      near.insert(near.end(), members_.begin() + static_cast<std::ptrdiff_t>(g.first),
                  members_.begin() + static_cast<std::ptrdiff_t>(g.last));
    }
  }

  std::vector<Block> blocks_;
  std::vector<Cell> cells_;
  std::vector<Group> groups_;
  std::vector<std::size_t> members_;
};

// A camera's pixel grid: its centre, its rotation (z towards the measuring volume's
// centre, y as the view's) and its distance to that centre. The first camera's is the
// view's own.
struct Eye {
  Vec3 centre;
  Eigen::Matrix3d rotation;
  double distance;
};

std::vector<Eye> eyes(const View& view, const Scanner& s) {
  const Vec3 target = view.camera_to_world * Vec3(0, 0, s.standoff);
  std::vector<Eye> result;
  for (const Vec3& c : s.camerasInScanner()) {
    const Vec3 centre = view.camera_to_world * c;
    const Vec3 z = (target - centre).normalized();
    const Vec3 x = view.camera_to_world.linear().col(1).cross(z).normalized();
    Eigen::Matrix3d rotation;
    rotation << x, z.cross(x), z;
    result.push_back({centre, rotation, (target - centre).norm()});
  }
  return result;
}

// The pixel grid of a simulated cloud.
struct CloudGrid {
  double spacing;
  int columns, rows;
  int view_id;
};

// Row `row` (over every camera's grid) of view `view_id`'s cloud: its random stream
// without the seed.
std::uint64_t rowStream(int view_id, std::uint64_t row) {
  return static_cast<std::uint64_t>(view_id) * 1000003ULL + row;
}

}  // namespace

struct Simulator::Impl {
  Scanner scanner;
  std::optional<Volume> volume;  // of the scanner
  SimulationOptions options;
  TriangleMesh world;  // part (first) then fixtures, world frame
  std::size_t part_triangles = 0;
  bool solid = false;          // the part is closed: it has an inside
  std::vector<char> specular;  // per face id (index 0: fixtures)
  std::vector<SurfacePoint> facets;
  std::vector<double> facet_area;
  std::optional<Cells> cells;  // of the part's facets
  std::size_t face_count = 0;
  double offset = 0;  // mm
  std::unique_ptr<RayCaster> caster;
  std::vector<Vec3> spot_centres;  // of options.covered, indexed
  std::unique_ptr<detail::PointCloudAdaptor> spot_cloud;
  std::unique_ptr<detail::PointTree> spots;

  bool isSpecular(int face) const {
    return face > 0 && face < static_cast<int>(specular.size()) && specular[face];
  }

  // A spot covers the point: the nearest spot's centre within its radius, the point near
  // its plane and facing its way.
  bool isCovered(const SurfacePoint& sp) const {
    if (!spots || sp.face <= 0) return false;
    unsigned nearest = 0;
    double squared = 0;
    spots->knnSearch(sp.position.data(), 1, &nearest, &squared);
    return spotCovers(options.covered[nearest], sp);
  }

  // The tests of a point that cast no ray, seen from the camera at `eye`: volume, angles,
  // reflection (in the order of Loss), a covering spot, the working plane.
  Loss testWithoutRays(const ViewGeometry& geometry, const SurfacePoint& sp,
                       const Vec3& eye) const {
    Loss loss = geometry.test(sp.position, sp.normal, isSpecular(sp.face), eye);
    if (loss == Loss::Measured && isCovered(sp)) loss = Loss::UnderMarker;
    if (loss == Loss::Measured && planeBlocks(sp.position, eye)) loss = Loss::CameraOccluded;
    if (loss == Loss::Measured && planeBlocks(sp.position, geometry.projector))
      loss = Loss::ProjectorOccluded;
    return loss;
  }

  // The first camera from `first` on that passes the tests without rays, with Measured;
  // else none, with the loss of the camera that passed most tests (Loss is in test order).
  std::pair<Loss, int> firstCamera(const ViewGeometry& geometry, const SurfacePoint& sp,
                                   std::size_t first = 0) const {
    Loss worst = Loss::Measured;
    for (std::size_t c = first; c < geometry.camera_count; ++c) {
      const Loss loss = testWithoutRays(geometry, sp, geometry.cameras[c]);
      if (loss == Loss::Measured) return {loss, static_cast<int>(c)};
      worst = c == first ? loss : std::max(worst, loss);
    }
    return {worst, -1};
  }

  // The measurement test of points[i] from geometry(i) for each i of `tested` (the others
  // keep their loss): the tests without rays, then an occlusion ray to the camera that
  // passed them and, where that one is free, one to the projector. A point the part hides
  // from that camera is tried from the next camera that passes them.
  template <typename GeometryOf>
  void testWithRays(std::span<const SurfacePoint> points, const std::vector<std::size_t>& tested,
                    const GeometryOf& geometry, std::vector<Loss>& losses,
                    std::size_t* ray_count) const {
    std::vector<std::int8_t> eye(points.size(), -1);  // the camera each point is tried from
    forEach(tested.size(), [&](std::size_t k) {
      const std::size_t i = tested[k];
      const auto [loss, c] = firstCamera(geometry(i), points[i]);
      losses[i] = loss;
      eye[i] = static_cast<std::int8_t>(c);
    });
    std::vector<std::size_t> candidates;
    for (std::size_t i : tested)
      if (losses[i] == Loss::Measured) candidates.push_back(i);
    while (!candidates.empty()) {
      const std::vector<bool> hidden = occluded(
          candidates, [&](std::size_t i) { return geometry(i).cameras[eye[i]]; }, points,
          ray_count);
      std::vector<std::size_t> again, seen;
      for (std::size_t k = 0; k < candidates.size(); ++k) {
        const std::size_t i = candidates[k];
        if (!hidden[k]) {
          seen.push_back(i);
          continue;
        }
        eye[i] = static_cast<std::int8_t>(firstCamera(geometry(i), points[i], eye[i] + 1).second);
        losses[i] = eye[i] >= 0 ? Loss::Measured : Loss::CameraOccluded;
        if (eye[i] >= 0) again.push_back(i);
      }
      const std::vector<bool> unlit = occluded(
          seen, [&](std::size_t i) { return geometry(i).projector; }, points, ray_count);
      for (std::size_t k = 0; k < seen.size(); ++k)
        if (unlit[k]) losses[seen[k]] = Loss::ProjectorOccluded;
      candidates = std::move(again);
    }
  }

  // Whether the part hides eye(i) from points[i], for each i of `which`.
  template <typename EyeOf>
  std::vector<bool> occluded(const std::vector<std::size_t>& which, const EyeOf& eye,
                             std::span<const SurfacePoint> points, std::size_t* ray_count) const {
    std::vector<Ray> rays(which.size());
    forEach(which.size(),
            [&](std::size_t k) { rays[k] = segment(points[which[k]], eye(which[k])); });
    if (ray_count) *ray_count += rays.size();
    return caster->occluded(rays);
  }

  // The working plane z = 0 hides the segment p -> eye when the point lies under it or the
  // eye is below it.
  bool planeBlocks(const Vec3& p, const Vec3& eye) const {
    return options.working_plane && (eye.z() < 0 || p.z() < -offset);
  }

  Ray segment(const SurfacePoint& point, const Vec3& eye) const {
    Ray ray;
    ray.origin = point.position + offset * point.normal;
    ray.direction = eye - ray.origin;
    ray.t_near = 0;
    ray.t_far = 1;
    return ray;
  }

  // The measurement test of `points` from `view`. With `subset`, only those indices are
  // tested and all others are outside the volume.
  std::vector<Loss> measure(const View& view, std::span<const SurfacePoint> points,
                            const std::vector<std::size_t>* subset, std::size_t* ray_count) const {
    const ViewGeometry geometry(view, *volume);
    std::vector<Loss> losses(points.size(), Loss::OutsideVolume);
    std::vector<std::size_t> all;
    if (!subset) {
      all.resize(points.size());
      std::iota(all.begin(), all.end(), std::size_t{0});
    }
    if (ray_count) *ray_count = 0;
    testWithRays(
        points, subset ? *subset : all,
        [&](std::size_t) -> const ViewGeometry& { return geometry; }, losses, ray_count);
    return losses;
  }

  // Rows [first, last) of camera e's pixel grid into rows[r]: the hits on the part that
  // camera e measures and no earlier camera does, lit by the projector, each with its ray
  // and its noise's standard deviation.
  void cloudBlock(const ViewGeometry& geometry, const std::vector<Eye>& all, std::size_t e,
                  const CloudGrid& grid, int first, int last, CloudRays* rows) const {
    const Eye& eye = all[e];
    std::vector<Ray> rays;
    rays.reserve(static_cast<std::size_t>(last - first) * grid.columns);
    for (int r = first; r < last; ++r)
      for (int c = 0; c < grid.columns; ++c) {
        const Vec3 pixel(-scanner.fov_width / 2 + (c + 0.5) * grid.spacing,
                         -scanner.fov_height / 2 + (r + 0.5) * grid.spacing, scanner.standoff);
        rays.push_back(Ray{eye.centre, eye.rotation * pixel.normalized()});
      }
    const auto hits = caster->intersect(rays);
    std::vector<std::size_t> kept;
    std::vector<SurfacePoint> surface;
    for (std::size_t i = 0; i < hits.size(); ++i) {
      const auto& hit = hits[i];
      if (!hit || hit->triangle >= static_cast<int>(part_triangles)) continue;
      const SurfacePoint sp{hit->point, hit->normal, hit->face};
      if (testWithoutRays(geometry, sp, eye.centre) != Loss::Measured) continue;
      kept.push_back(i);
      surface.push_back(sp);
    }
    std::vector<char> drop = seenBefore(geometry, all, e, surface);
    std::vector<Ray> to_projector(surface.size());
    for (std::size_t k = 0; k < surface.size(); ++k)
      to_projector[k] = segment(surface[k], geometry.projector);
    const std::vector<bool> blocked = caster->occluded(to_projector);
    for (std::size_t k = 0; k < surface.size(); ++k) drop[k] |= blocked[k];

    tbb::parallel_for(first, last, [&](int r) {
      CloudRays& out = rows[r];
      out.row_streams = {rowStream(grid.view_id, static_cast<std::uint64_t>(r) + e * grid.rows)};
      const std::size_t begin = static_cast<std::size_t>(r - first) * grid.columns;
      auto k = std::lower_bound(kept.begin(), kept.end(), begin) - kept.begin();
      for (; k < static_cast<std::ptrdiff_t>(kept.size()) && kept[k] < begin + grid.columns; ++k) {
        if (drop[k]) continue;
        const SurfacePoint& sp = surface[k];
        const Vec3 ray_direction = rays[kept[k]].direction;
        const double cos_incidence = std::clamp(-ray_direction.dot(sp.normal), 1e-3, 1.0);
        const double depth = (sp.position - eye.centre).dot(eye.rotation.col(2)) / eye.distance;
        out.sigma.push_back(scanner.noise_sigma * depth * depth / cos_incidence);
        out.along.push_back(ray_direction);
        out.cloud.points.push_back(sp.position);
        out.cloud.normals.push_back(sp.normal);
        out.cloud.faces.push_back(sp.face);
        out.cloud.incidence.push_back(static_cast<float>(degrees(std::acos(cos_incidence))));
        out.cloud.hits.push_back(sp.position);
      }
      out.row_ends = {out.sigma.size()};
    });
  }

  // Per point of `surface`: whether a camera before `e` measures it (it passes the tests
  // without rays from there, and nothing hides it), so that camera e's grid leaves it.
  std::vector<char> seenBefore(const ViewGeometry& geometry, const std::vector<Eye>& all,
                               std::size_t e, const std::vector<SurfacePoint>& surface) const {
    std::vector<char> seen(surface.size(), 0);
    for (std::size_t c = 0; c < e; ++c) {
      std::vector<std::size_t> tried;
      std::vector<Ray> rays;
      for (std::size_t k = 0; k < surface.size(); ++k)
        if (!seen[k] && testWithoutRays(geometry, surface[k], all[c].centre) == Loss::Measured) {
          tried.push_back(k);
          rays.push_back(segment(surface[k], all[c].centre));
        }
      const std::vector<bool> blocked = caster->occluded(rays);
      for (std::size_t j = 0; j < tried.size(); ++j) seen[tried[j]] |= !blocked[j];
    }
    return seen;
  }
};

Simulator::Simulator(const Part& part, const Scanner& scanner, SimulationOptions options)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  validate(scanner, scanner.name);
  d.scanner = scanner;
  d.volume.emplace(scanner);
  d.face_count = part.faces.size();
  d.specular.assign(d.face_count + 1, 0);
  for (int id : options.specular_faces) {
    part.face(id);  // throws for an unknown id
    d.specular[id] = 1;
  }
  // Points on the exact surface lie up to the mesh's chordal tolerance under its facets
  // where the surface is concave: the rays start above that.
  d.offset = std::max(
      {options.surface_offset * part.bounds().diagonal(), 1e-4, 1.1 * part.linear_deflection});
  d.options = std::move(options);

  // The part in the world, then the fixtures (face id 0).
  const Pose& placement = d.options.part_to_world;
  d.world.vertices.reserve(part.mesh.vertices.size());
  for (const Vec3& v : part.mesh.vertices) d.world.vertices.push_back(placement * v);
  d.world.triangles = part.mesh.triangles;
  d.world.triangle_faces = part.mesh.triangle_faces;
  d.part_triangles = d.world.triangles.size();
  d.solid = !part.solids.empty();
  for (const TriangleMesh& fixture : d.options.fixtures) d.world.append(fixture, 0);
  d.caster = std::make_unique<RayCaster>(d.world);
  if (!d.options.covered.empty()) {
    for (const CoveredSpot& spot : d.options.covered) d.spot_centres.push_back(spot.centre);
    d.spot_cloud =
        std::make_unique<detail::PointCloudAdaptor>(detail::PointCloudAdaptor{d.spot_centres});
    d.spots = std::make_unique<detail::PointTree>(3, *d.spot_cloud);
    d.spots->buildIndex();
  }

  d.facets.resize(d.part_triangles);
  d.facet_area.resize(d.part_triangles);
  tbb::parallel_for(std::size_t{0}, d.part_triangles, [&](std::size_t t) {
    const Vec3i& tri = d.world.triangles[t];
    d.facets[t].position =
        (d.world.vertices[tri[0]] + d.world.vertices[tri[1]] + d.world.vertices[tri[2]]) / 3;
    d.facets[t].normal = d.world.normal(t);
    d.facets[t].face = d.world.triangle_faces[t];
    d.facet_area[t] = d.world.area(t);
  });

  // Cells of a quarter of the depth of field: small enough to cull, large enough to be few.
  d.cells.emplace(std::span<const SurfacePoint>(d.facets.data(), d.part_triangles),
                  scanner.depth_of_field / 4, false);
}

Simulator::~Simulator() = default;
Simulator::Simulator(Simulator&&) noexcept = default;
Simulator& Simulator::operator=(Simulator&&) noexcept = default;

const Scanner& Simulator::scanner() const { return impl_->scanner; }

const SimulationOptions& Simulator::options() const { return impl_->options; }

double Simulator::surfaceOffset() const { return impl_->offset; }

std::vector<bool> Simulator::occluded(std::span<const Ray> rays) const {
  return impl_->caster->occluded(rays);
}

bool Simulator::insideSolid(const Vec3& point) const {
  const Impl& d = *impl_;
  if (!d.solid) return false;
  // Upwards, tilted off the axes so as not to graze the edges of axis-aligned faces.
  const Vec3 up = Vec3(0.0123, 0.0371, 1).normalized();
  const std::optional<RayHit> hit = d.caster->intersect(Ray{point, up});
  return hit && hit->triangle < static_cast<int>(d.part_triangles) && hit->normal.dot(up) > 0;
}

std::vector<SurfacePoint> Simulator::facetPoints() const { return impl_->facets; }

std::vector<SurfacePoint> Simulator::surfacePoints(double spacing, std::uint64_t seed) const {
  const Impl& d = *impl_;
  std::mt19937_64 random(seed);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::vector<SurfacePoint> points;
  const double cell = spacing * spacing;
  for (std::size_t t = 0; t < d.part_triangles; ++t) {
    // Whole expected count, plus one more with the probability of the fraction.
    const double expected = d.facet_area[t] / cell;
    auto count = static_cast<std::size_t>(expected);
    if (uniform(random) < expected - static_cast<double>(count)) ++count;
    const auto& tri = d.world.triangles[t];
    const Vec3 &a = d.world.vertices[tri[0]], &b = d.world.vertices[tri[1]],
               &c = d.world.vertices[tri[2]];
    for (std::size_t k = 0; k < count; ++k) {
      double u = uniform(random), v = uniform(random);
      if (u + v > 1) u = 1 - u, v = 1 - v;
      points.push_back({a + u * (b - a) + v * (c - a), d.facets[t].normal, d.facets[t].face});
    }
  }
  return points;
}

std::vector<Loss> Simulator::measure(const View& view, std::span<const SurfacePoint> points) const {
  return impl_->measure(view, points, nullptr, nullptr);
}

std::vector<std::vector<Loss>> Simulator::measure(std::span<const View> views,
                                                  std::span<const SurfacePoint> points) const {
  std::vector<std::vector<Loss>> result(views.size());
  tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t v) {
    result[v] = impl_->measure(views[v], points, nullptr, nullptr);
  });
  return result;
}

std::vector<Loss> Simulator::measurePairs(std::span<const View> views,
                                          std::span<const SurfacePoint> points) const {
  const Impl& d = *impl_;
  std::vector<Loss> losses(points.size());
  std::vector<std::optional<ViewGeometry>> geometries(points.size());
  tbb::parallel_for(std::size_t{0}, points.size(),
                    [&](std::size_t i) { geometries[i].emplace(views[i], *d.volume); });
  std::vector<std::size_t> all(points.size());
  std::iota(all.begin(), all.end(), std::size_t{0});
  d.testWithRays(
      points, all, [&](std::size_t i) -> const ViewGeometry& { return *geometries[i]; }, losses,
      nullptr);
  return losses;
}

Acquisition Simulator::acquire(const View& view) const {
  const Impl& d = *impl_;
  Acquisition acquisition;
  acquisition.view_id = view.id;
  const ViewGeometry geometry(view, *d.volume);
  const std::vector<std::size_t> reachable = d.cells->reaching(geometry);
  acquisition.facets = d.measure(view, d.facets, &reachable, &acquisition.rays);
  acquisition.face_area.assign(d.face_count, 0.0);
  for (std::size_t t = 0; t < acquisition.facets.size(); ++t) {
    Loss loss = acquisition.facets[t];
    ++acquisition.counts[static_cast<int>(loss)];
    if (loss != Loss::Measured) continue;
    acquisition.face_area[d.facets[t].face - 1] += d.facet_area[t];
    acquisition.measured_area += d.facet_area[t];
  }
  return acquisition;
}

std::vector<Acquisition> Simulator::acquire(std::span<const View> views) const {
  std::vector<Acquisition> result(views.size());
  tbb::parallel_for(std::size_t{0}, views.size(),
                    [&](std::size_t v) { result[v] = acquire(views[v]); });
  return result;
}

PointCloud Simulator::cloud(const View& view, std::uint64_t seed, double spacing) const {
  CloudRays made = rays(view, spacing);
  const std::vector<Vec3> noise = noiseOf(made, seed);
  for (std::size_t i = 0; i < noise.size(); ++i) made.cloud.points[i] += noise[i];
  return std::move(made.cloud);
}

CloudRays Simulator::rays(const View& view, double spacing) const {
  const Impl& d = *impl_;
  const Scanner& s = d.scanner;
  const ViewGeometry geometry(view, *d.volume);
  if (!(spacing > 0)) spacing = s.point_spacing;
  const CloudGrid grid{spacing, static_cast<int>(std::floor(s.fov_width / spacing)),
                       static_cast<int>(std::floor(s.fov_height / spacing)), view.id};
  const std::vector<Eye> all = eyes(view, s);
  // Rows are simulated in blocks to bound memory; each row has its own random stream so
  // that the cloud does not depend on thread scheduling.
  std::vector<CloudRays> rows(all.size() * static_cast<std::size_t>(grid.rows));
  constexpr int kBlock = 32;
  for (std::size_t e = 0; e < all.size(); ++e)
    for (int first = 0; first < grid.rows; first += kBlock)
      d.cloudBlock(geometry, all, e, grid, first, std::min(grid.rows, first + kBlock),
                   rows.data() + e * grid.rows);
  CloudRays made;
  PointCloud& cloud = made.cloud;
  const auto append = [](auto& to, const auto& from) {
    to.insert(to.end(), from.begin(), from.end());
  };
  for (const CloudRays& row : rows) {
    append(cloud.points, row.cloud.points);
    append(cloud.normals, row.cloud.normals);
    append(cloud.faces, row.cloud.faces);
    append(cloud.incidence, row.cloud.incidence);
    append(cloud.hits, row.cloud.hits);
    append(made.along, row.along);
    append(made.sigma, row.sigma);
    made.row_streams.push_back(row.row_streams.front());
    made.row_ends.push_back(made.sigma.size());
  }
  return made;
}

std::vector<Vec3> noiseOf(const CloudRays& rays, std::uint64_t seed) {
  std::vector<Vec3> noise(rays.sigma.size());
  tbb::parallel_for(std::size_t{0}, rays.row_streams.size(), [&](std::size_t r) {
    std::mt19937_64 random(seed * 0x9E3779B97F4A7C15ULL + rays.row_streams[r]);
    std::normal_distribution<double> normal(0.0, 1.0);
    for (std::size_t i = r == 0 ? 0 : rays.row_ends[r - 1]; i < rays.row_ends[r]; ++i)
      noise[i] = rays.sigma[i] * normal(random) * rays.along[i];
  });
  return noise;
}

// The points in cells a fortieth of the diagonal of their box across.
struct IndexedPoints::Impl {
  explicit Impl(std::vector<SurfacePoint> all)
      : points(std::move(all)), cells(points, size(), true) {}
  double size() const {
    Box box;
    for (const SurfacePoint& p : points) box.add(p.position);
    return std::max(box.diagonal() / 40, 1e-6);
  }
  std::vector<SurfacePoint> points;
  Cells cells;
};

IndexedPoints::IndexedPoints(std::vector<SurfacePoint> points)
    : impl_(std::make_unique<Impl>(std::move(points))) {}
IndexedPoints::~IndexedPoints() = default;
IndexedPoints::IndexedPoints(IndexedPoints&&) noexcept = default;

const std::vector<SurfacePoint>& IndexedPoints::points() const { return impl_->points; }

std::vector<std::vector<int>> IndexedPoints::measured(const Simulator& simulator,
                                                      std::span<const View> views) const {
  std::vector<std::vector<int>> result(views.size());
  if (impl_->points.empty()) return result;
  const Volume volume(simulator.scanner());
  tbb::parallel_for(std::size_t{0}, views.size(), [&](std::size_t v) {
    // Only the points of groups that reach the measuring volume and may face the view can
    // be measured.
    const std::vector<std::size_t> near = impl_->cells.facing(ViewGeometry(views[v], volume));
    std::vector<SurfacePoint> subset;
    subset.reserve(near.size());
    for (std::size_t i : near) subset.push_back(impl_->points[i]);
    const std::vector<Loss> losses = simulator.measure(views[v], subset);
    for (std::size_t k = 0; k < losses.size(); ++k)
      if (losses[k] == Loss::Measured) result[v].push_back(static_cast<int>(near[k]));
    std::sort(result[v].begin(), result[v].end());
  });
  return result;
}

std::vector<std::vector<int>> measuredPoints(const Simulator& simulator,
                                             std::span<const View> views,
                                             std::span<const SurfacePoint> points) {
  if (points.empty()) return std::vector<std::vector<int>>(views.size());
  return IndexedPoints({points.begin(), points.end()}).measured(simulator, views);
}

PointQuality pointQuality(const Scanner& scanner, const View& view, const Vec3& position,
                          const Vec3& normal) {
  const Vec3 ray = position - view.camera();
  const double z = ray.dot(view.axis()) / scanner.standoff;
  const double cosine = std::max(-ray.normalized().dot(normal), 1e-3);
  const double pitch = scanner.point_spacing * z;
  const double sigma = scanner.noise_sigma * z * z / cosine;
  return {sigma, sigma * cosine, cosine / (pitch * pitch)};
}

}  // namespace scanplan
