// The robot's arm and the scanner it carries against the part: capsules (or meshes) for
// the upper arm, the forearm and the wrist and a box for the scanner body, tested with FCL
// against one bounding-volume hierarchy (OBB/RSS) of the part's and the fixtures'
// triangles, and against the working plane.

#include <scanplan/core/errors.h>
#include <scanplan/robot/cell.h>

#include <fcl/fcl.h>

namespace scanplan {

struct CellCollisions::Impl {
  Cell cell;
  double margin = 0;
  bool working_plane = true;
  std::array<double, 3> radii{};
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> model;
  std::unique_ptr<fcl::CollisionObjectd> scene;  // null when there are no triangles
  std::vector<std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>>> links;  // the cell's link meshes
  std::vector<std::vector<Vec3>> link_vertices;                     // for the working plane
  double top = 0;                                                   // highest scene z
  // The scanner body grown by the margin, and its centre in the flange frame.
  std::shared_ptr<fcl::Boxd> body;
  Pose body_in_flange = Pose::Identity();
  // Bounds on how far a point of the robot or the scanner lies from each joint's axis and
  // from the table's axis, and a scene point from the table's axis, mm (travelBound).
  Joints axis_radii{};
  double table_radius = 0;

  // The robot's base frame carried into the plan's frame (the part at table angle 0).
  Pose toPlan(const CellPose& pose) const { return tableTurn(cell, -pose.table_angle) * cell.base; }

  bool meshesCollide(const CellPose& pose) const {
    const Pose to_plan = toPlan(pose);
    const std::array<Pose, 3> motions = linkMotions(cell.robot, pose.joints);
    for (std::size_t k = 0; k < links.size() && k < 3; ++k) {
      const Pose placed = to_plan * motions[k];
      if (working_plane)
        for (const Vec3& v : link_vertices[k])
          if ((placed * v).z() < margin) return true;
      if (!scene) continue;
      const fcl::CollisionObjectd link(links[k], fcl::Transform3d(placed.matrix()));
      fcl::DistanceRequestd request;
      fcl::DistanceResultd result;
      if (fcl::distance(&link, scene.get(), request, result) < margin) return true;
    }
    return false;
  }

  bool capsulesCollide(const std::vector<Capsule>& capsules) const {
    for (const Capsule& c : capsules) {
      const double radius = c.radius + margin;
      if (working_plane && std::min(c.a.z(), c.b.z()) - radius < 0) return true;
      if (!scene) continue;
      const Vec3 axis = c.b - c.a;
      const double length = axis.norm();
      // FCL's capsule lies along its z axis, centred on the origin.
      fcl::Transform3d placement = fcl::Transform3d::Identity();
      placement.translation() = 0.5 * (c.a + c.b);
      if (length > 1e-9)
        placement.linear() =
            Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis / length).toRotationMatrix();
      if (collidesWithScene(std::make_shared<fcl::Capsuled>(radius, length), placement))
        return true;
    }
    return false;
  }

  bool bodyCollides(const CellPose& pose) const {
    if (!body) return false;
    const Pose placed = toPlan(pose) * forwardKinematics(cell.robot, pose.joints) * body_in_flange;
    if (working_plane)
      for (int i = 0; i < 8; ++i) {
        const Vec3 corner((i & 1 ? 0.5 : -0.5) * body->side.x(),
                          (i & 2 ? 0.5 : -0.5) * body->side.y(),
                          (i & 4 ? 0.5 : -0.5) * body->side.z());
        if ((placed * corner).z() < 0) return true;
      }
    return scene && collidesWithScene(body, fcl::Transform3d(placed.matrix()));
  }

  bool collidesWithScene(const std::shared_ptr<fcl::CollisionGeometryd>& shape,
                         const fcl::Transform3d& placement) const {
    const fcl::CollisionObjectd object(shape, placement);
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    return fcl::collide(&object, scene.get(), request, result) > 0;
  }
};

