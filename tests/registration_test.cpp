// Registration feasibility against analytic cases: the stability of planes, cylinders
// and corners, markers, ICP on simulated clouds, bridging, and the sequence.

#include "planning/registration_error.h"
#include "registration/icp_stage.h"
#include "support.h"

#include <scanplan/cad/elementary.h>
#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/io/points_csv.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/planning/bridging.h>
#include <scanplan/registration/registration.h>
#include <scanplan/registration/sequencing.h>
#include <scanplan/robot/cycle.h>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <random>
#include <set>

namespace scanplan {
namespace {

// A scanner that sees and lights the three faces of a cube corner at once.
Scanner wideScanner() {
  Scanner scanner;
  scanner.triangulation_angle = 10;
  scanner.max_camera_angle = 75;
  scanner.max_projector_angle = 75;
  return scanner;
}

View aimedAt(const Scanner& scanner, const Vec3& target, Vec3 direction, int id,
             const Vec3& baseline = Vec3::UnitX()) {
  View view;
  direction.normalize();
  view.camera_to_world = lookAt(target + scanner.standoff * direction, target, baseline);
  view.target = target;
  view.id = id;
  return view;
}

TEST(IcpConditionTest, PlaneSphereAndCylinderAreDegenerateCornerIsNot) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(-50, 50);
  std::vector<Vec3> points, normals;
  for (int i = 0; i < 500; ++i) {
    points.emplace_back(u(random), u(random), 0);
    normals.emplace_back(0, 0, 1);
  }
  EXPECT_TRUE(std::isinf(icpCondition(points, normals)));

  points.clear();
  normals.clear();
  for (int i = 0; i < 500; ++i) {  // a cylinder about z: free to turn about and slide along z
    const double a = u(random) / 50 * M_PI;
    points.emplace_back(40 * std::cos(a), 40 * std::sin(a), u(random));
    normals.emplace_back(std::cos(a), std::sin(a), 0);
  }
  EXPECT_TRUE(std::isinf(icpCondition(points, normals)));

  points.clear();
  normals.clear();
  for (int i = 0; i < 500; ++i) {  // a sphere: free to turn about its centre
    const Vec3 n = Vec3(u(random), u(random), u(random)).normalized();
    points.push_back(30 * n);
    normals.push_back(n);
  }
  EXPECT_TRUE(std::isinf(icpCondition(points, normals)));

  points.clear();
  normals.clear();
  for (int i = 0; i < 600; ++i) {  // three faces of a cube corner
    const double a = u(random) + 50, b = u(random) + 50;
    const int side = i % 3;
    Vec3 p = Vec3::Zero(), n = Vec3::Zero();
    p[side] = 0;
    p[(side + 1) % 3] = a;
    p[(side + 2) % 3] = b;
    n[side] = -1;
    points.push_back(p);
    normals.push_back(n);
  }
  const double corner = icpCondition(points, normals);
  EXPECT_TRUE(std::isfinite(corner));
  EXPECT_LT(corner, 20);
}

// Patches of one to three randomly turned planes, their normals tilted a little or not at
// all, weighted or not: whether the condition is within a limit, asked of
// icpConditionWithin, is what the condition number itself says, just below and above it
// and at the limits the registration uses.
TEST(IcpConditionTest, WithinALimitAnswersAsTheConditionNumberDoes) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> u(-1, 1);
  std::normal_distribution<double> tilt(0, 1);
  int finite = 0, infinite = 0;
  for (int patch = 0; patch < 300; ++patch) {
    const int planes = 1 + patch % 3;
    const double wobble = (patch / 3) % 4 == 0 ? 0.0 : 0.02 * ((patch / 3) % 4);
    std::vector<Vec3> points, normals;
    std::vector<double> weights;
    for (int k = 0; k < planes; ++k) {
      const Vec3 n = Vec3(u(random), u(random), u(random)).normalized();
      const Vec3 a = n.unitOrthogonal(), b = n.cross(a);
      const Vec3 origin(40 * u(random), 40 * u(random), 40 * u(random));
      for (int i = 0; i < 40; ++i) {
        points.push_back(origin + 30 * u(random) * a + 30 * u(random) * b);
        normals.push_back(
            (n + wobble * Vec3(tilt(random), tilt(random), tilt(random))).normalized());
        weights.push_back(patch % 2 ? 1 + u(random) * 0.5 : 1.0);
      }
    }
    const std::span<const double> w =
        patch % 2 ? std::span<const double>(weights) : std::span<const double>();
    const double condition = icpCondition(points, normals, w);
    std::vector<double> limits = {10, 100, 1000, 1e6};
    if (std::isfinite(condition)) {
      ++finite;
      limits.push_back(condition * (1 - 1e-6));
      limits.push_back(condition * (1 + 1e-6));
    } else {
      ++infinite;
    }
    for (const double limit : limits)
      EXPECT_EQ(icpConditionWithin(points, normals, limit, w), condition <= limit)
          << "patch " << patch << ", condition " << condition << ", limit " << limit;
  }
  EXPECT_GT(finite, 100);
  EXPECT_GT(infinite, 10);
}

TEST(MarkersTest, ThreeMarkersOffALineRegister) {
  const std::vector<Vec3> line = {{0, 0, 0}, {50, 0, 0}, {100, 0.5, 0}, {150, 0, 0}};
  EXPECT_FALSE(markersRegister(line, 3, 10));
  const std::vector<Vec3> triangle = {{0, 0, 0}, {50, 0, 0}, {20, 30, 0}};
  EXPECT_TRUE(markersRegister(triangle, 3, 10));
  EXPECT_FALSE(markersRegister(std::span(triangle).first(2), 3, 10));
  EXPECT_FALSE(markersRegister(triangle, 4, 10));
}

TEST(MarkersTest, GridLeavesTheFootprintOut) {
  Box footprint;
  footprint.add(Vec3(0, 0, 0));
  footprint.add(Vec3(100, 100, 50));
  const std::vector<Marker> markers = markerGrid(footprint, 50, 100);
  // x and y from -100 to 200 by 50: 7 x 7 nodes, 3 x 3 of them under the footprint.
  EXPECT_EQ(markers.size(), 49u - 9u);
  for (const Marker& m : markers) EXPECT_EQ(m.position.z(), 0);
  EXPECT_THROW(markerGrid(footprint, 0, 10), InputError);
}

// Two views of the corner of a 200 mm cube standing on the working plane.
struct CornerScene {
  Scanner scanner = wideScanner();
  Part part;
  std::vector<View> views;
  CornerScene() {
    TriangleMesh mesh;
    test::addCube(mesh, Vec3(0, 0, 0), 200, 1);
    part = test::meshPart(mesh);
    const Vec3 corner(200, 200, 200);
    // Along the diagonal, baseline horizontal across it, so that the projector lights
    // the three faces as well as the camera sees them.
    const Vec3 across(1, -1, 0);
    views.push_back(aimedAt(scanner, corner - Vec3(30, 30, 30), Vec3(1, 0.9, 1), 1, across));
    views.push_back(aimedAt(scanner, corner - Vec3(30, 30, 30), Vec3(0.9, 1, 1), 2, across));
  }
};

TEST(IcpTest, CornerPairIsStableAndIcpRecoversThePerturbation) {
  const CornerScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  RegistrationOptions options;
  std::vector<View> views = scene.views;
  const Registration registration = registerWithBridging(simulator, views, {}, options, {});
  ASSERT_EQ(registration.pairs.size(), 1u);
  const PairCheck& pair = registration.pairs[0];
  EXPECT_GT(pair.overlap_a, 0.5);
  EXPECT_GT(pair.overlap_b, 0.5);
  EXPECT_LT(pair.condition, options.max_condition);
  EXPECT_TRUE(pair.stable);
  ASSERT_TRUE(pair.icp.has_value());
  EXPECT_LT(pair.icp->error, 0.1);      // RMS over the moved cloud
  EXPECT_LT(pair.icp->max_error, 0.1);  // and every point of it
  EXPECT_LT(pair.icp->rotation, 0.05);  // degrees left of the 2 degrees
  EXPECT_TRUE(pair.icp->passed);
  EXPECT_EQ(registration.components, 1u);
  EXPECT_EQ(registration.views[0].method, RegistrationMethod::Reference);
  EXPECT_EQ(registration.views[1].method, RegistrationMethod::Icp);
  EXPECT_EQ(registration.views[1].to, 1);
}

// A stage of the ICP check finds at every iteration, for every point, the fixed point
// Open3D's own RegistrationICP finds, and so the same motion: on the corner pair's clouds,
// the moved one turned 1 degree and shifted 2.4 mm, at distances from the coarse stages'
// to the fine one's; each stage from scratch, and from where the one before left the
// cloud and what it found.
TEST(IcpTest, AStageMatchesAsOpen3dsOwnIcpDoes) {
  namespace registration = open3d::pipelines::registration;
  const CornerScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  const RegistrationOptions options;
  const detail::IndexedCloud fixed(icpCloud(simulator, scene.views[0], options));
  open3d::geometry::PointCloud target, start;
  target.points_ = fixed.cloud.points;
  target.normals_ = fixed.cloud.normals;
  start.points_ = icpCloud(simulator, scene.views[1], options).points;
  Pose motion = Pose::Identity();
  motion.linear() = Eigen::AngleAxisd(radians(1), Vec3(1, 2, 3).normalized()).toRotationMatrix();
  motion.translation() = Vec3(2, -1, 0.8);
  start.Transform(motion.matrix());
  const auto sorted = [](const registration::CorrespondenceSet& set) {
    std::vector<std::pair<int, int>> pairs;
    for (const Eigen::Vector2i& c : set) pairs.push_back({c[0], c[1]});
    std::sort(pairs.begin(), pairs.end());
    return pairs;
  };
  open3d::geometry::PointCloud carried = start;
  std::vector<detail::Found> found(start.points_.size());
  for (const double distance : {10.0, 5.0, 3.0, 2.3}) {
    for (const bool from_scratch : {true, false}) {
      const open3d::geometry::PointCloud before = from_scratch ? start : carried;
      open3d::geometry::PointCloud moved = before;
      std::vector<detail::Found> fresh(start.points_.size());
      Eigen::Matrix4d ours = Eigen::Matrix4d::Identity();
      const registration::RegistrationResult mine =
          from_scratch ? detail::icpStage(fixed, target, moved, distance, ours, fresh)
                       : detail::icpStage(fixed, target, carried, distance, ours, found);
      const registration::RegistrationResult theirs = registration::RegistrationICP(
          before, target, distance, Eigen::Matrix4d::Identity(),
          registration::TransformationEstimationPointToPlane(
              std::make_shared<registration::TukeyLoss>(detail::kTukey * distance)),
          registration::ICPConvergenceCriteria(1e-4, 1e-4, 30));
      const std::string stage = std::to_string(distance) + (from_scratch ? " mm" : " mm, carried");
      EXPECT_GT(mine.correspondence_set_.size(), 10000u) << stage;
      EXPECT_EQ(sorted(mine.correspondence_set_), sorted(theirs.correspondence_set_)) << stage;
      EXPECT_LT((ours - theirs.transformation_).cwiseAbs().maxCoeff(), 1e-9) << stage;
      EXPECT_NEAR(mine.fitness_, theirs.fitness_, 1e-12) << stage;
      EXPECT_NEAR(mine.inlier_rmse_, theirs.inlier_rmse_, 1e-9) << stage;
    }
  }
}

// Adds a sphere of `radius` about `centre`, in 1-degree facets, as face `face`.
void addSphere(TriangleMesh& mesh, const Vec3& centre, double radius, int face) {
  const int n = 180;
  const auto at = [&](int i, int j) {
    const double theta = M_PI * i / n, phi = M_PI * j / n;
    return Vec3(centre + radius * Vec3(std::sin(theta) * std::cos(phi),
                                       std::sin(theta) * std::sin(phi), std::cos(theta)));
  };
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < 2 * n; ++j) {
      const int base = static_cast<int>(mesh.vertices.size());
      for (const Vec3& p : {at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)})
        mesh.vertices.push_back(p);
      mesh.triangles.push_back(Vec3i(base, base + 1, base + 2));
      mesh.triangles.push_back(Vec3i(base, base + 2, base + 3));
      mesh.triangle_faces.insert(mesh.triangle_faces.end(), 2, face);
    }
}

