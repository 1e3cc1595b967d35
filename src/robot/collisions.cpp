// The robot's arm against the part: capsules for the upper arm, the forearm and the wrist,
// tested with FCL against one bounding-volume hierarchy (OBB/RSS) of the part's and the
// fixtures' triangles, and against the working plane.

#include <scanplan/cell.h>
#include <scanplan/errors.h>

#include <fcl/fcl.h>

namespace scanplan {

struct CellCollisions::Impl {
  Cell cell;
  double margin = 0;
  bool working_plane = true;
  std::array<double, 3> radii{};
  std::shared_ptr<fcl::BVHModel<fcl::OBBRSSd>> model;
  std::unique_ptr<fcl::CollisionObjectd> scene;  // null when there are no triangles
};

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
  if (d.radii[0] <= 0) d.radii[0] = 0.1 * r.c2 + 20;
  if (d.radii[1] <= 0) d.radii[1] = 0.1 * std::hypot(r.a2, r.c3) + 20;
  if (d.radii[2] <= 0) d.radii[2] = 60;

  std::vector<fcl::Vector3d> vertices;
  std::vector<fcl::Triangle> triangles;
  auto add = [&](const TriangleMesh& mesh, const Pose& to_world) {
    const std::size_t base = vertices.size();
    for (const Vec3& v : mesh.vertices) vertices.push_back(to_world * v);
    for (const Vec3i& t : mesh.triangles)
      triangles.emplace_back(base + t[0], base + t[1], base + t[2]);
  };
  add(part, part_to_world);
  for (const TriangleMesh& fixture : fixtures) add(fixture, Pose::Identity());
  if (triangles.empty()) return;
  d.model = std::make_shared<fcl::BVHModel<fcl::OBBRSSd>>();
  if (d.model->beginModel() != fcl::BVH_OK ||
      d.model->addSubModel(vertices, triangles) != fcl::BVH_OK ||
      d.model->endModel() != fcl::BVH_OK)
    throw LibraryError("FCL", "could not build the collision model of the part");
  d.scene = std::make_unique<fcl::CollisionObjectd>(d.model);
}

CellCollisions::~CellCollisions() = default;

std::vector<CellCollisions::Capsule> CellCollisions::links(const CellPose& pose) const {
  const Impl& d = *impl_;
  const std::array<Vec3, 4> joints = jointCentres(d.cell.robot, pose.joints);
  // Base frame to world, then back with the table to the plan's frame (the part at 0).
  Pose to_plan = d.cell.base;
  if (d.cell.table) {
    const RotaryTable& t = *d.cell.table;
    to_plan = Eigen::Translation3d(t.origin) * Eigen::AngleAxisd(-pose.table_angle, t.axis) *
              Eigen::Translation3d(-t.origin) * to_plan;
  }
  std::vector<Capsule> capsules;
  for (int k = 0; k < 3; ++k)
    capsules.push_back({to_plan * joints[k], to_plan * joints[k + 1], d.radii[k]});
  return capsules;
}

bool CellCollisions::collides(const CellPose& pose) const {
  const Impl& d = *impl_;
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