namespace {

std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> bvh(const std::vector<fcl::Vector3d>& vertices,
                                                 const std::vector<fcl::Triangle>& triangles) {
  auto model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  if (model->beginModel() != fcl::BVH_OK ||
      model->addSubModel(vertices, triangles) != fcl::BVH_OK || model->endModel() != fcl::BVH_OK)
    throw LibraryError("FCL", "could not build a collision model");
  return model;
}

// Adds `mesh` placed by `to_world` to the vertex and triangle lists.
void append(const TriangleMesh& mesh, const Pose& to_world, std::vector<fcl::Vector3d>& vertices,
            std::vector<fcl::Triangle>& triangles) {
  const std::size_t base = vertices.size();
  for (const Vec3& v : mesh.vertices) vertices.push_back(to_world * v);
  for (const Vec3i& t : mesh.triangles)
    triangles.emplace_back(base + t[0], base + t[1], base + t[2]);
}

double farthestFrom(const Vec3& point, const std::vector<Vec3>& vertices) {
  double farthest = 0;
  for (const Vec3& v : vertices) farthest = std::max(farthest, (v - point).norm());
  return farthest;
}

// Bounds on how far a point of the robot or of `tool` (a box in the flange frame) lies from
// each joint's axis in any configuration, mm. The chain base origin, shoulder, elbow, wrist
// centre and flange has links of fixed length (an offset wrist's last one at most |d4| +
// |d5| + |d6|); each body hangs on one point of it and reaches a fixed distance beyond.
Joints axisRadii(const RobotModel& r, const std::array<double, 3>& radii,
                 const std::vector<TriangleMesh>& link_meshes, double tool_reach) {
  const std::array<Vec3, 4> c = jointCentres(r, zeroPose(r));
  const std::array<Vec3, 5> chain = {Vec3::Zero(), c[0], c[1], c[2], c[3]};
  std::array<double, 4> link{};
  for (int t = 0; t < 4; ++t) link[t] = (chain[t + 1] - chain[t]).norm();
  if (r.offset_wrist) {
    const OffsetWrist& w = *r.offset_wrist;
    link[3] = std::abs(w.d4) + std::abs(w.d5) + std::abs(w.d6);
  }
  // Beyond chain point 1 to 4: the upper arm, the forearm, the wrist, the scanner.
  std::array<double, 5> beyond = {0, link[1] + radii[0], link[2] + radii[1], link[3] + radii[2],
                                  tool_reach};
  for (std::size_t k = 0; k < link_meshes.size() && k < 3; ++k)
    beyond[k + 1] = k < 2 ? farthestFrom(chain[k + 1], link_meshes[k].vertices)
                          : link[3] + farthestFrom(chain[4], link_meshes[k].vertices);
  auto radius = [&](int from) {
    double largest = 0;
    for (int a = std::max(from, 1); a < 5; ++a) {
      double length = beyond[a];
      for (int t = from; t < a; ++t) length += link[t];
      largest = std::max(largest, length);
    }
    return largest;
  };
  // Axes 5 and 6 pass within the last link of the wrist centre.
  return {radius(0), radius(1), radius(2), radius(3), radius(3) + link[3], radius(3) + link[3]};
}

double fromAxis(const Vec3& point, const Vec3& origin, const Vec3& axis) {
  const Vec3 offset = point - origin;
  return (offset - offset.dot(axis) * axis).norm();
}

}  // namespace