// Point-to-plane ICP against a sampled surface is off where the surface curves between the
// fixed cloud's points, by about the curvature times the spacing squared. The corner pair
// with a 40 mm sphere on the cube's top, in both views, its noise a twentieth of the
// generic head's so that the sampling shows: the residual ICP leaves falls 4 times from
// 1.5 to 0.75 mm and 2.25 times from 0.75 to 0.5 mm as the square of the spacing would
// (measured 3.4 and 2.2), where it would fall 2 and 1.5 times as the spacing itself.
TEST(IcpTest, TheResidualOverACurvedOverlapFallsAsTheSquareOfTheCloudSpacing) {
  CornerScene scene;
  TriangleMesh mesh;
  test::addCube(mesh, Vec3(0, 0, 0), 200, 1);
  addSphere(mesh, Vec3(150, 150, 220), 40, 7);
  scene.part = test::meshPart(mesh);
  scene.scanner.noise_sigma = 0.0005;
  const Simulator simulator(scene.part, scene.scanner);
  std::vector<double> residual;
  for (const double spacing : {1.5, 0.75, 0.5}) {
    RegistrationOptions options;
    options.cloud_spacing = spacing;
    residual.push_back(checkIcp(simulator, scene.views[0], scene.views[1], options).error);
  }
  RecordProperty("residuals", std::to_string(residual[0]) + " " + std::to_string(residual[1]) +
                                  " " + std::to_string(residual[2]));
  EXPECT_GT(residual[0] / residual[1], 2.8);
  EXPECT_LT(residual[0] / residual[1], 5.0);
  EXPECT_GT(residual[1] / residual[2], 1.8);
  EXPECT_LT(residual[1] / residual[2], 2.8);
}

// A 1 m square plate, 10 mm above the working plane, seen from above by two views 120 mm
// apart: they overlap by 60% but the overlap is a plane, free to slide.
struct PlateScene {
  Scanner scanner;
  Part part;
  std::vector<View> views;
  PlateScene() {
    TriangleMesh mesh;
    test::addRectangle(mesh, Vec3(0, 0, 10), Vec3(500, 0, 0), Vec3(0, 500, 0), 1);
    part = test::meshPart(mesh);
    views.push_back(aimedAt(scanner, Vec3(-60, 0, 10), Vec3::UnitZ(), 1));
    views.push_back(aimedAt(scanner, Vec3(60, 0, 10), Vec3::UnitZ(), 2));
  }
};

TEST(RegistrationTest, PlaneOverlapIsNotRegistrableByIcp) {
  const PlateScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  std::vector<View> views = scene.views;
  RegistrationOptions options;
  options.bridging = false;
  const Registration registration = registerWithBridging(simulator, views, {}, options, {});
  ASSERT_EQ(registration.pairs.size(), 1u);
  const PairCheck& pair = registration.pairs[0];
  EXPECT_NEAR(pair.overlap_a, 0.6, 0.05);
  EXPECT_NEAR(pair.overlap_b, 0.6, 0.05);
  EXPECT_TRUE(std::isinf(pair.condition));
  EXPECT_FALSE(pair.stable);
  EXPECT_FALSE(pair.registrable());
  EXPECT_EQ(registration.components, 2u);
  EXPECT_EQ(registration.registered(), 1u);  // the reference alone
  EXPECT_EQ(registration.views[1].method, RegistrationMethod::None);
}

TEST(RegistrationTest, PlaneOverlapWithThreeSharedMarkersRegisters) {
  const PlateScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  std::vector<View> views = scene.views;
  // Markers stuck on the plate in the overlap, and one that only the first view sees.
  const std::vector<Marker> markers = {{Vec3(-40, -50, 10), Vec3::UnitZ()},
                                       {Vec3(40, -50, 10), Vec3::UnitZ()},
                                       {Vec3(0, 60, 10), Vec3::UnitZ()},
                                       {Vec3(-180, 0, 10), Vec3::UnitZ()}};
  const Registration registration = registerWithBridging(simulator, views, markers, {}, {});
  ASSERT_EQ(registration.pairs.size(), 1u);
  EXPECT_EQ(registration.pairs[0].shared_markers, 3u);
  EXPECT_TRUE(registration.pairs[0].markers);
  EXPECT_EQ(registration.components, 1u);
  EXPECT_EQ(registration.views[1].method, RegistrationMethod::Markers);
  EXPECT_EQ(registration.views[1].to, 1);
  EXPECT_EQ(registration.markers, 4u);

  // Two shared markers are not enough; nor are three on one line.
  std::vector<View> again = scene.views;
  const std::vector<Marker> two(markers.begin() + 1, markers.end());
  EXPECT_EQ(registerWithBridging(simulator, again, two, {}, {}).components, 2u);
  const std::vector<Marker> line = {{Vec3(0, -80, 10), Vec3::UnitZ()},
                                    {Vec3(0, 0, 10), Vec3::UnitZ()},
                                    {Vec3(0, 80, 10), Vec3::UnitZ()}};
  again = scene.views;
  EXPECT_EQ(registerWithBridging(simulator, again, line, {}, {}).components, 2u);
}

// Markers on the plate of PlateScene, at z = 10, facing up.
std::vector<Marker> plateMarkers(const std::vector<std::pair<double, double>>& at) {
  std::vector<Marker> markers;
  for (const auto& [x, y] : at) markers.push_back({Vec3(x, y, 10), Vec3::UnitZ()});
  return markers;
}

// Markers at `xs` x `ys` on the plate of PlateScene (z = 10), facing up.
std::vector<Marker> markerGrid(const std::vector<double>& xs, const std::vector<double>& ys) {
  std::vector<std::pair<double, double>> at;
  for (double x : xs)
    for (double y : ys) at.emplace_back(x, y);
  return plateMarkers(at);
}

// The mean square of the displacement, mm², that a rigid fit of `markers` (each measured in
// both views, per axis sigma 1) leaves over a grid across the field of a view aimed at
// (`x`, 0) on the plate: the full 6x6 covariance of the fit (detail::rigidFitCovariance).
double fitError(const std::vector<Marker>& markers, double x) {
  std::vector<Vec3> at;
  for (const Marker& m : markers) at.push_back(m.position);
  const detail::TwistCovariance covariance = detail::rigidFitCovariance(at, std::sqrt(2.0));
  double sum = 0;
  int count = 0;
  for (double u = -150; u <= 150; u += 50)
    for (double v = -100; v <= 100; v += 50) {
      const Eigen::Matrix<double, 3, 6> jacobian = detail::motionAt(Vec3(x + u, v, 10));
      sum += (jacobian * covariance * jacobian.transpose()).trace();
      ++count;
    }
  return sum / count;
}

// Each view registers along the chain of pairs whose errors add up least. Three views of the
// plate in a row (aimed at x = -100, 0 and 100), the first seeing the most markers (the
// reference); markers in the middle that all three see, one more that only the first two
// see and one that only the last two see. Fifteen in the middle: the third view's direct
// link to the first is surer than the chain through the second, though each of the chain's
// pairs shares one marker more (their errors add). Three close together in the middle (a
// triangle 30 mm across, as few and as close as still register): the
// direct link is far weaker, and the third registers through the second, its pairs sharing
// three spread markers more each.
TEST(RegistrationTest, EachViewRegistersAlongTheChainWhoseErrorsAddUpLeast) {
  const PlateScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  const std::vector<View> row = {aimedAt(scene.scanner, Vec3(-100, 0, 10), Vec3::UnitZ(), 1),
                                 aimedAt(scene.scanner, Vec3(0, 0, 10), Vec3::UnitZ(), 2),
                                 aimedAt(scene.scanner, Vec3(100, 0, 10), Vec3::UnitZ(), 3)};
  const std::vector<Marker> first_only = markerGrid({-230, -190}, {-100, -50, 0, 50, 100});
  RegistrationOptions options;
  options.bridging = false;
  const auto third = [&](const std::vector<Marker>& middle, const std::vector<Marker>& first_two,
                         const std::vector<Marker>& last_two) {
    std::vector<Marker> markers = first_only;
    for (const auto* list : {&middle, &first_two, &last_two})
      markers.insert(markers.end(), list->begin(), list->end());
    std::vector<View> views = row;
    const Registration r = registerWithBridging(simulator, views, markers, options, {});
    EXPECT_EQ(r.reference, 1);
    EXPECT_EQ(r.views[1].to, 1);
    const PairCheck* first = r.pair(1, 3);
    EXPECT_TRUE(first && first->markers && first->shared_markers == middle.size());
    const PairCheck* through = r.pair(1, 2);
    EXPECT_TRUE(through && through->shared_markers == middle.size() + first_two.size());
    return r.views[2];
  };
  const auto with = [](std::vector<Marker> a, const std::vector<Marker>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };

  const std::vector<Marker> wide = markerGrid({-40, 0, 40}, {-100, -50, 0, 50, 100});
  const std::vector<Marker> one_left = plateMarkers({{-100, 0}}),
                            one_right = plateMarkers({{100, 0}});
  ASSERT_LT(fitError(wide, 100),
            fitError(with(wide, one_left), 100) + fitError(with(wide, one_right), 100));
  const ViewRegistration direct = third(wide, one_left, one_right);
  EXPECT_EQ(direct.method, RegistrationMethod::Markers);
  EXPECT_EQ(direct.to, 1);

  const std::vector<Marker> close = plateMarkers({{-15, -10}, {15, -10}, {0, 14}});
  const std::vector<Marker> left = markerGrid({-140, -100}, {-90, 0, 90}),
                            right = markerGrid({100, 140}, {-90, 0, 90});
  ASSERT_GT(fitError(close, 100),
            fitError(with(close, left), 100) + fitError(with(close, right), 100));
  const ViewRegistration chained = third(close, left, right);
  EXPECT_EQ(chained.method, RegistrationMethod::Markers);
  EXPECT_EQ(chained.to, 2);
}

RegistrationOptions referencePoints() {
  RegistrationOptions options;
  options.method = RegistrationMode::ReferencePoints;
  options.bridging = false;
  return options;
}

// With reference points, each view registers into the markers' frame by the markers it sees
// itself: the two views of the plate share no marker, and no overlap ICP could register
// them by, yet both register when each sees three markers in a triangle of its own (the
// field of view reaches from x = -210 to 90 mm for the first, -90 to 210 for the second).
TEST(ReferencePointsTest, ViewsSeeingThreeMarkersInATriangleRegisterWithoutSharingOne) {
  const PlateScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  std::vector<View> views = scene.views;
  const std::vector<Marker> markers =
      plateMarkers({{-180, -50}, {-120, -50}, {-150, 60}, {120, -50}, {180, -50}, {150, 60}});
  const Registration registration =
      registerWithBridging(simulator, views, markers, referencePoints(), {});
  ASSERT_EQ(registration.views.size(), 2u);
  EXPECT_EQ(registration.method, RegistrationMode::ReferencePoints);
  EXPECT_EQ(registration.views[0].method, RegistrationMethod::ReferencePoints);
  EXPECT_EQ(registration.views[1].method, RegistrationMethod::ReferencePoints);
  EXPECT_EQ(registration.registered(), 2u);
  EXPECT_EQ(registration.components, 1u);
  // Under the pairs' rule, the same markers register nothing to anything.
  RegistrationOptions pairs = referencePoints();
  pairs.method = RegistrationMode::Markers;
  views = scene.views;
  EXPECT_EQ(registerWithBridging(simulator, views, markers, pairs, {}).registered(), 1u);
}

