// Coverage by area (planning/coverage_area.h) against analytic cases: a cube seen from above
// and a plate half inside the field of view.

#include "support.h"

#include <scanplan/planning/coverage_area.h>
#include <scanplan/spec/spec.h>

namespace scanplan {
namespace {

// The default scanner looking straight down at (x, 0, z): its measuring volume's centre
// there, its x along the world's x.
View lookingDown(double x, double z) {
  View view;
  view.id = 1;
  Eigen::Matrix3d r;
  r << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  view.camera_to_world.linear() = r;
  view.camera_to_world.translation() = Vec3(x, 0, z + Scanner{}.standoff);
  view.target = Vec3(x, 0, z);
  return view;
}

Plan planOf(const View& view) {
  Plan plan;
  plan.views = {view};
  return plan;
}

// Every area point stands for its share of a triangle: they add up to the mesh's area, and
// they lie on it.
TEST(CoverageArea, AreaPointsAddUpToTheMeshArea) {
  TriangleMesh mesh;
  test::addRectangle(mesh, Vec3(0, 0, 0), Vec3(70, 0, 0), Vec3(0, 20, 0), 1);  // 140 x 40
  const AreaPoints points = areaPoints(mesh, 3);
  double area = 0;
  for (std::size_t i = 0; i < points.points.size(); ++i) {
    area += points.area[i];
    EXPECT_NEAR(points.points[i].position.z(), 0, 1e-12);
    EXPECT_LE(std::abs(points.points[i].position.x()), 70);
  }
  EXPECT_NEAR(area, 140 * 40, 1e-6);
  // Each triangle's longest side, the 145.6 mm diagonal, cut into 49 parts of at most 3 mm:
  // 49² points a triangle.
  EXPECT_EQ(points.points.size(), 2u * 49 * 49);
}

// A 100 mm cube standing on the plane, seen from straight above at its top: the top face
// whole, the sides (seen at 90°, beyond the camera's 60°) and the bottom not at all.
TEST(CoverageArea, ACubeSeenFromAboveHasItsTopMeasuredWhole) {
  TriangleMesh mesh;
  const double h = 50;
  test::addRectangle(mesh, Vec3(0, 0, 2 * h), Vec3(h, 0, 0), Vec3(0, h, 0), 1);  // top, +z
  test::addRectangle(mesh, Vec3(0, 0, 0), Vec3(0, h, 0), Vec3(h, 0, 0), 2);      // bottom, -z
  test::addRectangle(mesh, Vec3(h, 0, h), Vec3(0, h, 0), Vec3(0, 0, h), 3);      // +x
  test::addRectangle(mesh, Vec3(-h, 0, h), Vec3(0, 0, h), Vec3(0, h, 0), 4);     // -x
  test::addRectangle(mesh, Vec3(0, h, h), Vec3(0, 0, h), Vec3(h, 0, 0), 5);      // +y
  test::addRectangle(mesh, Vec3(0, -h, h), Vec3(h, 0, 0), Vec3(0, 0, h), 6);     // -y
  const Part part = test::meshPart(mesh);
  const std::vector<FaceArea> faces =
      measuredArea(part, resolveSpec(part, defaultSpec()), planOf(lookingDown(0, 2 * h)));
  ASSERT_EQ(faces.size(), 6u);
  for (const FaceArea& f : faces) EXPECT_NEAR(f.area, 4 * h * h, 1e-6) << f.face;
  EXPECT_NEAR(faces[0].measured / faces[0].area, 1, 0.01);
  for (int f = 1; f < 6; ++f) EXPECT_EQ(faces[f].measured, 0) << f + 1;
}

// A 300 x 100 mm plate at the standoff from x = 0 to 300, the view centred on x = 0: the
// field, 300 mm wide there, reaches x = 150, half the plate.
TEST(CoverageArea, APlateHalfInTheFieldIsHalfMeasured) {
  TriangleMesh mesh;
  test::addRectangle(mesh, Vec3(150, 0, 0), Vec3(150, 0, 0), Vec3(0, 50, 0), 1);
  const Part part = test::meshPart(mesh);
  const std::vector<FaceArea> faces =
      measuredArea(part, resolveSpec(part, defaultSpec()), planOf(lookingDown(0, 0)));
  ASSERT_EQ(faces.size(), 1u);
  EXPECT_NEAR(faces[0].area, 300 * 100, 1e-6);
  EXPECT_NEAR(faces[0].measured / faces[0].area, 0.5, 0.01);
}

}  // namespace
}  // namespace scanplan