CellCollisions::CellCollisions(const Cell& cell, const Box& scanner_body, const TriangleMesh& part,
                               const Pose& part_to_world, const std::vector<TriangleMesh>& fixtures,
                               bool working_plane, double margin)
    : impl_(std::make_unique<Impl>()) {
  Impl& d = *impl_;
  d.cell = cell;
  d.margin = margin;
  d.working_plane = working_plane;
  const RobotModel& r = cell.robot;
  d.radii = r.link_radii;
  const double upper = r.offset_wrist ? std::abs(r.offset_wrist->a2) : r.c2;
  const double fore = r.offset_wrist ? std::abs(r.offset_wrist->a3) : std::hypot(r.a2, r.c3);
  if (d.radii[0] <= 0) d.radii[0] = 0.1 * upper + 20;
  if (d.radii[1] <= 0) d.radii[1] = 0.1 * fore + 20;
  if (d.radii[2] <= 0) d.radii[2] = 60;

  double tool_reach = 0;
  if (!scanner_body.empty()) {
    d.body = std::make_shared<fcl::Boxd>(scanner_body.size() + Vec3::Constant(2 * margin));
    d.body_in_flange = cell.mount * Eigen::Translation3d(scanner_body.center());
    for (int i = 0; i < 8; ++i) {
      const Vec3 corner(i & 1 ? scanner_body.max.x() : scanner_body.min.x(),
                        i & 2 ? scanner_body.max.y() : scanner_body.min.y(),
                        i & 4 ? scanner_body.max.z() : scanner_body.min.z());
      tool_reach = std::max(tool_reach, (cell.mount * corner).norm());
    }
  }
  d.axis_radii = axisRadii(r, d.radii, cell.link_meshes, tool_reach);

  for (const TriangleMesh& mesh : cell.link_meshes) {
    std::vector<fcl::Vector3d> vertices;
    std::vector<fcl::Triangle> triangles;
    append(mesh, Pose::Identity(), vertices, triangles);
    d.links.push_back(bvh(vertices, triangles));
    d.link_vertices.push_back(mesh.vertices);
  }
  std::vector<fcl::Vector3d> vertices;
  std::vector<fcl::Triangle> triangles;
  append(part, part_to_world, vertices, triangles);
  for (const TriangleMesh& fixture : fixtures)
    append(fixture, Pose::Identity(), vertices, triangles);
  if (cell.table) {
    // A turn of the table moves each robot point against the scene (and against the
    // working plane, unless the axis is vertical), or each scene point against the robot,
    // about its axis.
    const RotaryTable& t = *cell.table;
    double scene = 0;
    for (const fcl::Vector3d& v : vertices) scene = std::max(scene, fromAxis(v, t.origin, t.axis));
    const double robot = fromAxis(cell.base.translation(), t.origin, t.axis) + d.axis_radii[0];
    const bool vertical = std::abs(t.axis.normalized().z()) > 1 - 1e-9;
    d.table_radius = vertical || !working_plane ? std::min(scene, robot) : robot;
  }
  if (triangles.empty()) return;
  d.top = vertices.front().z();
  for (const fcl::Vector3d& v : vertices) d.top = std::max(d.top, v.z());
  d.model = bvh(vertices, triangles);
  d.scene = std::make_unique<fcl::CollisionObjectd>(d.model);
}

CellCollisions::~CellCollisions() = default;

double CellCollisions::top() const { return impl_->top; }

std::vector<CellCollisions::Capsule> CellCollisions::links(const CellPose& pose) const {
  const Impl& d = *impl_;
  const std::array<Vec3, 4> joints = jointCentres(d.cell.robot, pose.joints);
  const Pose to_plan = d.toPlan(pose);
  std::vector<Capsule> capsules;
  for (int k = 0; k < 3; ++k)
    capsules.push_back({to_plan * joints[k], to_plan * joints[k + 1], d.radii[k]});
  return capsules;
}

bool CellCollisions::collides(const CellPose& pose) const {
  const Impl& d = *impl_;
  if (!d.links.empty() ? d.meshesCollide(pose) : d.capsulesCollide(links(pose))) return true;
  return d.bodyCollides(pose);
}

double CellCollisions::travelBound(const CellPose& from, const CellPose& to) const {
  const Impl& d = *impl_;
  double bound = d.table_radius * std::abs(to.table_angle - from.table_angle);
  for (int j = 0; j < 6; ++j) bound += d.axis_radii[j] * std::abs(to.joints[j] - from.joints[j]);
  return bound;
}

double CellCollisions::sampleSpacing() const { return std::max(impl_->margin, 2.0) / 2; }

}  // namespace scanplan