// Three markers on one line leave a view free to turn about it: the second view, which sees
// only those, does not register; the first, seeing its triangle, does.
TEST(ReferencePointsTest, AViewSeeingThreeMarkersOnALineDoesNotRegister) {
  const PlateScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  std::vector<View> views = scene.views;
  const std::vector<Marker> markers =
      plateMarkers({{-180, -50}, {-120, -50}, {-150, 60}, {150, -80}, {150, 0}, {150, 80}});
  const Registration registration =
      registerWithBridging(simulator, views, markers, referencePoints(), {});
  ASSERT_EQ(registration.views.size(), 2u);
  EXPECT_EQ(registration.views[0].method, RegistrationMethod::ReferencePoints);
  EXPECT_EQ(registration.views[1].method, RegistrationMethod::None);
  EXPECT_EQ(registration.registered(), 1u);
  EXPECT_EQ(registration.components, 2u);
}

// The plan's frame turns with the table: at 90 degrees about z through the origin, a marker
// of the working plane at (100, 0) is seen at (0, -100), its normal along x turned to -y;
// the table's and the part's markers turn with the part and stay where they are.
TEST(MarkersTest, PlaneMarkersTurnAgainstTheTableAndTheTablesStay) {
  TableTurn table;
  table.origin = Vec3::Zero();
  table.axis = Vec3::UnitZ();
  const std::vector<Marker> markers = {{Vec3(100, 0, 5), Vec3::UnitX(), MarkerCarrier::Plane},
                                       {Vec3(100, 0, 5), Vec3::UnitX(), MarkerCarrier::Table},
                                       {Vec3(100, 0, 5), Vec3::UnitX(), MarkerCarrier::Part}};
  const std::vector<Marker> turned = markersAtTableAngle(markers, table, M_PI / 2);
  ASSERT_EQ(turned.size(), 3u);
  EXPECT_LT((turned[0].position - Vec3(0, -100, 5)).norm(), 1e-9);
  EXPECT_LT((turned[0].normal - Vec3(0, -1, 0)).norm(), 1e-9);
  for (int k : {1, 2}) {
    EXPECT_LT((turned[k].position - markers[k].position).norm(), 1e-12);
    EXPECT_LT((turned[k].normal - markers[k].normal).norm(), 1e-12);
  }
}

// The second view of the plate is taken with the table turned half a turn about the
// origin. The three markers of the working plane under the first view are then seen under
// the second (turned to x = 120..180 mm), which registers by them; markers carried by the
// table turn with the part and stay out of the second view's field.
TEST(ReferencePointsTest, AViewAtAnotherTableAngleSeesThePlanesMarkersTurned) {
  const PlateScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  auto table = std::make_shared<TableTurn>();
  table->origin = Vec3::Zero();
  table->axis = Vec3::UnitZ();
  table->angle = [](const View& view) { return view.id == 2 ? M_PI : 0.0; };
  RegistrationOptions options = referencePoints();
  options.table = table;
  std::vector<Marker> markers = plateMarkers({{-180, -50}, {-120, -50}, {-150, 60}});
  std::vector<View> views = scene.views;
  const Registration on_plane = registerWithBridging(simulator, views, markers, options, {});
  ASSERT_EQ(on_plane.views.size(), 2u);
  EXPECT_EQ(on_plane.views[0].method, RegistrationMethod::ReferencePoints);
  EXPECT_EQ(on_plane.views[1].method, RegistrationMethod::ReferencePoints);
  for (Marker& m : markers) m.on = MarkerCarrier::Table;
  views = scene.views;
  const Registration on_table = registerWithBridging(simulator, views, markers, options, {});
  EXPECT_EQ(on_table.views[0].method, RegistrationMethod::ReferencePoints);
  EXPECT_EQ(on_table.views[1].method, RegistrationMethod::None);
  // Without the table, the second view is at angle 0 and sees none of them either.
  options.table = nullptr;
  for (Marker& m : markers) m.on = MarkerCarrier::Plane;
  views = scene.views;
  EXPECT_EQ(registerWithBridging(simulator, views, markers, options, {}).registered(), 1u);
}

// Under reference points without markers, the plate's first view is the reference and the
// second registers to nothing. Candidate positions in the second view's field (x = 120 to
// 200 mm) serve it; candidates under the first view only (x = -200 to -160 mm, outside
// the second's field, which starts at -90) do not, nor do candidates on one line, and the
// proposal names it.
TEST(ReferencePointsTest, AProposalNamesTheViewsNoCandidateServes) {
  const PlateScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  std::vector<View> views = scene.views;
  const Registration registration =
      registerWithBridging(simulator, views, {}, referencePoints(), {});
  ASSERT_EQ(registration.views.size(), 2u);
  ASSERT_EQ(registration.views[1].method, RegistrationMethod::None);
  const auto proposal = [&](double x0, double x1) {
    return proposeMarkers(simulator, views, registration,
                          plateMarkers({{x0, -60}, {x1, -60}, {x0, 0}, {x1, 60}}), {},
                          referencePoints());
  };
  const MarkerProposal served = proposal(120, 200);
  EXPECT_EQ(served.views, 1u);
  EXPECT_TRUE(served.unserved.empty());
  EXPECT_GE(served.markers.size(), 3u);
  const MarkerProposal unserved = proposal(-200, -160);
  EXPECT_EQ(unserved.views, 0u);
  EXPECT_EQ(unserved.unserved, std::vector<int>{2});
  EXPECT_TRUE(unserved.markers.empty());
  // Candidates in its field but on one line (y = 0) cannot register it either.
  const MarkerProposal on_a_line =
      proposeMarkers(simulator, views, registration,
                     plateMarkers({{120, 0}, {150, 0}, {180, 0}, {200, 0}}), {}, referencePoints());
  EXPECT_EQ(on_a_line.views, 0u);
  EXPECT_EQ(on_a_line.unserved, std::vector<int>{2});
}

// A 1.6 m bar with 40 mm blocks along it every 60 mm, and two groups of views, one at
// each end, far apart. Each view sees the top, the front and the sides of blocks.
struct BarScene {
  Scanner scanner = wideScanner();
  Part part;
  std::vector<View> views;
  BarScene() {
    TriangleMesh mesh;
    for (int k = 0; k < 16; ++k) test::addCube(mesh, Vec3(-800 + 100 * k, 0, 0), 100, 1);
    for (int k = 0; k < 26; ++k) test::addCube(mesh, Vec3(-770 + 60 * k, 30, 100), 40, 2);
    part = test::meshPart(mesh);
    const Vec3 tilt(0.5, -0.5, 0.8);
    for (double x : {-640.0, -540.0, 540.0, 640.0})
      views.push_back(aimedAt(scanner, Vec3(x, 50, 110), tilt, static_cast<int>(views.size()) + 1));
  }
};

TEST(RegistrationTest, BridgingJoinsTwoGroupsFarApart) {
  const BarScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  RegistrationOptions options;
  options.bridging = false;
  std::vector<View> views = scene.views;
  const Registration apart = registerWithBridging(simulator, views, {}, options, {});
  EXPECT_EQ(apart.components, 2u);
  EXPECT_EQ(apart.registered(), 2u);

  options.bridging = true;
  const Registration joined = registerWithBridging(simulator, views, {}, options, {});
  EXPECT_EQ(joined.components, 1u);
  EXPECT_GT(joined.bridging_views, 0u);
  EXPECT_EQ(views.size(), scene.views.size() + joined.bridging_views);
  EXPECT_EQ(joined.registered(), views.size());
  for (std::size_t v = scene.views.size(); v < views.size(); ++v) {
    EXPECT_TRUE(joined.views[v].bridge);
    EXPECT_EQ(views[v].id, static_cast<int>(v) + 1);
  }
  // Every ICP link of the tree is a checked pair that passed verification.
  for (std::size_t v = 0; v < views.size(); ++v) {
    const ViewRegistration& r = joined.views[v];
    if (r.method != RegistrationMethod::Icp) continue;
    const PairCheck* pair = joined.pair(views[v].id, r.to);
    ASSERT_NE(pair, nullptr) << "view " << views[v].id << " to " << r.to;
    ASSERT_TRUE(pair->icp.has_value()) << views[v].id << "-" << r.to;
    EXPECT_TRUE(pair->icp->passed) << views[v].id << "-" << r.to;
  }
  for (const PairCheck& pair : joined.pairs)
    if (pair.icp) {
      EXPECT_EQ(pair.icp->passed, pair.icp->error <= options.tolerance);
    }

  // The sequence visits every registered view once, from the reference, and is no longer
  // than the nearest-neighbour order.
  const Sequence sequence = sequenceViews(simulator, views, joined);
  ASSERT_EQ(sequence.views.size(), views.size());
  std::vector<int> ids = sequence.views;
  std::sort(ids.begin(), ids.end());
  for (std::size_t k = 0; k < ids.size(); ++k) EXPECT_EQ(ids[k], static_cast<int>(k) + 1);
  EXPECT_EQ(sequence.views.front(), joined.reference);
  EXPECT_LE(sequence.length, sequence.nearest_neighbour_length + 1e-9);
  for (std::size_t k = 1; k < sequence.views.size(); ++k) {
    bool follows = false;
    for (std::size_t j = 0; j < k; ++j)
      follows = follows || joined.linked(sequence.views[k], sequence.views[j]);
    EXPECT_TRUE(follows) << "view " << sequence.views[k];
  }
}

// The bridging budget holds: the bar's two groups are joined with as many bridging views as
// joining them takes, and stay apart, with none added, when the budget is one short.
TEST(RegistrationTest, BridgingAddsNoMoreViewsThanItsBudget) {
  const BarScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  RegistrationOptions options;
  std::vector<View> unlimited = scene.views;
  const std::size_t needed =
      registerWithBridging(simulator, unlimited, {}, options, {}).bridging_views;
  ASSERT_GT(needed, 0u);
  for (const std::size_t budget : {needed - 1, needed}) {
    options.max_bridging_views = static_cast<int>(budget);
    std::vector<View> views = scene.views;
    const Registration registration = registerWithBridging(simulator, views, {}, options, {});
    EXPECT_LE(registration.bridging_views, budget) << budget;
    EXPECT_EQ(views.size(), scene.views.size() + registration.bridging_views) << budget;
    EXPECT_EQ(registration.components, budget == needed ? 1u : 2u) << budget;
  }
}

// Without verification no pair is checked by ICP, and every stable pair counts: the bar's
// groups register within themselves as with verification, and no pair carries an ICP
// result.
TEST(RegistrationTest, WithoutVerificationStablePairsRegisterUnchecked) {
  const BarScene scene;
  const Simulator simulator(scene.part, scene.scanner);
  RegistrationOptions options;
  options.bridging = false;
  options.verify = false;
  const Registration unchecked = registerViews(simulator, scene.views, {}, options);
  EXPECT_FALSE(unchecked.verified);
  for (const PairCheck& pair : unchecked.pairs) EXPECT_FALSE(pair.icp.has_value());
  options.verify = true;
  const Registration checked = registerViews(simulator, scene.views, {}, options);
  EXPECT_TRUE(checked.verified);
  EXPECT_GE(unchecked.registered(), checked.registered());
  EXPECT_EQ(unchecked.components, 2u);
  for (const PairCheck& pair : unchecked.pairs) EXPECT_EQ(unchecked.links(pair), pair.passes());
}

// `n` points drawn uniformly over a 1000 mm square of the plane z = 0.
std::vector<Vec3> randomPlanarPoints(std::mt19937& random, int n) {
  std::uniform_real_distribution<double> u(0, 1000);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i) points.emplace_back(u(random), u(random), 0);
  return points;
}

// Points on a plane, cost = distance.
Eigen::MatrixXd planarCosts(const std::vector<Vec3>& points) {
  const auto n = static_cast<Eigen::Index>(points.size());
  Eigen::MatrixXd cost(n, n);
  for (Eigen::Index i = 0; i < n; ++i)
    for (Eigen::Index j = 0; j < n; ++j) cost(i, j) = (points[i] - points[j]).norm();
  return cost;
}

