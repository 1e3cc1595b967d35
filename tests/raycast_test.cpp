// RayCaster against analytic truth on unit cubes.

#include "support.h"

#include <scanplan/cad/raycast.h>

namespace scanplan {
namespace {

TriangleMesh unitCube() {
  TriangleMesh mesh;
  test::addCube(mesh, Vec3::Zero(), 1.0, 1);
  return mesh;
}

TEST(RayCaster, CubeIsClosedAndOutward) {
  TriangleMesh cube = unitCube();
  EXPECT_NEAR(signedVolume(cube), 1.0, 1e-12);
  EdgeReport edges = edgeReport(cube, 0);
  EXPECT_EQ(edges.edges, 18u);
  EXPECT_EQ(edges.boundary + edges.non_manifold + edges.misoriented, 0u);
}

TEST(Mesh, ClosestPointOnTriangleInEachRegion) {
  const Vec3 a(0, 0, 0), b(4, 0, 0), c(0, 4, 0);
  EXPECT_TRUE(closestPointOnTriangle(Vec3(1, 1, 5), a, b, c).isApprox(Vec3(1, 1, 0)));   // interior
  EXPECT_TRUE(closestPointOnTriangle(Vec3(-1, -1, 2), a, b, c).isApprox(a));             // vertex a
  EXPECT_TRUE(closestPointOnTriangle(Vec3(6, -1, 0), a, b, c).isApprox(b));              // vertex b
  EXPECT_TRUE(closestPointOnTriangle(Vec3(2, -3, 1), a, b, c).isApprox(Vec3(2, 0, 0)));  // edge ab
  EXPECT_TRUE(closestPointOnTriangle(Vec3(3, 3, 0), a, b, c).isApprox(Vec3(2, 2, 0)));   // edge bc
  EXPECT_TRUE(closestPointOnTriangle(Vec3(-2, 1, 0), a, b, c).isApprox(Vec3(0, 1, 0)));  // edge ca
}

TEST(RayCaster, HitsEachSideAtKnownDistanceAndNormal) {
  RayCaster caster(unitCube());
  // From 2 units outside each face centre, towards the cube centre.
  for (int axis = 0; axis < 3; ++axis)
    for (double sign : {-1.0, 1.0}) {
      Vec3 n = Vec3::Zero();
      n[axis] = sign;
      Ray ray{Vec3(0.5, 0.5, 0.5) + 2.5 * n, -n};
      auto hit = caster.intersect(ray);
      ASSERT_TRUE(hit) << "axis " << axis << " sign " << sign;
      EXPECT_NEAR(hit->t, 2.0, 1e-6);
      EXPECT_TRUE(hit->normal.isApprox(n, 1e-9)) << hit->normal.transpose();
      EXPECT_TRUE(hit->point.isApprox(Vec3(0.5, 0.5, 0.5) + 0.5 * n, 1e-6));
      EXPECT_EQ(hit->face, 1);
    }
}

TEST(RayCaster, HitsAtAnObliqueAngle) {
  RayCaster caster(unitCube());
  // Aimed at (0.25, 0.75, 1) on the top from 45 degrees: distance sqrt(2).
  Vec3 target(0.25, 0.75, 1.0);
  Vec3 direction = Vec3(1, 0, -1).normalized();
  auto hit = caster.intersect(Ray{target - std::sqrt(2.0) * direction, direction});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, std::sqrt(2.0), 1e-6);
  EXPECT_TRUE(hit->point.isApprox(target, 1e-6));
}

TEST(RayCaster, MissesBesideTheCube) {
  RayCaster caster(unitCube());
  EXPECT_FALSE(caster.intersect(Ray{Vec3(1.5, 0.5, 3), -Vec3::UnitZ()}));
  EXPECT_FALSE(caster.occluded(Ray{Vec3(1.5, 0.5, 3), -Vec3::UnitZ()}));
  // Pointing away from the cube.
  EXPECT_FALSE(caster.intersect(Ray{Vec3(0.5, 0.5, 3), Vec3::UnitZ()}));
}

TEST(RayCaster, SegmentEndingShortOfTheCubeIsFree) {
  RayCaster caster(unitCube());
  Ray ray{Vec3(0.5, 0.5, 3), -Vec3::UnitZ(), 0, 1.9};  // stops 0.1 above the top
  EXPECT_FALSE(caster.occluded(ray));
  ray.t_far = 2.1;
  EXPECT_TRUE(caster.occluded(ray));
}

TEST(RayCaster, RayThroughVertex) {
  RayCaster caster(unitCube());
  Vec3 direction = Vec3(1, 1, 1).normalized();
  auto hit = caster.intersect(Ray{Vec3(-1, -1, -1), direction});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, std::sqrt(3.0), 1e-5);
  EXPECT_TRUE(hit->point.isApprox(Vec3::Zero(), 1e-5) || hit->point.norm() < 1e-5);
}

