// The robot's arm against the part: capsules for the upper arm, the forearm and the wrist,
// tested with FCL against one bounding-volume hierarchy (OBB/RSS) of the part's and the
// fixtures' triangles, and against the working plane.

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

}  // namespace

CellCollisions::CellCollisions(const Cell& cell, const TriangleMesh& part,
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
  if (!d.links.empty()) return d.meshesCollide(pose);
  for (const Capsule& c : links(pose)) {
    const double radius = c.radius + d.margin;
    if (d.working_plane && std::min(c.a.z(), c.b.z()) - radius < 0) return true;
    if (!d.scene) continue;
    const Vec3 axis = c.b - c.a;
    const double length = axis.norm();
    // FCL's capsule lies along its z axis, centred on the origin.
    fcl::Transform3d placement = fcl::Transform3d::Identity();
    placement.translation() = 0.5 * (c.a + c.b);
    if (length > 1e-9)
      placement.linear() =
          Eigen::Quaterniond::FromTwoVectors(Vec3::UnitZ(), axis / length).toRotationMatrix();
    const fcl::CollisionObjectd link(std::make_shared<fcl::Capsuled>(radius, length), placement);
    fcl::CollisionRequestd request;
    fcl::CollisionResultd result;
    if (fcl::collide(&link, d.scene.get(), request, result) > 0) return true;
  }
  return false;
}

}  // namespace scanplan