TEST(SequencingTest, TwoOptIsNoLongerThanNearestNeighbour) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 20; ++trial) {
    const std::vector<Vec3> points = randomPlanarPoints(random, 40);
    const Eigen::MatrixXd cost = planarCosts(points);
    const std::vector<int> nearest = nearestNeighbourOrder(cost, {}, 0);
    const std::vector<int> improved = twoOpt(cost, {}, nearest);
    EXPECT_LE(pathLength(cost, improved), pathLength(cost, nearest) + 1e-9);
    std::vector<int> sorted = improved;
    std::sort(sorted.begin(), sorted.end());
    for (int i = 0; i < 40; ++i) EXPECT_EQ(sorted[i], i);
    EXPECT_EQ(improved.front(), 0);
  }
  // Points on a line, shuffled: the best open path from one end is the line itself.
  std::vector<Vec3> line;
  for (int i : {0, 7, 3, 9, 1, 5, 8, 2, 6, 4}) line.emplace_back(100.0 * i, 0, 0);
  const Eigen::MatrixXd cost = planarCosts(line);
  EXPECT_NEAR(pathLength(cost, twoOpt(cost, {}, {0, 1, 2, 3, 4, 5, 6, 7, 8, 9})), 900, 1e-9);
}

// Nodes of `order` after the first with no node linked to them before them.
std::size_t ruleBreaks(const std::vector<std::vector<char>>& linked,
                       const std::vector<int>& order) {
  std::size_t count = 0;
  for (std::size_t k = 1; k < order.size(); ++k)
    count += std::none_of(order.begin(), order.begin() + static_cast<std::ptrdiff_t>(k),
                          [&](int before) { return linked[order[k]][before] != 0; });
  return count;
}

// The shortest open path from node 0 through every node, by brute force; with `linked`,
// among the paths that leave no node before every node it is linked to.
double optimalPathLength(const Eigen::MatrixXd& cost,
                         const std::vector<std::vector<char>>& linked = {}) {
  std::vector<int> order(static_cast<std::size_t>(cost.rows()));
  std::iota(order.begin(), order.end(), 0);
  double best = std::numeric_limits<double>::infinity();
  do
    if (linked.empty() || ruleBreaks(linked, order) == 0)
      best = std::min(best, pathLength(cost, order));
  while (std::next_permutation(order.begin() + 1, order.end()));
  return best;
}

// Over 30 random instances of 8 points, where brute force (7! orders) gives the optimum:
// the mean and the worst gap of `found` to it, and how many it finds.
struct Gaps {
  double mean = 0, worst = 0;
  int optimal = 0;
};
Gaps gapsToTheOptimum(bool with_links,
                      const std::function<std::vector<int>(
                          const Eigen::MatrixXd&, const std::vector<std::vector<char>>&)>& found) {
  std::mt19937 random(5);
  Gaps gaps;
  for (int trial = 0; trial < 30; ++trial) {
    const std::vector<Vec3> points = randomPlanarPoints(random, 8);
    const Eigen::MatrixXd cost = planarCosts(points);
    // Links: a random tree over the nodes (each linked to one before it) and 4 more.
    std::vector<std::vector<char>> linked;
    if (with_links) {
      linked.assign(8, std::vector<char>(8, 0));
      auto link = [&](int a, int b) { linked[a][b] = linked[b][a] = a != b; };
      for (int i = 1; i < 8; ++i) link(i, std::uniform_int_distribution<int>(0, i - 1)(random));
      for (int k = 0; k < 4; ++k)
        link(std::uniform_int_distribution<int>(0, 7)(random),
             std::uniform_int_distribution<int>(0, 7)(random));
    }
    const double best = optimalPathLength(cost, linked);
    const std::vector<int> order = found(cost, linked);
    if (with_links) {
      EXPECT_EQ(ruleBreaks(linked, order), 0u) << trial;
    }
    EXPECT_GE(pathLength(cost, order), best - 1e-9);
    const double gap = pathLength(cost, order) / best - 1;
    gaps.mean += gap / 30;
    gaps.worst = std::max(gaps.worst, gap);
    gaps.optimal += gap < 1e-9;
  }
  return gaps;
}

// Records `gaps` as the test's properties, their names after `prefix`.
void recordGaps(const std::string& prefix, const Gaps& gaps) {
  ::testing::Test::RecordProperty(prefix + "mean_gap", std::to_string(gaps.mean));
  ::testing::Test::RecordProperty(prefix + "worst_gap", std::to_string(gaps.worst));
  ::testing::Test::RecordProperty(prefix + "optimal", std::to_string(gaps.optimal));
}

TEST(SequencingTest, TwoOptComesCloseToTheOptimumOfSmallInstances) {
  // The nearest-neighbour order improved by 2-opt, as sequenceViews first orders views.
  const Gaps gaps = gapsToTheOptimum(false, [](const auto& cost, const auto&) {
    return twoOpt(cost, {}, nearestNeighbourOrder(cost, {}, 0));
  });
  recordGaps("", gaps);
  // Measured: a mean gap of 1.9%, 9.6% at worst, 17 of 30 optimal.
  EXPECT_LT(gaps.mean, 0.03);
  EXPECT_LT(gaps.worst, 0.15);
  EXPECT_GE(gaps.optimal, 15);
}

TEST(SequencingTest, OrOptAfterTwoOptComesCloserToTheOptimum) {
  // The same instances, improved by 2-opt and or-opt in turn (improvedOrder): without links,
  // and with links that each node must follow one of (the shortest path that keeps the rule,
  // by brute force, is then the reference).
  auto improved = [](const auto& cost, const auto& linked) {
    return improvedOrder(cost, linked, nearestNeighbourOrder(cost, linked, 0));
  };
  const Gaps free = gapsToTheOptimum(false, improved);
  const Gaps ruled = gapsToTheOptimum(true, improved);
  recordGaps("", free);
  recordGaps("linked_", ruled);
  // Measured: a mean gap of 0.34%, 3.8% at worst, 26 of 30 optimal (2-opt alone: 1.9%,
  // 9.6%, 17); with links 0.95%, 6.7% at worst, 24 of 30 optimal.
  EXPECT_LT(free.mean, 0.01);
  EXPECT_LT(free.worst, 0.08);
  EXPECT_GE(free.optimal, 20);
  EXPECT_LT(ruled.mean, 0.03);
}

TEST(SequencingTest, NoRunOfUpToThreeNodesMovedElsewhereShortensAnOrOptPath) {
  // Every run of 1 to 3 nodes (not the start) put after every other node, either way round,
  // tried one by one: none that keeps the registration rule shortens the path or-opt gives.
  std::mt19937 random(17);
  for (int trial = 0; trial < 5; ++trial) {
    const std::vector<Vec3> points = randomPlanarPoints(random, 25);
    const Eigen::MatrixXd cost = planarCosts(points);
    std::vector<std::vector<char>> linked(25, std::vector<char>(25, 0));
    for (int i = 1; i < 25; ++i)
      for (int j = 0; j < i; ++j)
        if ((points[i] - points[j]).norm() < 350) linked[i][j] = linked[j][i] = 1;
    const std::vector<int> start = nearestNeighbourOrder(cost, linked, 0);
    const std::vector<int> order = orOpt(cost, linked, start);
    const double length = pathLength(cost, order);
    EXPECT_LE(length, pathLength(cost, start) + 1e-9);
    EXPECT_LE(ruleBreaks(linked, order), ruleBreaks(linked, start));
    for (std::size_t size = 1; size <= 3; ++size)
      for (std::size_t first = 1; first + size <= order.size(); ++first)
        for (bool reversed : {false, true}) {
          std::vector<int> rest = order, run(order.begin() + first, order.begin() + first + size);
          rest.erase(rest.begin() + first, rest.begin() + first + size);
          if (reversed) std::reverse(run.begin(), run.end());
          for (std::size_t at = 1; at <= rest.size(); ++at) {
            std::vector<int> other = rest;
            other.insert(other.begin() + at, run.begin(), run.end());
            if (ruleBreaks(linked, other) <= ruleBreaks(linked, order)) {
              EXPECT_GE(pathLength(cost, other), length - 1e-6) << trial << " " << first;
            }
          }
        }
  }
}

TEST(SequencingTest, EachNodeComesAfterOneItIsLinkedTo) {
  // Four points on a line at 0, 1, 2, 3 (x 100 mm), linked only as a chain 0-3, 3-1, 1-2:
  // the shortest path 0, 1, 2, 3 would put 1 before any node it is linked to.
  const std::vector<Vec3> points = {{0, 0, 0}, {100, 0, 0}, {200, 0, 0}, {300, 0, 0}};
  const Eigen::MatrixXd cost = planarCosts(points);
  std::vector<std::vector<char>> linked(4, std::vector<char>(4, 0));
  auto link = [&](int a, int b) { linked[a][b] = linked[b][a] = 1; };
  link(0, 3);
  link(3, 1);
  link(1, 2);
  const std::vector<int> order = twoOpt(cost, linked, nearestNeighbourOrder(cost, linked, 0));
  EXPECT_EQ(order, (std::vector<int>{0, 3, 1, 2}));
}

// Four views on a line at 0, 100, 200 and 300 mm (ids 1 to 4), the motion between them
// their distance, registered as a chain from view 1: 4 to 1, 2 to 4, 3 to 2, each pair by
// `method` (ICP verified, or shared markers).
struct ViewChain {
  std::vector<View> views;
  Registration registration;
  Eigen::MatrixXd cost = planarCosts({{0, 0, 0}, {100, 0, 0}, {200, 0, 0}, {300, 0, 0}});
  explicit ViewChain(RegistrationMethod method) {
    for (int id = 1; id <= 4; ++id) {
      View view;
      view.id = id;
      views.push_back(view);
    }
    registration.reference = 1;
    registration.verified = true;
    registration.views.resize(4);
    registration.views[0].method = RegistrationMethod::Reference;
    for (auto [from, to] : {std::pair{4, 1}, {2, 4}, {3, 2}}) {
      PairCheck pair;
      pair.a = std::min(from, to);
      pair.b = std::max(from, to);
      pair.stable = true;
      pair.markers = method == RegistrationMethod::Markers;
      pair.icp = IcpCheck{};
      pair.icp->passed = true;
      registration.pairs.push_back(pair);
      registration.views[from - 1].method = method;
      registration.views[from - 1].to = to;
    }
  }
  std::vector<int> sequence() const { return sequenceViews(cost, cost, views, registration).views; }
};

TEST(SequencingTest, ScansAlignedOnceAllAreTakenComeInAnyOrder) {
  // Aligned as taken, each view follows one it registers to: 1, 4, 2, 3 (600 mm). Aligned
  // once all are taken, the views registered by ICP come in the shortest order: 1, 2, 3, 4
  // (300 mm). Views registered by markers keep the rule either way.
  ViewChain icp(RegistrationMethod::Icp), markers(RegistrationMethod::Markers);
  EXPECT_EQ(icp.sequence(), (std::vector<int>{1, 4, 2, 3}));
  EXPECT_EQ(markers.sequence(), (std::vector<int>{1, 4, 2, 3}));
  icp.registration.aligned_as_taken = false;
  markers.registration.aligned_as_taken = false;
  EXPECT_EQ(icp.sequence(), (std::vector<int>{1, 2, 3, 4}));
  EXPECT_EQ(markers.sequence(), (std::vector<int>{1, 4, 2, 3}));
}

TEST(SequencingTest, ShortestPathsGoAroundWhatBlocksTheDirectMove) {
  // A direct move 0-2 that costs more than going through 1.
  Eigen::MatrixXd direct(3, 3);
  direct << 0, 1, 10, 1, 0, 2, 10, 2, 0;
  const Eigen::MatrixXd paths = shortestPaths(direct);
  EXPECT_DOUBLE_EQ(paths(0, 2), 3);
  EXPECT_DOUBLE_EQ(paths(2, 0), 3);
  EXPECT_DOUBLE_EQ(paths(0, 1), 1);
}