TEST(RayCaster, RayAlongAnEdgeEntersAtTheCorner) {
  // Along the edge y = z = 0: the ray crosses the face x = 0 at its corner (0, 0, 0).
  // Embree's watertight test must not let it slip between the triangles there.
  RayCaster caster(unitCube());
  auto hit = caster.intersect(Ray{Vec3(-1, 0, 0), Vec3::UnitX()});
  ASSERT_TRUE(hit);
  EXPECT_NEAR(hit->t, 1.0, 1e-5);
}

TEST(RayCaster, RayGrazingAboveAFaceMisses) {
  RayCaster caster(unitCube());
  EXPECT_FALSE(caster.intersect(Ray{Vec3(-1, 0.5, 1.0 + 1e-4), Vec3::UnitX()}));
}

TEST(RayCaster, BoxInFrontOccludesBoxBehind) {
  TriangleMesh mesh;
  test::addCube(mesh, Vec3(0, 0, 0), 1.0, 1);  // behind
  test::addCube(mesh, Vec3(0, 0, 3), 1.0, 2);  // in front, seen from +z
  RayCaster caster(mesh);
  // From the top of the back box (offset along its normal) to a camera above both.
  Vec3 point(0.5, 0.5, 1.0 + 1e-6), camera(0.5, 0.5, 10);
  Ray to_camera{point, camera - point, 0, 1};
  EXPECT_TRUE(caster.occluded(to_camera));
  auto hit = caster.intersect(to_camera);
  ASSERT_TRUE(hit);
  EXPECT_EQ(hit->face, 2);
  EXPECT_NEAR(hit->point.z(), 3.0, 1e-5);
  // A camera off to the side sees past the front box.
  Vec3 side_camera(5, 0.5, 1.5);
  EXPECT_FALSE(caster.occluded(Ray{point, side_camera - point, 0, 1}));
}

// Batches are traced as coherent packets: where a ray meets the edge two triangles share
// (the diagonals of the cubes' faces here), a batch may report either triangle; the face
// and the point are the same.
TEST(RayCaster, BatchedQueriesHitWhereSingleOnesDo) {
  TriangleMesh mesh;
  test::addCube(mesh, Vec3(0, 0, 0), 1.0, 1);
  test::addCube(mesh, Vec3(0.25, 0.25, 3), 0.5, 2);
  RayCaster caster(mesh);
  std::vector<Ray> rays;
  for (int i = 0; i < 40; ++i)
    for (int j = 0; j < 40; ++j)
      rays.push_back(Ray{Vec3(-0.4875 + 0.05 * i, -0.4875 + 0.05 * j, 10), -Vec3::UnitZ()});
  auto hits = caster.intersect(rays);
  auto blocked = caster.occluded(rays);
  ASSERT_EQ(hits.size(), rays.size());
  int front = 0, back = 0;
  for (std::size_t r = 0; r < rays.size(); ++r) {
    auto single = caster.intersect(rays[r]);
    ASSERT_EQ(hits[r].has_value(), single.has_value());
    EXPECT_EQ(blocked[r], single.has_value());
    if (!single) continue;
    EXPECT_EQ(hits[r]->face, single->face);
    EXPECT_NEAR((hits[r]->point - single->point).norm(), 0, 1e-6);
    // Analytic truth: inside the small box's shadow the top of it at z = 3.5.
    const Vec3& o = rays[r].origin;
    bool over_small = o.x() > 0.25 && o.x() < 0.75 && o.y() > 0.25 && o.y() < 0.75;
    EXPECT_EQ(single->face, over_small ? 2 : 1);
    EXPECT_NEAR(single->point.z(), over_small ? 3.5 : 1.0, 1e-5);
    (over_small ? front : back)++;
  }
  EXPECT_GT(front, 0);
  EXPECT_GT(back, 0);
  EXPECT_EQ(castRays(mesh, rays).size(), rays.size());
}

TEST(RayCaster, LargeBatchesSplitIntoPackets) {
  // Far more rays than one packet per task: every ray aimed at the top of the cube hits it
  // at z = 1, every ray beside it misses.
  RayCaster caster(unitCube());
  std::vector<Ray> rays;
  for (int i = 0; i < 200000; ++i) {
    const double x = (i % 2 == 0) ? 0.5 : 3.0;
    rays.push_back(Ray{Vec3(x, 0.25 + 0.5 * (i % 7) / 7.0, 5), -Vec3::UnitZ()});
  }
  auto hits = caster.intersect(rays);
  auto blocked = caster.occluded(rays);
  for (std::size_t i = 0; i < rays.size(); ++i) {
    ASSERT_EQ(hits[i].has_value(), i % 2 == 0) << i;
    ASSERT_EQ(blocked[i], i % 2 == 0) << i;
    if (hits[i]) {
      ASSERT_NEAR(hits[i]->point.z(), 1.0, 1e-5);
    }
  }
}

TEST(RayCaster, EmptyMeshHitsNothing) {
  RayCaster caster{TriangleMesh{}};
  EXPECT_FALSE(caster.intersect(Ray{Vec3::Zero(), Vec3::UnitZ()}));
  EXPECT_EQ(caster.triangleCount(), 0u);
}

}  // namespace
}  // namespace scanplan
