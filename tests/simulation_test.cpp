// The measurement test and the acquisition simulation against analytic truth, and on a
// real part against an independent brute-force ray cast.

#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/cloud_ply.h>
#include <scanplan/scanner/simulation.h>

#include <cmath>
#include <cstring>
#include <random>

namespace scanplan {
namespace {

// The default scanner looking along world +Z from the origin: S is the world frame, the
// volume centre is (0, 0, 400), the projector is at (400 tan 25°, 0, 0).
Scanner scanner() { return Scanner{}; }
View identityView() { return View{}; }

Vec3 centre() { return Vec3(0, 0, scanner().standoff); }

// A small box far outside the volume: a part that occludes nothing.
Part farPart() {
  TriangleMesh mesh;
  test::addCube(mesh, Vec3(5000, 5000, 5000), 1, 1);
  return test::meshPart(mesh);
}

SimulationOptions noPlane() {
  SimulationOptions options;
  options.working_plane = false;
  return options;
}

Loss measureOne(const Simulator& simulator, const SurfacePoint& point,
                const View& view = identityView()) {
  return simulator.measure(view, std::span<const SurfacePoint>(&point, 1)).front();
}

// The normal at the volume centre tilted by `angle` degrees from facing the camera,
// towards +X (the projector) or -X.
Vec3 tilted(double angle, double towards_x) {
  return Vec3(towards_x * std::sin(radians(angle)), 0, -std::cos(radians(angle)));
}

TEST(MeasurementTest, CameraAngleLimit) {
  // Tilting towards the projector: the camera angle is the tilt, the projector angle
  // |tilt - 25°| stays well inside its limit.
  Simulator simulator(farPart(), scanner(), noPlane());
  EXPECT_EQ(measureOne(simulator, {centre(), tilted(59.5, 1)}), Loss::Measured);
  EXPECT_EQ(measureOne(simulator, {centre(), tilted(60.5, 1)}), Loss::CameraAngle);
  EXPECT_EQ(measureOne(simulator, {centre(), tilted(0, 1)}), Loss::Measured);
  // Facing away from the camera.
  EXPECT_EQ(measureOne(simulator, {centre(), Vec3(0, 0, 1)}), Loss::CameraAngle);
}

TEST(MeasurementTest, ProjectorAngleLimit) {
  // Tilting away from the projector: projector angle = tilt + 25°, limit at 35° of tilt.
  Simulator simulator(farPart(), scanner(), noPlane());
  EXPECT_EQ(measureOne(simulator, {centre(), tilted(34.5, -1)}), Loss::Measured);
  EXPECT_EQ(measureOne(simulator, {centre(), tilted(35.5, -1)}), Loss::ProjectorAngle);
}

TEST(MeasurementTest, LimitsFollowTheScannerParameters) {
  Scanner narrow = scanner();
  narrow.max_camera_angle = 30;
  Simulator simulator(farPart(), narrow, noPlane());
  EXPECT_EQ(measureOne(simulator, {centre(), tilted(29.5, 1)}), Loss::Measured);
  EXPECT_EQ(measureOne(simulator, {centre(), tilted(30.5, 1)}), Loss::CameraAngle);
}

TEST(MeasurementTest, TiltedPlateFacetsFollowTheLimits) {
  // A 2 x 2 mm plate at the volume centre, tilted about the y axis towards the projector.
  for (double angle : {55.0, 59.0, 61.0, 65.0}) {
    TriangleMesh mesh;
    Vec3 u(std::cos(radians(angle)), 0, std::sin(radians(angle)));  // normal = u x v
    test::addRectangle(mesh, centre(), u, Vec3(0, -1, 0), 1);
    Part part = test::meshPart(mesh);
    Simulator simulator(part, scanner(), noPlane());
    Acquisition acquisition = simulator.acquire(identityView());
    const double area = part.area();
    if (angle < 60) {
      EXPECT_NEAR(acquisition.measured_area, area, 1e-9) << angle;
      EXPECT_EQ(acquisition.counts[0], 2u);
    } else {
      EXPECT_EQ(acquisition.measured_area, 0) << angle;
      EXPECT_EQ(acquisition.counts[static_cast<int>(Loss::CameraAngle)], 2u) << angle;
    }
  }
}

TEST(MeasurementTest, MeasuringVolumeFaces) {
  const Scanner s = scanner();
  Simulator simulator(farPart(), s, noPlane());
  const Vec3 facing(0, 0, -1);
  const double near = s.standoff - s.depth_of_field / 2, far = s.standoff + s.depth_of_field / 2;
  const double eps = 0.01;
  EXPECT_EQ(measureOne(simulator, {Vec3(0, 0, near + eps), facing}), Loss::Measured);
  EXPECT_EQ(measureOne(simulator, {Vec3(0, 0, near - eps), facing}), Loss::OutsideVolume);
  EXPECT_EQ(measureOne(simulator, {Vec3(0, 0, far - eps), facing}), Loss::Measured);
  EXPECT_EQ(measureOne(simulator, {Vec3(0, 0, far + eps), facing}), Loss::OutsideVolume);
  // The field widens linearly with depth: at depth z the half-width is fov/2 * z/standoff.
  for (double z : {near + 1, s.standoff, far - 1}) {
    const double half_w = s.fov_width / 2 * z / s.standoff,
                 half_h = s.fov_height / 2 * z / s.standoff;
    for (double sign : {-1.0, 1.0}) {
      EXPECT_EQ(measureOne(simulator, {Vec3(sign * (half_w - eps), 0, z), facing}), Loss::Measured)
          << z;
      EXPECT_EQ(measureOne(simulator, {Vec3(sign * (half_w + eps), 0, z), facing}),
                Loss::OutsideVolume)
          << z;
      EXPECT_EQ(measureOne(simulator, {Vec3(0, sign * (half_h - eps), z), facing}), Loss::Measured)
          << z;
      EXPECT_EQ(measureOne(simulator, {Vec3(0, sign * (half_h + eps), z), facing}),
                Loss::OutsideVolume)
          << z;
    }
  }
}

// A marker stuck on the surface covers what lies within its radius of its centre on its
// own surface: a point 3.9 mm from the centre of a 4 mm spot is lost under it; one 4.1 mm
// away is measured, and so is one 3 mm off the spot's plane (another surface). The marker
// itself (face 0) is seen.
TEST(MeasurementTest, AMarkerOnTheSurfaceCoversWhatLiesUnderIt) {
  SimulationOptions options = noPlane();
  const Vec3 facing(0, 0, -1);
  options.covered.push_back({centre(), facing, 4});
  const Simulator simulator(farPart(), scanner(), options);
  EXPECT_EQ(measureOne(simulator, {centre() + Vec3(3.9, 0, 0), facing, 1}), Loss::UnderMarker);
  EXPECT_EQ(measureOne(simulator, {centre() + Vec3(0, 4.1, 0), facing, 1}), Loss::Measured);
  EXPECT_EQ(measureOne(simulator, {centre() + Vec3(1, 0, 3), facing, 1}), Loss::Measured);
  EXPECT_EQ(measureOne(simulator, {centre(), facing, 0}), Loss::Measured);
  // underSpots judges the same points as the simulation, whatever the view.
  const std::vector<SurfacePoint> points = {{centre() + Vec3(3.9, 0, 0), facing, 1},
                                            {centre() + Vec3(0, 4.1, 0), facing, 1},
                                            {centre() + Vec3(1, 0, 3), facing, 1},
                                            {centre(), facing, 0}};
  EXPECT_EQ(underSpots(options.covered, points), (std::vector<char>{1, 0, 0, 0}));
  // Without the spot, the covered point is measured.
  const Simulator bare(farPart(), scanner(), noPlane());
  EXPECT_EQ(measureOne(bare, {centre() + Vec3(3.9, 0, 0), facing, 1}), Loss::Measured);
}

TEST(MeasurementTest, OccluderInFrontOfProjectorOnly) {
  // Target plate at the volume centre; a 20 mm cube halfway along the projector's ray.
  const double b = scanner().baseline();
  TriangleMesh mesh;
  test::addRectangle(mesh, centre(), Vec3(10, 0, 0), Vec3(0, -10, 0), 1);
  test::addCube(mesh, Vec3(b / 2 - 10, -10, 190), 20, 2);
  Simulator simulator(test::meshPart(mesh), scanner(), noPlane());
  EXPECT_EQ(measureOne(simulator, {centre(), Vec3(0, 0, -1), 1}), Loss::ProjectorOccluded);
}

TEST(MeasurementTest, OccluderInFrontOfCameraOnly) {
  TriangleMesh mesh;
  test::addRectangle(mesh, centre(), Vec3(10, 0, 0), Vec3(0, -10, 0), 1);
  test::addCube(mesh, Vec3(-10, -10, 190), 20,
                2);  // on the optical axis, clear of the projector ray
  Simulator simulator(test::meshPart(mesh), scanner(), noPlane());
  EXPECT_EQ(measureOne(simulator, {centre(), Vec3(0, 0, -1), 1}), Loss::CameraOccluded);
}

// A fringe head with a second camera at twice the baseline (docs/design.md §4): the
// identity view puts camera 1 at the origin, the projector at (b, 0, 0) and camera 2 at
// (2b, 0, 0). A 20 mm cube on camera 1's axis halfway to the plate hides the plate's
// centre from camera 1 only: camera 2's ray crosses z = 200 at x = b, the projector's at
// x = b / 2, both far from the cube's |x| <= 10.
TEST(MeasurementTest, ASecondCameraMeasuresWhatTheFirstCannotSee) {
  TriangleMesh mesh;
  test::addRectangle(mesh, centre(), Vec3(10, 0, 0), Vec3(0, -10, 0), 1);
  test::addCube(mesh, Vec3(-10, -10, 190), 20, 2);
  Scanner two = scanner();
  two.cameras = 2;
  const Part part = test::meshPart(mesh);
  const SurfacePoint point{centre(), Vec3(0, 0, -1), 1};
  EXPECT_EQ(measureOne(Simulator(part, scanner(), noPlane()), point), Loss::CameraOccluded);
  EXPECT_EQ(measureOne(Simulator(part, two, noPlane()), point), Loss::Measured);
  // A cube on camera 2's ray instead: camera 1 sees, so both models measure.
  TriangleMesh other;
  test::addRectangle(other, centre(), Vec3(10, 0, 0), Vec3(0, -10, 0), 1);
  const double b = scanner().baseline();
  test::addCube(other, Vec3(b - 10, -10, 190), 20, 2);
  EXPECT_EQ(measureOne(Simulator(test::meshPart(other), two, noPlane()), point), Loss::Measured);
  // Cubes before both cameras: occluded for the head too.
  test::addCube(mesh, Vec3(b - 10, -10, 190), 20, 2);
  EXPECT_EQ(measureOne(Simulator(test::meshPart(mesh), two, noPlane()), point),
            Loss::CameraOccluded);
  // The second camera sits in the scanner body.
  EXPECT_GE(two.body().max.x(), 2 * b);
  two.cameras = 3;
  EXPECT_THROW(validate(two, "head"), InputError);
}

TEST(MeasurementTest, FixturesOcclude) {
  SimulationOptions options = noPlane();
  TriangleMesh fixture;
  test::addCube(fixture, Vec3(-10, -10, 190), 20, 1);
  options.fixtures.push_back(fixture);
  Simulator simulator(farPart(), scanner(), options);
  EXPECT_EQ(measureOne(simulator, {centre(), Vec3(0, 0, -1)}), Loss::CameraOccluded);
}

TEST(MeasurementTest, WorkingPlane) {
  // A view looking down from z = 500 at a point at z = 100 on top of the part.
  View down;
  down.camera_to_world.linear() << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  down.camera_to_world.translation() = Vec3(0, 0, 500);
  SimulationOptions with_plane;
  Simulator simulator(farPart(), scanner(), with_plane);
  EXPECT_EQ(measureOne(simulator, {Vec3(0, 0, 100), Vec3(0, 0, 1)}, down), Loss::Measured);
  // Looking up from below the plane: the plane hides the point.
  View up = identityView();
  up.camera_to_world.translation() = Vec3(0, 0, -300);
  EXPECT_EQ(measureOne(simulator, {Vec3(0, 0, 100), Vec3(0, 0, -1)}, up), Loss::CameraOccluded);
  // Without the plane the same point is measured.
  Simulator free_space(farPart(), scanner(), noPlane());
  EXPECT_EQ(measureOne(free_space, {Vec3(0, 0, 100), Vec3(0, 0, -1)}, up), Loss::Measured);
}

TEST(MeasurementTest, SpecularReflection) {
  const Vec3 p = centre();
  const Vec3 to_camera = (Vec3::Zero() - p).normalized();
  const Vec3 to_projector = (scanner().projectorInScanner() - p).normalized();
  const Vec3 mirror = (to_camera + to_projector).normalized();  // reflects projector into camera
  auto rotated = [&](double angle) {  // about the y axis, away from the projector
    return Vec3(Eigen::AngleAxisd(radians(angle), Vec3::UnitY()) * mirror);
  };
  SimulationOptions options = noPlane();
  options.specular_faces = {1};
  Simulator simulator(farPart(), scanner(), options);
  EXPECT_EQ(measureOne(simulator, {p, mirror, 1}), Loss::Reflection);
  // Turning the face by a turns the reflection by 2a: 4° stays in the 10° cone, 6° leaves it.
  EXPECT_EQ(measureOne(simulator, {p, rotated(4), 1}), Loss::Reflection);
  EXPECT_EQ(measureOne(simulator, {p, rotated(6), 1}), Loss::Measured);
  EXPECT_EQ(measureOne(simulator, {p, rotated(11), 1}), Loss::Measured);
  // The same geometry on a face that is not specular is measured.
  EXPECT_EQ(measureOne(simulator, {p, mirror, 0}), Loss::Measured);
}

TEST(MeasurementTest, UnknownSpecularFaceIsAnError) {
  SimulationOptions options;
  options.specular_faces = {99};
  EXPECT_THROW(Simulator(farPart(), scanner(), options), InputError);
}

TEST(MeasurementTest, ManyViewsMatchOneByOne) {
  Part part = test::meshPart([] {
    TriangleMesh mesh;
    test::addRectangle(mesh, Vec3(0, 0, 400), Vec3(50, 0, 0), Vec3(0, -50, 0), 1);
    test::addCube(mesh, Vec3(-5, -5, 300), 10, 2);
    return mesh;
  }());
  Simulator simulator(part, scanner(), noPlane());
  std::vector<View> views(5);
  for (int v = 0; v < 5; ++v) {
    views[v].id = v + 1;
    views[v].camera_to_world.translation() = Vec3(20.0 * v, -10.0 * v, 0);
  }
  std::vector<SurfacePoint> points = simulator.facetPoints();
  auto all = simulator.measure(views, points);
  for (int v = 0; v < 5; ++v) EXPECT_EQ(all[v], simulator.measure(views[v], points));
}

// Measuring only the points whose cell reaches the volume and whose group of normals may
// face the view gives what testing every point gives: on patches tilted in quarter degrees
// across the cameras' and the projector's limits, and on points with random normals, seen
// by a two-camera head from views turned every way.
TEST(MeasurementTest, IndexedPointsMeasureWhatTestingEveryPointMeasures) {
  Scanner two = scanner();
  two.cameras = 2;
  Simulator simulator(farPart(), two, noPlane());
  std::vector<SurfacePoint> points;
  int face = 1;
  for (double tilt = 40; tilt <= 80; tilt += 0.25)
    for (const Vec3& towards : {Vec3(1, 0, 0), Vec3(-1, 0, 0), Vec3(0, 1, 0), Vec3(0, -1, 0)}) {
      const Vec3 normal =
          std::cos(radians(tilt)) * -Vec3::UnitZ() + std::sin(radians(tilt)) * towards;
      const Vec3 at = centre() + 3 * tilt * towards;
      for (int k = 0; k < 9; ++k) points.push_back({at + Vec3(k % 3, k / 3, 0), normal, face});
      ++face;
    }
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> spread(-60, 60);
  std::normal_distribution<double> normal(0, 1);
  for (int k = 0; k < 3000; ++k) {
    const Vec3 n(normal(random), normal(random), normal(random));
    points.push_back(
        {centre() + Vec3(spread(random), spread(random), spread(random)), n.normalized(), k % 4});
  }
  std::vector<View> views(24);
  for (std::size_t v = 0; v < views.size(); ++v) {
    const Vec3 axis = Vec3(normal(random), normal(random), normal(random)).normalized();
    views[v].id = static_cast<int>(v) + 1;
    views[v].camera_to_world.linear() =
        Eigen::AngleAxisd(radians(3.0 * static_cast<double>(v)), axis).toRotationMatrix();
    views[v].camera_to_world.translation() = Vec3(spread(random), spread(random), 0) / 3;
  }
  const auto indexed = measuredPoints(simulator, views, points);
  std::size_t measured = 0, by_angle = 0;
  for (std::size_t v = 0; v < views.size(); ++v) {
    const std::vector<Loss> losses = simulator.measure(views[v], points);
    std::vector<int> every;
    for (std::size_t i = 0; i < points.size(); ++i) {
      if (losses[i] == Loss::Measured) every.push_back(static_cast<int>(i));
      by_angle += losses[i] == Loss::CameraAngle || losses[i] == Loss::ProjectorAngle;
    }
    EXPECT_EQ(indexed[v], every) << "view " << views[v].id;
    measured += every.size();
  }
  EXPECT_GT(measured, 10000u);
  EXPECT_GT(by_angle, 10000u);
}

// A plane at the standoff facing the camera: its cloud has area / spacing² points and
// depth noise of the documented sigma.
TEST(SimulatedCloud, PlaneAtStandoffCountAndNoise) {
  Scanner s = scanner();
  s.point_spacing = 1.0;
  s.noise_sigma = 0.05;
  TriangleMesh mesh;
  test::addRectangle(mesh, centre(), Vec3(50, 0, 0), Vec3(0, -50, 0), 1);  // 100 x 100 mm
  Simulator simulator(test::meshPart(mesh), s, noPlane());
  PointCloud cloud = simulator.cloud(identityView(), 7);
  const double expected = 100.0 * 100.0 / (s.point_spacing * s.point_spacing);
  EXPECT_NEAR(static_cast<double>(cloud.points.size()), expected, 0.02 * expected);
  // On a plane at constant depth the noise along the ray projects to sigma along z.
  double sum = 0, sum2 = 0;
  for (const Vec3& p : cloud.points) {
    double dz = p.z() - s.standoff;
    sum += dz;
    sum2 += dz * dz;
  }
  const double n = static_cast<double>(cloud.points.size());
  const double mean = sum / n, sigma = std::sqrt(sum2 / n - mean * mean);
  EXPECT_NEAR(sigma, s.noise_sigma, 0.1 * s.noise_sigma);
  EXPECT_NEAR(mean, 0, 3 * s.noise_sigma / std::sqrt(n) + 1e-6);
  for (std::size_t i = 0; i < cloud.points.size(); ++i) {
    ASSERT_EQ(cloud.faces[i], 1);
    ASSERT_LT(cloud.incidence[i], 10.1f);  // atan(50 sqrt 2 / 400) = 10.0°
  }
  // The same seed gives the same cloud.
  EXPECT_EQ(simulator.cloud(identityView(), 7).points, cloud.points);
}

// The same cube hides a 40 mm square at the plate's centre from camera 1 (the cube at
// z = 190 to 210 casts a shadow about 2x its size at z = 400). The second camera fills it,
// and adds nothing where camera 1 measures: the two clouds are the same away from it.
TEST(SimulatedCloud, ASecondCameraFillsTheFirstCamerasShadowWithoutDuplicates) {
  Scanner one = scanner();
  one.point_spacing = 1.0;
  Scanner two = one;
  two.cameras = 2;
  TriangleMesh mesh;
  test::addRectangle(mesh, centre(), Vec3(50, 0, 0), Vec3(0, -50, 0), 1);  // 100 x 100 mm
  test::addCube(mesh, Vec3(-10, -10, 190), 20, 2);
  const Part part = test::meshPart(mesh);
  const PointCloud single = Simulator(part, one, noPlane()).cloud(identityView(), 3);
  const PointCloud both = Simulator(part, two, noPlane()).cloud(identityView(), 3);
  auto count = [](const PointCloud& cloud, double low, double high) {
    std::size_t n = 0;
    for (const Vec3& p : cloud.points) {
      const double r = std::max(std::abs(p.x()), std::abs(p.y()));
      n += r >= low && r < high;
    }
    return n;
  };
  EXPECT_EQ(count(single, 0, 15), 0u);  // the shadow's middle
  EXPECT_GT(count(both, 0, 15), 200u);  // 900 mm², sampled more coarsely by camera 2
  EXPECT_EQ(count(both, 30, 60), count(single, 30, 60));
  EXPECT_GT(count(single, 30, 60), 6000u);
}

TEST(SimulatedCloud, NoiseGrowsWithRange) {
  Scanner s = scanner();
  s.point_spacing = 1.0;
  s.noise_sigma = 0.05;
  const double depth = s.standoff + 80;
  TriangleMesh mesh;
  test::addRectangle(mesh, Vec3(0, 0, depth), Vec3(40, 0, 0), Vec3(0, -40, 0), 1);
  Simulator simulator(test::meshPart(mesh), s, noPlane());
  PointCloud cloud = simulator.cloud(identityView(), 3);
  double sum2 = 0;
  for (const Vec3& p : cloud.points) sum2 += (p.z() - depth) * (p.z() - depth);
  const double sigma = std::sqrt(sum2 / static_cast<double>(cloud.points.size()));
  const double expected = s.noise_sigma * (depth / s.standoff) * (depth / s.standoff);
  EXPECT_NEAR(sigma, expected, 0.1 * expected);
}

// A plane through the volume centre turned 45° from facing the camera: the noise lies along
// the camera's rays, sigma / cos 45° there (pointQuality's sigma), and its part along the
// plane's normal is sigma (pointQuality's along_normal), which a plane fit sees. Measured
// from the simulated cloud's distances to the plane; the patch is small (30 mm) so that
// depth stays within 4 % of the standoff.
TEST(SimulatedCloud, PointQualityGivesTheNoiseAlongTheNormalOfATiltedPlane) {
  Scanner s = scanner();
  s.point_spacing = 0.25;
  s.noise_sigma = 0.05;
  const Vec3 normal = tilted(45, 1);  // towards the projector, which then lights it at 20°
  const Vec3 across = 15 * Vec3(std::cos(radians(45)), 0, std::sin(radians(45)));
  TriangleMesh mesh;
  test::addRectangle(mesh, centre(), across, Vec3(0, -15, 0), 1);
  Simulator simulator(test::meshPart(mesh), s, noPlane());
  const PointCloud cloud = simulator.cloud(identityView(), 5);
  ASSERT_GT(cloud.points.size(), 5000u);
  double sum2 = 0;
  for (const Vec3& p : cloud.points) sum2 += std::pow((p - centre()).dot(normal), 2);
  const double measured = std::sqrt(sum2 / static_cast<double>(cloud.points.size()));
  const PointQuality q = pointQuality(s, identityView(), centre(), normal);
  RecordProperty("noise_along_normal", std::to_string(measured));
  EXPECT_NEAR(q.sigma, s.noise_sigma / std::cos(radians(45)), 1e-12);
  EXPECT_NEAR(q.along_normal, s.noise_sigma, 1e-12);
  EXPECT_NEAR(measured, q.along_normal, 0.06 * q.along_normal);
}

TEST(SimulatedCloud, PlyHasHeaderAndOneRecordPerPoint) {
  PointCloud cloud;
  cloud.points = {Vec3(1, 2, 3), Vec3(4, 5, 6)};
  cloud.normals = {Vec3::UnitZ(), Vec3::UnitX()};
  cloud.faces = {7, 8};
  cloud.incidence = {10.f, 20.f};
  test::TempDir dir;
  writePly(cloud, dir.file("cloud.ply"));
  std::ifstream in(dir.file("cloud.ply"), std::ios::binary);
  std::string text((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const std::string end = "end_header\n";
  auto header_end = text.find(end);
  ASSERT_NE(header_end, std::string::npos);
  EXPECT_NE(text.find("element vertex 2"), std::string::npos);
  EXPECT_EQ(text.size() - header_end - end.size(), 2u * (6 * 4 + 4 + 4));
  float x;
  std::memcpy(&x, text.data() + header_end + end.size() + 28 + 4, 4);  // second record
  EXPECT_FLOAT_EQ(x, 4.f);
  EXPECT_THROW(writePly(cloud, "/nonexistent/folder/cloud.ply"), OutputError);
}

// Independent check on a real part: a brute-force, double-precision segment test against
// every triangle (Möller & Trumbore 1997) for every facet the simulation measures, and for
// facets it loses to occlusion.
bool segmentHitsTriangle(const Vec3& a, const Vec3& b, const Vec3& v0, const Vec3& v1,
                         const Vec3& v2) {
  const Vec3 d = b - a, e1 = v1 - v0, e2 = v2 - v0;
  const Vec3 h = d.cross(e2);
  const double det = e1.dot(h);
  if (std::abs(det) < 1e-12) return false;
  const Vec3 s = a - v0;
  const double u = s.dot(h) / det;
  if (u < 0 || u > 1) return false;
  const Vec3 q = s.cross(e1);
  const double v = d.dot(q) / det;
  if (v < 0 || u + v > 1) return false;
  const double t = e2.dot(q) / det;
  return t > 1e-9 && t < 1 - 1e-9;
}

TEST(SimulationOnRealPart, MeasuredFacetsAreVisibleAndOccludedOnesHiddenByBruteForce) {
  Part part = importPart(test::example("parts/nist_ctc_01_asme1_ap242-e1.stp"));
  SimulationOptions options;
  options.part_to_world.translation() = Vec3(0, 0, 100);  // the part spans z in [-100, 50]
  Simulator simulator(part, scanner(), options);
  // Two views from above and one oblique, aimed into the part's pockets.
  std::vector<View> views(3);
  for (int v = 0; v < 3; ++v) {
    views[v].id = v + 1;
    views[v].camera_to_world.linear() << 1, 0, 0, 0, -1, 0, 0, 0, -1;
  }
  views[0].camera_to_world.translation() = Vec3(0, 0, 550);
  views[1].camera_to_world.translation() = Vec3(-250, 100, 550);
  views[2].camera_to_world.linear() =
      Eigen::Quaterniond(Eigen::AngleAxisd(radians(35), Vec3::UnitX())).toRotationMatrix() *
      views[0].camera_to_world.linear();
  views[2].camera_to_world.translation() = Vec3(150, -230, 480);

  const std::vector<SurfacePoint> facets = simulator.facetPoints();
  const double offset = options.surface_offset * part.bounds().diagonal();
  std::vector<Vec3> world(part.mesh.vertices.size());
  for (std::size_t i = 0; i < world.size(); ++i)
    world[i] = options.part_to_world * part.mesh.vertices[i];
  std::size_t checked = 0, occluded = 0;
  for (const View& view : views) {
    Acquisition acquisition = simulator.acquire(view);
    const Vec3 eyes[2] = {view.camera(), projectorPosition(view, scanner())};
    for (std::size_t f = 0; f < facets.size(); ++f) {
      if (acquisition.facets[f] != Loss::Measured) continue;
      ++checked;
      const Vec3 origin = facets[f].position + offset * facets[f].normal;
      for (const Vec3& eye : eyes)
        for (std::size_t t = 0; t < part.mesh.triangles.size(); ++t) {
          const Vec3i& tri = part.mesh.triangles[t];
          ASSERT_FALSE(
              segmentHitsTriangle(origin, eye, world[tri[0]], world[tri[1]], world[tri[2]]))
              << "view " << view.id << ": facet " << f << " is hidden by triangle " << t;
        }
    }
    EXPECT_GT(acquisition.counts[0], 0u) << "view " << view.id << " measures nothing";
    // And the other way: a facet lost to occlusion is hidden from that eye by some
    // triangle (at most 200 such facets a view, spread over them).
    std::vector<std::pair<std::size_t, Vec3>> lost;  // facet, the eye it is hidden from
    for (std::size_t f = 0; f < facets.size(); ++f)
      if (acquisition.facets[f] == Loss::CameraOccluded)
        lost.push_back({f, eyes[0]});
      else if (acquisition.facets[f] == Loss::ProjectorOccluded)
        lost.push_back({f, eyes[1]});
    const std::size_t stride = std::max<std::size_t>(1, lost.size() / 200);
    for (std::size_t k = 0; k < lost.size(); k += stride) {
      const auto& [f, eye] = lost[k];
      const Vec3 origin = facets[f].position + offset * facets[f].normal;
      bool hidden = false;
      for (std::size_t t = 0; t < part.mesh.triangles.size() && !hidden; ++t) {
        const Vec3i& tri = part.mesh.triangles[t];
        hidden = segmentHitsTriangle(origin, eye, world[tri[0]], world[tri[1]], world[tri[2]]);
      }
      EXPECT_TRUE(hidden) << "view " << view.id << ": facet " << f << " is lost to occlusion "
                          << "but nothing lies between it and the eye";
      ++occluded;
    }
  }
  EXPECT_GT(checked, 100u);
  EXPECT_GT(occluded, 50u);
}

}  // namespace
}  // namespace scanplan