// Against Bellman-Ford (another algorithm than the library's Floyd-Warshall) on a random
// cost matrix: not symmetric, with moves that cannot be made (infinite) and a view no
// move reaches.
TEST(SequencingTest, ShortestPathsAgreeWithBellmanFord) {
  const int n = 60;
  std::mt19937 random(7);
  std::uniform_real_distribution<double> cost(1, 100);
  const double inf = std::numeric_limits<double>::infinity();
  Eigen::MatrixXd direct(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      direct(i, j) = i == j ? 0 : (random() % 3 == 0 ? inf : cost(random));
  for (int i = 0; i < n - 1; ++i) direct(i, n - 1) = inf;
  // From each source, relax every move n - 1 times.
  Eigen::MatrixXd expected = Eigen::MatrixXd::Constant(n, n, inf);
  for (int source = 0; source < n; ++source) {
    expected(source, source) = 0;
    for (int round = 1; round < n; ++round)
      for (int u = 0; u < n; ++u)
        for (int v = 0; v < n; ++v)
          expected(source, v) = std::min(expected(source, v), expected(source, u) + direct(u, v));
  }
  const Eigen::MatrixXd paths = shortestPaths(direct);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) EXPECT_DOUBLE_EQ(paths(i, j), expected(i, j)) << i << "-" << j;
  EXPECT_EQ(paths(0, n - 1), inf);
}

// A 200 mm cube on the plane, and two cameras on either side of it, level with it.
struct CubeBetweenTwoViews {
  CubeBetweenTwoViews() : part(cube()), simulator(part, Scanner{}) {
    views.push_back(aimedAt(Scanner{}, Vec3(-100, 0, 100), Vec3(-1, 0, 0), 1));
    views.push_back(aimedAt(Scanner{}, Vec3(100, 0, 100), Vec3(1, 0, 0), 2));
  }
  static Part cube() {
    TriangleMesh mesh;
    test::addCube(mesh, Vec3(-100, -100, 0), 200, 1);
    return test::meshPart(mesh);
  }
  Part part;
  Simulator simulator;
  std::vector<View> views;
};

TEST(SequencingTest, MovesThroughThePartGoOverIt) {
  // The straight move between the two cameras crosses the cube, so it goes over the top
  // (clearance 100 mm above z = 200).
  const CubeBetweenTwoViews scene;
  const Simulator& simulator = scene.simulator;
  const std::vector<View>& views = scene.views;
  SequenceOptions options;
  options.rotation_arm = 0;
  const Eigen::MatrixXd cost = directCosts(simulator, views, options);
  // Up 200 from z = 100 to 300, across 1000, down 200.
  EXPECT_NEAR(cost(0, 1), 200 + 1000 + 200, 1e-6);
  options.rotation_arm = 200;
  EXPECT_NEAR(directCosts(simulator, views, options)(0, 1), 1400 + 200 * M_PI, 1e-6);
}

// From each view to each of another list: the same costs as between every two views, the
// move over the cube included.
TEST(SequencingTest, CostsFromSomeViewsToOthersAreThoseBetweenEveryTwo) {
  CubeBetweenTwoViews scene;
  const Simulator& simulator = scene.simulator;
  std::vector<View>& views = scene.views;
  views.push_back(aimedAt(Scanner{}, Vec3(0, 0, 200), Vec3(0, 0, 1), 3));
  const Eigen::MatrixXd all = directCosts(simulator, views);
  const auto view = std::span<const View>(views);
  const Eigen::MatrixXd some = directCosts(simulator, view.subspan(0, 1), view.subspan(1));
  ASSERT_EQ(some.rows(), 1);
  ASSERT_EQ(some.cols(), 2);
  EXPECT_NEAR(some(0, 0), all(0, 1), 1e-9);
  EXPECT_NEAR(some(0, 1), all(0, 2), 1e-9);
  EXPECT_GT(all(0, 1), 1400);  // over the top
}

// Points on a line, taken in a shuffled order: a path through the first k of them is at
// least as long as their span, and cheapest insertion finds one that long.
TEST(SequencingTest, InsertionPathThroughPointsOnALineIsTheirSpan) {
  std::mt19937 random(3);
  std::uniform_real_distribution<double> u(0, 1000);
  std::vector<Vec3> points;
  for (int i = 0; i < 40; ++i) points.emplace_back(u(random), 0, 0);
  const std::vector<double> lengths = insertionPathLengths(planarCosts(points));
  ASSERT_EQ(lengths.size(), points.size());
  double low = points[0].x(), high = low;
  for (std::size_t k = 0; k < points.size(); ++k) {
    low = std::min(low, points[k].x());
    high = std::max(high, points[k].x());
    EXPECT_NEAR(lengths[k], high - low, 1e-9) << k + 1 << " points";
  }
}

TEST(MarkersTest, OnThePartWhereItFacesUp) {
  // A 200 mm cube with a 120 mm cube on top of it: markers on both tops, none on the sides.
  TriangleMesh mesh;
  test::addCube(mesh, Vec3(0, 0, 0), 200, 1);
  test::addCube(mesh, Vec3(40, 40, 200), 120, 2);
  const std::vector<Marker> markers = markersOnPart(mesh, 20);
  EXPECT_EQ(markers.size(), 100u);  // a 10 x 10 grid over the 200 mm footprint
  std::size_t high = 0;
  for (const Marker& m : markers) {
    EXPECT_NEAR(m.normal.z(), 1, 1e-12);
    const bool on_top = std::abs(m.position.x() - 100) < 60 && std::abs(m.position.y() - 100) < 60;
    EXPECT_NEAR(m.position.z(), on_top ? 320 : 200, 1e-9);
    high += on_top;
  }
  EXPECT_EQ(high, 36u);  // grid lines 50 ... 150 over the top cube
}

// The bundled NIST CTC 01 planned with the example spec (markers on the plate and on the
// part), once per test run and read back from its plan.json: the registration, the
// sequence and the plan file are consistent with each other and with an independent check.
class RegisteredPlan : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    part_ = new Part(importPart(test::example("parts/nist_ctc_01_asme1_ap242-e1.stp")));
    spec_ = new Spec(loadSpec(test::example("specs/ctc01.yaml")));
    plan_ = new Plan(readPlan(test::examplePlan()));
  }
  static void TearDownTestSuite() {
    delete plan_;
    delete spec_;
    delete part_;
  }
  static Part* part_;
  static Spec* spec_;
  static Plan* plan_;
};
Part* RegisteredPlan::part_ = nullptr;
Spec* RegisteredPlan::spec_ = nullptr;
Plan* RegisteredPlan::plan_ = nullptr;

TEST_F(RegisteredPlan, EveryRegisteredViewReachesTheReferenceByCheckedPairs) {
  const Plan& plan = *plan_;
  ASSERT_TRUE(plan.registration && plan.sequence);
  const Registration& r = *plan.registration;
  ASSERT_EQ(r.views.size(), plan.views.size());
  EXPECT_GT(plan.markers.size(), 0u);
  std::map<int, std::size_t> index;
  for (std::size_t v = 0; v < plan.views.size(); ++v) index[plan.views[v].id] = v;
  std::size_t references = 0;
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    const ViewRegistration& view = r.views[v];
    if (view.method == RegistrationMethod::None) continue;
    if (view.method == RegistrationMethod::Reference) {
      ++references;
      EXPECT_EQ(plan.views[v].id, r.reference);
      continue;
    }
    // Its link is a checked pair that registers by the method named.
    const auto pair = std::find_if(r.pairs.begin(), r.pairs.end(), [&](const PairCheck& p) {
      return p.a == std::min(view.to, plan.views[v].id) &&
             p.b == std::max(view.to, plan.views[v].id);
    });
    ASSERT_NE(pair, r.pairs.end()) << "view " << plan.views[v].id;
    if (view.method == RegistrationMethod::Markers) {
      EXPECT_TRUE(pair->markers);
      EXPECT_GE(pair->shared_markers, 3u);
    } else {
      EXPECT_TRUE(pair->stable);
      EXPECT_LE(pair->condition, spec_->registration.max_condition);
      ASSERT_TRUE(pair->icp.has_value());
      EXPECT_TRUE(pair->icp->passed);
      EXPECT_LE(pair->icp->error, spec_->registration.tolerance);
    }
    // Following the links leads to the reference without a loop.
    int id = plan.views[v].id;
    for (std::size_t step = 0; step <= plan.views.size() && id != r.reference; ++step) {
      const ViewRegistration& next = r.views[index.at(id)];
      ASSERT_NE(next.method, RegistrationMethod::None);
      id = next.to;
    }
    EXPECT_EQ(id, r.reference);
  }
  EXPECT_EQ(references, 1u);
  // With the markers, nine views in ten register at least; bridging views, if any, come
  // last.
  EXPECT_GE(10 * r.registered(), 9 * plan.views.size());
  const std::size_t unregistered = plan.views.size() - r.registered();
  EXPECT_GE(r.components, 1 + (unregistered > 0 ? 1u : 0u));
  EXPECT_LE(r.components, 1 + unregistered);
  for (std::size_t v = 0; v < plan.views.size(); ++v)
    EXPECT_EQ(r.views[v].bridge, v >= plan.views.size() - r.bridging_views);
}

TEST_F(RegisteredPlan, SequenceVisitsEveryViewOnceAndBeatsNearestNeighbour) {
  const Plan& plan = *plan_;
  const Sequence& sequence = *plan.sequence;
  std::vector<int> ids = sequence.views, expected;
  for (const View& view : plan.views) expected.push_back(view.id);
  std::sort(ids.begin(), ids.end());
  std::sort(expected.begin(), expected.end());
  EXPECT_EQ(ids, expected);
  EXPECT_EQ(sequence.views.front(), plan.registration->reference);
  // The tour is no longer than the nearest-neighbour one it improves, and no shorter than
  // the straight lines between consecutive cameras (moves go around the part, never
  // through it).
  EXPECT_LE(sequence.length, sequence.nearest_neighbour_length + 1e-6);
  std::map<int, Vec3> camera;
  for (const View& view : plan.views) camera[view.id] = view.camera();
  double straight = 0;
  for (std::size_t k = 1; k < sequence.views.size(); ++k)
    straight += (camera.at(sequence.views[k]) - camera.at(sequence.views[k - 1])).norm();
  EXPECT_GE(sequence.length, straight - 1e-6);
  EXPECT_GT(straight, 0);
}

// A slab `length` x `width` x 20 mm (400 x 400 by default), its top a grid of triangles
// 20 mm apart.
Part flatSlab(int length = 400, int width = 400) {
  TriangleMesh mesh;
  test::addCube(mesh, Vec3::Zero(), 1, 1);  // the box without its top, then the top as a grid
  for (Vec3& v : mesh.vertices) v = v.cwiseProduct(Vec3(length, width, 20));
  mesh.triangles.erase(mesh.triangles.begin() + 2, mesh.triangles.begin() + 4);
  mesh.triangle_faces.erase(mesh.triangle_faces.begin() + 2, mesh.triangle_faces.begin() + 4);
  const int nx = length / 20, ny = width / 20;
  const int base = static_cast<int>(mesh.vertices.size());
  for (int j = 0; j <= ny; ++j)
    for (int i = 0; i <= nx; ++i) mesh.vertices.emplace_back(20.0 * i, 20.0 * j, 20);
  for (int j = 0; j < ny; ++j)
    for (int i = 0; i < nx; ++i) {
      const int a = base + i + (nx + 1) * j, b = a + 1, c = a + nx + 2, d = a + nx + 1;
      mesh.triangles.emplace_back(a, b, c);
      mesh.triangles.emplace_back(a, c, d);
      mesh.triangle_faces.insert(mesh.triangle_faces.end(), 2, 2);
    }
  return test::meshPart(mesh);
}

// Adds the rectangle from `corner` spanned by `u` and `v` (normal u x v) to `mesh` as face
// `face`, in square cells of about 10 mm so that it is sampled as a CAD face would be.
void addGrid(TriangleMesh& mesh, const Vec3& corner, const Vec3& u, const Vec3& v, int face) {
  const int nu = std::max(1, static_cast<int>(std::lround(u.norm() / 10)));
  const int nv = std::max(1, static_cast<int>(std::lround(v.norm() / 10)));
  const int base = static_cast<int>(mesh.vertices.size());
  for (int j = 0; j <= nv; ++j)
    for (int i = 0; i <= nu; ++i) mesh.vertices.push_back(corner + u * i / nu + v * j / nv);
  for (int j = 0; j < nv; ++j)
    for (int i = 0; i < nu; ++i) {
      const int a = base + i + (nu + 1) * j, b = a + 1, c = a + nu + 2, d = a + nu + 1;
      mesh.triangles.emplace_back(a, b, c);
      mesh.triangles.emplace_back(a, c, d);
      mesh.triangle_faces.insert(mesh.triangle_faces.end(), 2, face);
    }
}

// An L-bracket standing on its base: a base 200 x 100 x 15 mm and an upright 15 mm thick
// and 150 mm high at its back (x = 0), one face per plane, clamped in the corner of a
// fixture (face 9) that hides its back and its end at y = 100: it is seen from three sides,
// the front, the top and the end at y = 0.
Part lBracket() {
  TriangleMesh mesh;
  const Vec3 x = Vec3::UnitX(), y = Vec3::UnitY(), z = Vec3::UnitZ();
  addGrid(mesh, Vec3::Zero(), 100 * y, 200 * x, 1);     // bottom
  addGrid(mesh, Vec3(15, 0, 15), 185 * x, 100 * y, 2);  // top of the base
  addGrid(mesh, Vec3(200, 0, 0), 100 * y, 15 * z, 3);   // end of the base
  addGrid(mesh, Vec3(15, 0, 15), 100 * y, 135 * z, 4);  // front of the upright
  addGrid(mesh, Vec3(0, 0, 150), 15 * x, 100 * y, 5);   // top of the upright
  addGrid(mesh, Vec3::Zero(), 150 * z, 100 * y, 6);     // back
  addGrid(mesh, Vec3::Zero(), 200 * x, 15 * z, 7);      // side, y = 0
  addGrid(mesh, Vec3(0, 0, 15), 15 * x, 135 * z, 7);
  addGrid(mesh, Vec3(0, 100, 0), 15 * z, 200 * x, 8);  // side, y = 100
  addGrid(mesh, Vec3(0, 100, 15), 135 * z, 15 * x, 8);
  addGrid(mesh, Vec3(-5, -100, 0), 210 * y, 250 * z, 9);
  addGrid(mesh, Vec3(-5, 105, 0), 300 * x, 250 * z, 9);
  return test::meshPart(mesh);
}

// Adds the box [lo, hi] to `mesh`, its six sides faces `first`.. first + 5.
void addBox(TriangleMesh& mesh, const Vec3& lo, const Vec3& hi, int first) {
  const Vec3 d = hi - lo, x = d.x() * Vec3::UnitX(), y = d.y() * Vec3::UnitY(),
             z = d.z() * Vec3::UnitZ();
  addGrid(mesh, lo, y, x, first);          // bottom
  addGrid(mesh, lo + z, x, y, first + 1);  // top
  addGrid(mesh, lo, x, z, first + 2);      // y = lo
  addGrid(mesh, lo + y, z, x, first + 3);  // y = hi
  addGrid(mesh, lo, z, y, first + 4);      // x = lo
  addGrid(mesh, lo + x, y, z, first + 5);  // x = hi
}

// A row of eight blocks 40 mm wide and 30 mm apart, 15 and 30 mm high in turn, on a plate
// 600 mm long:
// longer than the field of view, with steps everywhere to register by.
Part blockRow() {
  TriangleMesh mesh;
  addBox(mesh, Vec3(0, 0, 0), Vec3(600, 100, 10), 1);
  for (int k = 0; k < 8; ++k)
    addBox(mesh, Vec3(30 + 70.0 * k, 30, 10), Vec3(70 + 70.0 * k, 70, k % 2 ? 40 : 25), 7 + 6 * k);
  return test::meshPart(mesh);
}

// With registration by geometry the selection grows the views from one another, so that
// more of them register than of the fewest views chosen for coverage alone, measuring the
// same samples. Measured: 8 of 24 views registered, against 1 of
// 10: the blocks' walls face four ways, and views from opposite sides share only planes.
TEST(RegistrationTest, RegistrationAwareSelectionRegistersMoreViewsOfABlockRow) {
  const Part part = blockRow();
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"), "tasks:\n  - {type: global}\n");
  const Spec spec = loadSpec(dir.file("spec.yaml"));
  const Plan plan = planViews(part, spec);
  // The fewest views, registered as the plan's are (the part stands as planned).
  PlanningOptions coverage_only;
  coverage_only.registration = false;
  Plan plain = planViews(part, spec, coverage_only);
  const Simulator simulator(part, spec.scanner);
  RegistrationOptions options = spec.registration;
  options.seed = spec.planner.seed;
  const Registration registered = registerWithBridging(simulator, plain.views, {}, options, {});
  RecordProperty("views", std::to_string(plan.views.size()));
  RecordProperty("registered", std::to_string(plan.registration->registered()));
  RecordProperty("fewest_views", std::to_string(plain.views.size()));
  RecordProperty("fewest_registered", std::to_string(registered.registered()));
  EXPECT_GT(plan.registration->registered(), 2 * registered.registered());
  EXPECT_GE(plan.views.size(), plain.views.size());
  auto measured = [](const Plan& p) {
    return std::count_if(p.samples.begin(), p.samples.end(),
                         [](const PlannedSample& s) { return !s.measured_by.empty(); });
  };
  EXPECT_EQ(measured(plan), measured(plain));
}

// A plan does not depend on the number of threads: the block row, whose plan runs every
// parallel stage (pool, selection with pair checks, registration and bridging), planned on
// one thread and on two gives the same plan.json but for the seconds it took.
TEST(RegistrationTest, APlanIsTheSameOnOneThreadAndOnTwo) {
  const Part part = blockRow();
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"), "tasks:\n  - {type: global}\n");
  const Spec spec = loadSpec(dir.file("spec.yaml"));
  auto planned = [&](std::size_t threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    nlohmann::json json = planJson(planViews(part, spec));
    json["summary"].erase("seconds");
    json["summary"].erase("stage_seconds");
    return json;
  };
  const nlohmann::json one = planned(1);
  RecordProperty("bridging_views", one["summary"]["bridging_views"].dump());
  EXPECT_FALSE(one["registration"]["pairs"].empty());
  EXPECT_EQ(one.dump(), planned(2).dump());
}

// Seen from the front, from above and from one end, an L-bracket registers by its geometry
// alone: every view registers, and every pair the registration uses passes ICP from a 3 mm /
// 2 degree perturbation. Three planes at right angles in one view need a scanner that
// measures up to 75 degrees from the normal (the default's 60 leave no direction within
// range of all three for both camera and projector).
TEST(RegistrationTest, AnLBracketRegistersByItsGeometry) {
  const Part part = lBracket();
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"),
                  "scanner: {preset: generic-structured-light, max_camera_angle: 75, "
                  "max_projector_angle: 75}\nroles: {fixture: [9]}\n"
                  "tasks:\n  - {type: global}\n");
  const Spec spec = loadSpec(dir.file("spec.yaml"));
  ASSERT_EQ(spec.registration.perturbation, 3);
  ASSERT_EQ(spec.registration.perturbation_angle, 2);
  const Plan plan = planViews(part, spec);
  ASSERT_TRUE(plan.registration);
  const Registration& registration = *plan.registration;
  RecordProperty("views", std::to_string(plan.views.size()));
  EXPECT_EQ(registration.method, RegistrationMode::Geometry);
  for (int face : {2, 4, 7})  // the top, the front and the end
    EXPECT_TRUE(std::any_of(
        plan.samples.begin(), plan.samples.end(),
        [&](const PlannedSample& s) { return s.sample.face == face && !s.measured_by.empty(); }))
        << "face " << face;
  EXPECT_GE(plan.views.size(), 2u);
  EXPECT_EQ(registration.registered(), plan.views.size());
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    const ViewRegistration& r = registration.views[v];
    if (r.method == RegistrationMethod::Reference) continue;
    EXPECT_EQ(r.method, RegistrationMethod::Icp) << "view " << plan.views[v].id;
    const int a = std::min(plan.views[v].id, r.to), b = std::max(plan.views[v].id, r.to);
    const auto pair = std::find_if(registration.pairs.begin(), registration.pairs.end(),
                                   [&](const PairCheck& p) { return p.a == a && p.b == b; });
    ASSERT_NE(pair, registration.pairs.end());
    ASSERT_TRUE(pair->icp) << a << "-" << b;
    EXPECT_TRUE(pair->icp->passed) << a << "-" << b;
    EXPECT_LE(pair->icp->error, spec.registration.tolerance) << a << "-" << b;
  }
}

// A slab seen from above: its views see little but the flat top, which ICP cannot
// register to. Markers stuck on the part register them.
TEST(RegistrationTest, MarkersOnAFlatPartRegisterItsViews) {
  const Part part = flatSlab();
  test::TempDir dir;
  auto planWith = [&](const std::string& markers) {
    test::writeText(dir.file("spec.yaml"), markers + "tasks:\n  - {type: global}\n");
    return planViews(part, loadSpec(dir.file("spec.yaml")));
  };
  const Plan bare = planWith("");
  const Plan marked = planWith("markers: {grid: 40, on: part}\n");
  ASSERT_GE(bare.views.size(), 2u);
  RecordProperty("registered_without_markers", std::to_string(bare.registration->registered()));
  RecordProperty("registered_with_markers", std::to_string(marked.registration->registered()));
  RecordProperty("views",
                 std::to_string(bare.views.size()) + " and " + std::to_string(marked.views.size()));
  RecordProperty("measured_by_registered_views",
                 std::to_string(bare.registeredMeasuredCount()) + " and " +
                     std::to_string(marked.registeredMeasuredCount()) + " of " +
                     std::to_string(bare.samples.size()));
  // Measured: 1 of 8 views registered without markers, 5 of 9 with them; 83 and 200 of
  // 210 samples measured by a registered view.
  EXPECT_LT(bare.registration->registered(), bare.views.size());
  EXPECT_GT(marked.registration->registered(), bare.registration->registered());
  EXPECT_GT(marked.registeredMeasuredCount(), bare.registeredMeasuredCount());
}

// The markers of `markers` inside the field of `view` (its width and height at the
// standoff, growing with depth) and within its depth of field: where the view can see them,
// judged from the geometry alone.
std::vector<Vec3> markersInField(const Scanner& scanner, const View& view,
                                 const std::vector<Marker>& markers) {
  const Pose world_to_camera = view.camera_to_world.inverse();
  std::vector<Vec3> inside;
  for (const Marker& m : markers) {
    const Vec3 p = world_to_camera * m.position;
    const double scale = p.z() / scanner.standoff;
    if (std::abs(p.z() - scanner.standoff) <= scanner.depth_of_field / 2 &&
        std::abs(p.x()) <= scanner.fov_width / 2 * scale &&
        std::abs(p.y()) <= scanner.fov_height / 2 * scale)
      inside.push_back(m.position);
  }
  return inside;
}

// The slab, wider than the field of view, on a marker plate (markers every 40 mm around it,
// their positions known): with reference points every view registers, each into the plate's
// frame by three or more markers in its field off one line, and the plan has no more views
// than the plan made without registration, and measures as much.
TEST(ReferencePointsTest, EveryViewOfASlabOnAMarkerPlateRegistersWithoutMoreViews) {
  const Part part = flatSlab();
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"),
                  "markers: {grid: 40, on: plate}\nregistration: {method: reference_points}\n"
                  "tasks:\n  - {type: global}\n");
  const Spec spec = loadSpec(dir.file("spec.yaml"));
  const Plan framed = planViews(part, spec);
  const Plan alone = planViews(part, spec, PlanningOptions{.registration = false});
  RecordProperty("views", std::to_string(framed.views.size()) + " with reference points, " +
                              std::to_string(alone.views.size()) + " without registration");
  ASSERT_TRUE(framed.registration);
  ASSERT_GE(framed.views.size(), 2u);
  EXPECT_EQ(framed.registration->registered(), framed.views.size());
  for (const View& view : framed.views) {
    const std::vector<Vec3> seen = markersInField(framed.scanner, view, framed.markers);
    EXPECT_TRUE(markersRegister(seen, 3, spec.registration.marker_spread)) << "view " << view.id;
  }
  EXPECT_LE(framed.views.size(), alone.views.size());
  EXPECT_GE(framed.measuredCount(), alone.measuredCount());
}

// The slab, turned over once (part.rest: all), its two setups registered by reference
// points. With markers stuck on the part as well as on the plate, each setup has views
// that see three or more of the part's markers in their field, off one line: every view
// registers in the part's frame, one for both setups. With markers on the plate alone,
// each setup registers in a frame of its own, and the plan says the two are not joined.
// The markers on the part hide the surface they cover.
TEST(ReferencePointsTest, MarkersOnThePartJoinTheSetupsOfAPartTurnedOver) {
  const Part part = flatSlab(300, 200);
  test::TempDir dir;
  auto planOn = [&](const std::string& on) {
    test::writeText(dir.file("spec.yaml"),
                    "part: {rest: all}\nmarkers: {grid: 40, diameter: 16, on: " + on +
                        "}\nregistration: {method: reference_points}\n"
                        "tasks:\n  - {type: global}\n");
    return planViews(part, loadSpec(dir.file("spec.yaml")));
  };
  const Plan joined = planOn("both");
  ASSERT_EQ(joined.orientations.size(), 2u);
  EXPECT_EQ(joined.registration->registered(), joined.views.size());
  const std::vector<SetupRegistration> setups = setupRegistration(joined);
  EXPECT_EQ(setups[0].frame, 0u);
  EXPECT_EQ(setups[1].frame, 0u);
  EXPECT_EQ(registeredInOneFrame(setups), joined.views.size());
  EXPECT_EQ(planJson(joined)["summary"]["setups"]["joined"], true);
  // Independently of the registration: in each setup, some view has three of the part's
  // markers in its field, off one line.
  const std::vector<std::size_t> setup_of = viewOrientations(joined);
  for (std::size_t k = 0; k < 2; ++k) {
    std::vector<Marker> on_part;
    for (const Marker& m : joined.orientations[k].markers)
      if (m.on == MarkerCarrier::Part) on_part.push_back(m);
    bool framed = false;
    for (std::size_t v = 0; v < joined.views.size(); ++v)
      framed = framed ||
               (setup_of[v] == k &&
                markersRegister(markersInField(joined.scanner, joined.views[v], on_part), 3, 10));
    EXPECT_TRUE(framed) << "setup " << k + 1;
  }
  // The same markers on the part in both setups: the second's are the first's turned over.
  const Pose turn = joined.orientations[1].rest.part_to_world *
                    joined.orientations[0].rest.part_to_world.inverse();
  std::size_t same = 0, on_part = 0;
  for (const Marker& m : joined.orientations[0].markers) {
    if (m.on != MarkerCarrier::Part) continue;
    ++on_part;
    for (const Marker& n : joined.orientations[1].markers)
      same += n.on == MarkerCarrier::Part && (n.position - turn * m.position).norm() < 1e-6;
  }
  EXPECT_GT(on_part, 0u);
  EXPECT_EQ(same, on_part);
  // The markers on the part cover its surface: no view measures a sample within 8 mm
  // (half the diameter) of one on its face, which the plan with the plate's markers alone
  // measures.
  std::vector<std::size_t> covered;
  for (std::size_t i = 0; i < joined.samples.size(); ++i)
    for (const Marker& m : joined.orientations[0].markers) {
      const Sample& s = joined.samples[i].sample;
      if (m.on == MarkerCarrier::Part && (s.position - m.position).norm() < 7.9 &&
          s.normal.dot(m.normal) > 0.9) {
        covered.push_back(i);
        break;
      }
    }

  const Plan apart = planOn("plate");
  ASSERT_EQ(apart.orientations.size(), 2u);
  const std::vector<SetupRegistration> alone = setupRegistration(apart);
  EXPECT_EQ(alone[1].frame, 1u);
  EXPECT_LT(registeredInOneFrame(alone), apart.views.size());
  EXPECT_EQ(planJson(apart)["summary"]["setups"]["joined"], false);
  EXPECT_GT(covered.size(), 0u);
  for (std::size_t i : covered) {
    EXPECT_TRUE(joined.samples[i].measured_by.empty()) << "sample " << i;
    EXPECT_FALSE(apart.samples[i].measured_by.empty()) << "sample " << i;
  }
  // plan.json keeps each setup's frame and what carries each marker.
  writePlan(joined, dir.file("plan.json"));
  const Plan read = readPlan(dir.file("plan.json"));
  EXPECT_EQ(setupRegistration(read)[1].frame, 0u);
  EXPECT_EQ(read.orientations[0].markers.front().on, joined.orientations[0].markers.front().on);
}

// A marker frame around a panel `length` x `width` on the working plane: two rings of
// markers 40 mm apart, 200 and 240 mm out from its edges.
std::vector<Marker> markerFrame(double length, double width) {
  std::vector<Marker> frame;
  for (double x = -240; x <= length + 240 + 1e-9; x += 40)
    for (double y = -240; y <= width + 240 + 1e-9; y += 40) {
      const double out = std::max({-x, x - length, -y, y - width});  // beyond the nearest edge
      if (out >= 200 - 1e-9) frame.push_back({Vec3(x, y, 0), Vec3::UnitZ()});
    }
  return frame;
}

// A panel 500 x 375 mm in a marker frame: views over its middle see no marker of the frame
// and only a plane, so they register to nothing. The markers proposed for reference points
// give each of them three, within 1.5 times the proposal's bound; added to the frame's
// (and those the plans made again propose), every view of the last plan registers.
TEST(ReferencePointsTest, MarkersProposedInAFrameRegisterEveryViewOfAPanel) {
  const Part part = flatSlab(500, 375);
  test::TempDir dir;
  writeMarkers(markerFrame(500, 375), dir.file("frame.csv"));
  test::writeText(dir.file("spec.yaml"), "markers: " + dir.file("frame.csv") +
                                             "\nregistration: {method: reference_points}\n"
                                             "tasks:\n  - {type: global}\n");
  Spec spec = loadSpec(dir.file("spec.yaml"));
  const Plan bare = planViews(part, spec);
  ASSERT_TRUE(bare.proposed_markers);
  const MarkerProposal& proposal = *bare.proposed_markers;
  RecordProperty("registered", std::to_string(bare.registration->registered()) + " of " +
                                   std::to_string(bare.views.size()));
  RecordProperty("proposed", std::to_string(proposal.markers.size()) + ", bound " +
                                 std::to_string(proposal.lower_bound));
  EXPECT_LT(bare.registration->registered(), bare.views.size());
  ASSERT_GT(proposal.lower_bound, 0u);
  EXPECT_LE(static_cast<double>(proposal.markers.size()),
            1.5 * static_cast<double>(proposal.lower_bound));

  const PlacedMarkers placed = planWithProposedMarkers(part, spec, bare);
  RecordProperty("registered_with_them", std::to_string(placed.plan.registration->registered()) +
                                             " of " + std::to_string(placed.plan.views.size()) +
                                             ", " + std::to_string(placed.placed.size()) +
                                             " markers placed");
  EXPECT_EQ(placed.plan.markers.size(), markerFrame(500, 375).size() + placed.placed.size());
  EXPECT_EQ(placed.plan.registration->registered(), placed.plan.views.size());

  // Written and read back, the markers placed are known as such: verified against the spec,
  // which lists the frame's alone, every view registers as planned.
  writePlan(placed.plan, dir.file("placed.json"));
  const Plan read = readPlan(dir.file("placed.json"));
  EXPECT_EQ(static_cast<std::size_t>(std::count_if(read.markers.begin(), read.markers.end(),
                                                   [](const Marker& m) { return m.placed; })),
            placed.placed.size());
  const PlanCheck check = verifyPlan(read, part, spec);
  EXPECT_EQ(check.registration_differences, 0u);
  EXPECT_EQ(check.unregistered, 0u);
}

// In robot mode, the robot's pose accuracy places views that ICP cannot: within the
// 0.1 mm tolerance at 0.05 mm, every view of the slab registers; at 1 mm, those that see
// only the plane do not, as without the robot.
TEST(RegistrationTest, AnAccurateRobotRegistersViewsOfAPlane) {
  const Part part = flatSlab();
  test::TempDir dir;
  auto planWith = [&](const std::string& registration) {
    test::writeText(dir.file("spec.yaml"),
                    "registration: " + registration + "\ntasks:\n  - {type: global}\n");
    return planViews(part, loadSpec(dir.file("spec.yaml")));
  };
  const Plan accurate = planWith("{method: robot, robot_accuracy: 0.05, tolerance: 0.1}");
  const Plan coarse = planWith("{method: robot, robot_accuracy: 1, tolerance: 0.1}");
  const Plan geometry = planWith("{method: geometry}");
  ASSERT_GE(accurate.views.size(), 2u);
  EXPECT_EQ(accurate.registration->method, RegistrationMode::Robot);
  EXPECT_EQ(accurate.registration->registered(), accurate.views.size());
  EXPECT_EQ(accurate.registration->bridging_views, 0u);
  std::size_t by_robot = 0;
  for (const ViewRegistration& view : accurate.registration->views)
    by_robot += view.method == RegistrationMethod::Robot;
  EXPECT_GT(by_robot, 0u);
  EXPECT_LT(coarse.registration->registered(), coarse.views.size());
  EXPECT_EQ(coarse.registration->registered(), geometry.registration->registered());
  // plan.json keeps the method and the accuracy.
  writePlan(accurate, dir.file("plan.json"));
  const Plan read = readPlan(dir.file("plan.json"));
  EXPECT_EQ(read.registration->method, RegistrationMode::Robot);
  EXPECT_EQ(read.registration->robot_accuracy, 0.05);
  EXPECT_EQ(read.registration->registered(), accurate.views.size());
}

// The slab's views see only a plane: the plan proposes markers, at least the bound (each
// view registered to nothing needs 3 it sees) and at most 3 per pair of views it joins plus
// one where those lie on a line, all on the plate (markers on the slab would hide its
// surface); placed (`--place-markers`), every view of the plan made again registers.
// Measured: 16 markers for 5 views, bound 6 (pairs of views must share their markers);
// 20 placed in two rounds, and all 9 views of the last plan registered; 1 of 5 without.
TEST(RegistrationTest, MarkersProposedForAFlatPartRegisterItsViews) {
  const Part part = flatSlab();
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"), "tasks:\n  - {type: global}\n");
  const Plan bare = planViews(part, loadSpec(dir.file("spec.yaml")));
  ASSERT_TRUE(bare.proposed_markers);
  const MarkerProposal& proposal = *bare.proposed_markers;
  RecordProperty("proposed", std::to_string(proposal.markers.size()));
  RecordProperty("lower_bound", std::to_string(proposal.lower_bound));
  RecordProperty("registered", std::to_string(bare.registration->registered()) + " of " +
                                   std::to_string(bare.views.size()));
  EXPECT_LT(bare.registration->registered(), bare.views.size());
  EXPECT_GT(proposal.views, 0u);
  ASSERT_GT(proposal.lower_bound, 0u);
  EXPECT_GE(proposal.markers.size(), proposal.lower_bound);
  EXPECT_LE(proposal.markers.size(), 4 * (bare.views.size() - 1));

  // Markers on the slab would hide its surface: the plate serves, so they lie on the plate.
  for (const Marker& m : proposal.markers) EXPECT_EQ(m.on, MarkerCarrier::Plane);

  const PlacedMarkers marked = planWithProposedMarkers(part, loadSpec(dir.file("spec.yaml")), bare);
  RecordProperty("registered_with_them", std::to_string(marked.plan.registration->registered()) +
                                             " of " + std::to_string(marked.plan.views.size()) +
                                             ", " + std::to_string(marked.placed.size()) +
                                             " markers placed");
  EXPECT_EQ(marked.plan.registration->registered(), marked.plan.views.size());
}

// The cycle of the first k views, read back from plan.json: one time per view, the first
// view's standing time alone, each further view adding at least its standing time; the
// path through all of them within a fifth of the plan's own cycle, which walks its 2-opt
// tour with home and approach moves.
TEST_F(RegisteredPlan, CycleByViewsRisesByEachViewsStandingTime) {
  const Plan& plan = *plan_;
  ASSERT_TRUE(plan.cycle);
  const std::vector<double>& seconds = plan.cycle->by_views;
  ASSERT_EQ(seconds.size(), plan.views.size());
  const double standing = viewSeconds(plan.scanner, spec_->cycle);
  EXPECT_NEAR(seconds.front(), standing, 1e-9);
  for (std::size_t k = 1; k < seconds.size(); ++k)
    EXPECT_GE(seconds[k] - seconds[k - 1], standing - 1e-9) << "view " << k + 1;
  EXPECT_NEAR(seconds.back(), plan.cycle->total(), 0.2 * plan.cycle->total());
}

TEST_F(RegisteredPlan, VerifyAgreesWithThePlanWrittenAndReadBack) {
  test::TempDir dir;
  writePlan(*plan_, dir.file("plan.json"));
  const Plan read = readPlan(dir.file("plan.json"));
  ASSERT_EQ(read.views.size(), plan_->views.size());
  EXPECT_EQ(read.markers.size(), plan_->markers.size());
  EXPECT_EQ(read.samples.size(), plan_->samples.size());
  EXPECT_EQ(read.sequence->views, plan_->sequence->views);
  ASSERT_TRUE(read.registration);
  EXPECT_EQ(read.registration->pairs.size(), plan_->registration->pairs.size());
  EXPECT_EQ(read.registration->registered(), plan_->registration->registered());
  const PlanCheck check = verifyPlan(read, *part_, *spec_);
  EXPECT_EQ(check.coverage_differences, 0u);
  EXPECT_EQ(check.registration_differences, 0u);
  EXPECT_EQ(check.sequence_missing, 0u);
  EXPECT_EQ(check.sequence_breaks, 0u);
  EXPECT_EQ(check.plan.registration->registered(), plan_->registration->registered());
  EXPECT_EQ(check.plan.registration->bridging_views, plan_->registration->bridging_views);
  EXPECT_NEAR(check.plan.sequence->length, plan_->sequence->length, 1e-6);

  // A plan that claims a view measures what it does not is caught.
  Plan wrong = read;
  for (PlannedSample& s : wrong.samples)
    if (s.measured_by.empty()) {
      s.measured_by.push_back(wrong.views.front().id);
      break;
    }
  EXPECT_EQ(verifyPlan(wrong, *part_, *spec_).coverage_differences, 1u);
}

// The bundled example's samples lie on their faces of the part planned. Moved along their
// normals by twice what a sample may lie off an elementary surface, each on a plane,
// cylinder, cone, sphere or torus lies off it (by the test's own count of such faces), and
// the part is refused as not the plan's; by half that, none does.
TEST_F(RegisteredPlan, SamplesMovedOffTheirFacesMakeThePartNotThePlans) {
  const PartFit fit = partFit(*plan_, *part_);
  EXPECT_EQ(fit.samples, plan_->samples.size());
  EXPECT_EQ(fit.off, 0u);
  EXPECT_LT(fit.exact_farthest, 1e-6);
  EXPECT_NO_THROW(checkPlanPart(*plan_, *part_));
  std::size_t elementary = 0;
  for (const PlannedSample& s : plan_->samples)
    elementary += elementarySurface(*part_, s.sample.face).has_value();
  ASSERT_GT(elementary, plan_->samples.size() / 2);
  auto moved = [&](double by) {
    Plan plan = *plan_;
    for (PlannedSample& s : plan.samples) s.sample.position += by * s.sample.normal;
    return plan;
  };
  EXPECT_EQ(partFit(moved(fit.exact_tolerance / 2), *part_).off, 0u);
  const Plan off = moved(2 * fit.exact_tolerance);
  EXPECT_GE(partFit(off, *part_).off, elementary);
  try {
    checkPlanPart(off, *part_);
    ADD_FAILURE() << "a part its plan's samples lie off is taken";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(part_->file), std::string::npos) << message;
    EXPECT_NE(message.find("not the part the plan was made for"), std::string::npos) << message;
  }
}

// On the die-cast housing's plan: the check verifies by ICP only the pairs its own tree
// needs, where the planner verified others too (bridging, checks run ahead), and a sequence
// may rely on one of those: view `b` right after `a`, which it registers to by a stable pair the
// check left unverified and the plan says ICP passed. The check confirms such a link by ICP before
// it counts a break; where the plan says ICP failed the pair, it counts one.
TEST(RegistrationTest, VerifyConfirmsTheIcpLinksTheSequenceReliesOn) {
  SHARED_DATA_OR_SKIP(path, "mech/asi_repatch-hpdc.stp");
  const Part part = importPart(path);
  const Spec spec = defaultSpec();
  const Plan plan = planViews(part, spec);
  ASSERT_TRUE(plan.registration && plan.registration->aligned_as_taken);
  const PlanCheck first = verifyPlan(plan, part, spec);
  EXPECT_EQ(first.sequence_breaks, 0u);
  const Registration& checked = *first.plan.registration;
  std::map<int, std::size_t> index;
  for (std::size_t v = 0; v < plan.views.size(); ++v) index[plan.views[v].id] = v;
  const Simulator simulator(
      part, plan.scanner, simulationOptionsFor(resolveSpec(part, spec), part, plan.part_to_world));
  std::optional<PairCheck> relied;  // a stable pair the check left unverified that ICP passes
  for (const PairCheck& p : checked.pairs)
    if (!p.markers && p.stable && !p.icp &&
        checked.views[index.at(p.b)].method != RegistrationMethod::None &&
        checkIcp(simulator, plan.views[index.at(p.a)], plan.views[index.at(p.b)],
                 registrationOptions(spec))
            .passed) {
      relied = p;
      break;
    }
  ASSERT_TRUE(relied) << "no stable pair left unverified that ICP passes";

  Plan reordered = plan;
  std::vector<int>& order = reordered.sequence->views;
  std::erase_if(order, [&](int id) { return id == relied->a || id == relied->b; });
  order.insert(order.begin(), {relied->a, relied->b});
  auto claim = [&](bool passed) {
    for (PairCheck& p : reordered.registration->pairs)
      if (p.a == relied->a && p.b == relied->b) p.icp = IcpCheck{.passed = passed};
    return verifyPlan(reordered, part, spec).sequence_breaks;
  };
  EXPECT_EQ(claim(true), 0u);
  EXPECT_EQ(claim(false), 1u);
}

// The die-cast housing in every rest orientation (four setups), registered by its geometry.
// The merged plan numbers each later setup's views after the earlier ones', where each
// setup was planned with its views numbered from 1; those numbers seed each view's
// simulated cloud and ICP's start. The check runs each setup with its numbers as planned:
// every pair both verified by ICP has the same ICP error, in the later setups too, and no
// view registers otherwise than planned.
TEST(RegistrationTest, VerifyRunsEachSetupsIcpAsItWasPlanned) {
  SHARED_DATA_OR_SKIP(path, "mech/asi_repatch-hpdc.stp");
  const Part part = importPart(path);
  Spec spec = defaultSpec();
  spec.rest_all = true;
  const Plan plan = planViews(part, spec);
  ASSERT_GE(plan.orientations.size(), 2u);
  const PlanCheck check = verifyPlan(plan, part, spec);
  EXPECT_EQ(check.registration_differences, 0u);
  EXPECT_EQ(check.plan.registration->registered(), plan.registration->registered());
  const std::set<int> first(plan.orientations[0].views.begin(), plan.orientations[0].views.end());
  std::size_t compared = 0, later = 0;
  for (const PairCheck& p : plan.registration->pairs) {
    const PairCheck* again = check.plan.registration->pair(p.a, p.b);
    if (!p.icp || !again || !again->icp) continue;
    ++compared;
    later += !first.count(p.a);
    EXPECT_NEAR(again->icp->error, p.icp->error, 1e-9) << "views " << p.a << ", " << p.b;
    EXPECT_EQ(again->icp->passed, p.icp->passed) << "views " << p.a << ", " << p.b;
  }
  EXPECT_GT(later, 0u) << "no pair of a later setup verified by ICP in both";
  EXPECT_GT(compared, later);
}

// The die-cast housing in every rest orientation on a cell's turning table, registered by
// the markers on the table's plate, which turn with it: the check of each setup takes each
// of its views at the table angle the plan takes it at, and finds the views registered as
// planned.
TEST(RegistrationTest, VerifyTurnsTheTableForEachSetupsViewsAsPlanned) {
  SHARED_DATA_OR_SKIP(path, "mech/asi_repatch-hpdc.stp");
  const Part part = importPart(path);
  test::TempDir dir;
  test::writeText(dir.file("spec.yaml"),
                  "part: {rest: all}\n"
                  "markers: {grid: 40, on: plate}\n"
                  "registration: {method: markers}\n"
                  "tasks: [{type: global}]\n"
                  "cell:\n"
                  "  robot: {preset: abb-irb4600-60-205, base: {position: [-1000, 0, 0]}}\n"
                  "  mount: {position: [0, 0, 150]}\n"
                  "  table: {}\n");
  const Spec spec = loadSpec(dir.file("spec.yaml"));
  const Plan plan = planViews(part, spec);
  ASSERT_GE(plan.orientations.size(), 2u);
  std::set<double> angles;
  for (const std::optional<CellPose>& pose : plan.cell_poses)
    if (pose) angles.insert(pose->table_angle);
  ASSERT_GE(angles.size(), 2u) << "the table does not turn";
  const PlanCheck check = verifyPlan(plan, part, spec);
  EXPECT_EQ(check.registration_differences, 0u);
  EXPECT_EQ(check.plan.registration->registered(), plan.registration->registered());
}

// The first rest orientation of a plan over several may hold no view (the planner keeps
// the first, whatever it adds). NIST FTC 11's plan, its views put in a second setup that
// stands the part as planned, behind an empty first one: the check finds every view as
// planned.
TEST(RegistrationTest, VerifyChecksAPlanWhoseFirstSetupHasNoViews) {
  const Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  const Spec spec = defaultSpec();
  Plan plan = planViews(part, spec);
  ASSERT_TRUE(plan.registration);
  PlannedOrientation empty, all;
  empty.rest.part_to_world = Pose(Eigen::Translation3d(0, 0, 50)) * plan.part_to_world;
  all.rest.part_to_world = plan.part_to_world;
  all.reference = plan.registration->reference;
  all.frame = 1;
  for (const View& view : plan.views) all.views.push_back(view.id);
  plan.orientations = {empty, all};
  const PlanCheck check = verifyPlan(plan, part, spec);
  EXPECT_EQ(check.coverage_differences, 0u);
  EXPECT_EQ(check.registration_differences, 0u);
  EXPECT_EQ(check.sequence_missing, 0u);
  EXPECT_EQ(check.sequence_breaks, 0u);
  EXPECT_EQ(check.plan.registration->registered(), plan.registration->registered());
}

}  // namespace
}  // namespace scanplan
