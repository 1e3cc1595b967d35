// Fits of ideal geometry against closed-form answers.

#include <scanplan/solve/fits.h>

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <vector>

using namespace scanplan;

namespace {

// A square grid of n x n points over side `side` in z = 0, each with Gaussian noise in z.
std::vector<Vec3> noisyGrid(int n, double side, double sigma, std::mt19937_64& random) {
  std::normal_distribution<double> noise(0, sigma);
  std::vector<Vec3> points;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
      points.push_back({side * ((i + 0.5) / n - 0.5), side * ((j + 0.5) / n - 0.5), noise(random)});
  return points;
}

double standardDeviation(const std::vector<double>& values) {
  double mean = 0, squares = 0;
  for (double v : values) mean += v / static_cast<double>(values.size());
  for (double v : values) squares += (v - mean) * (v - mean);
  return std::sqrt(squares / static_cast<double>(values.size() - 1));
}

}  // namespace

// A least-squares plane through N points of noise sigma: its offset has the deviation
// sigma / sqrt(N), and each slope sigma / sqrt(sum u^2), sum u^2 = N side^2 / 12 on a
// uniform grid (less the grid's own discreteness, (n^2 - 1) / n^2).
TEST(Fits, PlaneFitsSpreadIsTheClosedFormUnderKnownNoise) {
  std::mt19937_64 random(7);
  const int n = 20;
  const double side = 100, sigma = 0.01;
  std::vector<double> offsets, slopes;
  for (int draw = 0; draw < 400; ++draw) {
    const std::vector<Vec3> points = noisyGrid(n, side, sigma, random);
    const PlaneFit fit = fitPlane(points, Vec3::UnitZ());
    ASSERT_TRUE(fit.determined);
    offsets.push_back(fit.point.z());
    slopes.push_back(fit.normal.x() / fit.normal.z());
  }
  const double count = n * n;
  const double spread_u = side * side / 12 * (1 - 1.0 / (n * n));
  EXPECT_NEAR(standardDeviation(offsets), sigma / std::sqrt(count), 0.1 * sigma / std::sqrt(count));
  const double slope = sigma / std::sqrt(count * spread_u);
  EXPECT_NEAR(standardDeviation(slopes), slope, 0.1 * slope);
}

// Points on a bowl z = b (1 - r^2 / R^2) over a disc of radius R, tilted: whatever the
// tilt, the narrowest zone is b (the vertex against the rim), where the least-squares
// plane's peak to valley is larger once the bowl is tilted off the fit's plane.
TEST(Fits, MinimumZoneFlatnessOfABowIsTheBow) {
  const double bow = 0.05, radius = 50;
  std::vector<Vec3> points;
  for (int ring = 0; ring <= 10; ++ring)
    for (int k = 0; k < 36; ++k) {
      const double r = radius * ring / 10, a = 2 * std::numbers::pi * k / 36;
      const double x = r * std::cos(a), y = r * std::sin(a);
      points.push_back({x, y, bow * (1 - r * r / (radius * radius)) + 0.001 * x});
    }
  EXPECT_NEAR(minimumZoneFlatness(points, Vec3::UnitZ()), bow, 1e-6);
  EXPECT_NEAR(minimumZoneFlatness(points, Vec3(0.05, 0.02, 1).normalized()), bow, 1e-6);
  std::vector<Vec3> flat = points;
  for (Vec3& p : flat) p.z() = 0.001 * p.x();
  EXPECT_NEAR(minimumZoneFlatness(flat, Vec3::UnitZ()), 0, 1e-9);
}

// A full circle of N points of radial noise sigma: the fitted radius has the deviation
// sigma / sqrt(N); a tilted, shifted nominal start converges on the true axis.
TEST(Fits, CylinderFitsRadiusSpreadIsTheClosedFormAndTheAxisIsFound) {
  std::mt19937_64 random(11);
  const double radius = 17.5, sigma = 0.01;
  const Vec3 axis = Vec3(0.1, -0.2, 1).normalized(), origin(30, -20, 5);
  const Vec3 e1 = axis.unitOrthogonal(), e2 = axis.cross(e1);
  std::normal_distribution<double> noise(0, sigma);
  std::vector<double> radii;
  const int around = 40, along = 10;
  for (int draw = 0; draw < 300; ++draw) {
    std::vector<Vec3> points;
    for (int k = 0; k < around; ++k)
      for (int h = 0; h < along; ++h) {
        const double a = 2 * std::numbers::pi * (k + 0.5) / around;
        points.push_back(origin + 3.0 * h * axis +
                         (radius + noise(random)) * (std::cos(a) * e1 + std::sin(a) * e2));
      }
    CylinderFit start;
    start.point = origin + Vec3(0.5, 0.3, 0);
    start.axis = Vec3::UnitZ();
    start.radius = 18;
    const CylinderFit fit = fitCylinder(points, start);
    ASSERT_TRUE(fit.determined);
    ASSERT_GT(std::abs(fit.axis.dot(axis)), 1 - 1e-6);
    ASSERT_LT(axisDistance(fit, origin), 0.01);
    radii.push_back(fit.radius);
  }
  const double expected = sigma / std::sqrt(around * along);
  EXPECT_NEAR(standardDeviation(radii), expected, 0.12 * expected);
}

// Points spread evenly over a sphere (a Fibonacci lattice of `count`) within `polar` of
// its pole, with radial noise.
std::vector<Vec3> onSphere(const Vec3& centre, double radius, double polar, int count,
                           std::normal_distribution<double>& noise, std::mt19937_64& random) {
  std::vector<Vec3> points;
  const double lowest = std::cos(polar), golden = std::numbers::pi * (3 - std::sqrt(5.0));
  for (int k = 0; k < count; ++k) {
    const double z = 1 - (1 - lowest) * (k + 0.5) / count, ring = std::sqrt(1 - z * z);
    const Vec3 u(ring * std::cos(golden * k), ring * std::sin(golden * k), z);
    points.push_back(centre + (radius + noise(random)) * u);
  }
  return points;
}

// A sphere's radius fitted to 400 points all over it spreads as the noise over the root of
// their count (the centre's directions orthogonal to the radius'), its centre found; a cap
// 100° across fixes it too (without noise, exactly), a band 10° wide about its equator does
// not (the centre is free along its axis).
TEST(Fits, SphereFitsRadiusSpreadIsTheClosedFormAndOnlyACapFixesIt) {
  std::mt19937_64 random(12);
  const double radius = 15.875, sigma = 0.01;
  const Vec3 centre(-114.3, 63.5, -107.95);
  std::normal_distribution<double> noise(0, sigma);
  std::vector<double> radii;
  for (int draw = 0; draw < 300; ++draw) {
    const SphereFit fit = fitSphere(onSphere(centre, radius, std::numbers::pi, 400, noise, random));
    ASSERT_TRUE(fit.determined);
    ASSERT_LT((fit.centre - centre).norm(), 0.01);
    radii.push_back(fit.radius);
  }
  const double expected = sigma / std::sqrt(400.0);
  EXPECT_NEAR(standardDeviation(radii), expected, 0.12 * expected);
  std::normal_distribution<double> none(0, 0);
  const SphereFit cap = fitSphere(onSphere(centre, radius, radians(50), 400, none, random));
  EXPECT_TRUE(cap.determined);
  EXPECT_NEAR(cap.radius, radius, 1e-9);
  EXPECT_NEAR((cap.centre - centre).norm(), 0, 1e-9);
  std::vector<Vec3> band;
  for (int k = 0; k < 400; ++k) {
    const double a = 2 * std::numbers::pi * k / 400, z = radians(5) * std::sin(7.0 * a);
    band.push_back(
        centre + radius * Vec3(std::cos(z) * std::cos(a), std::cos(z) * std::sin(a), std::sin(z)));
  }
  EXPECT_FALSE(fitSphere(band).determined);
}

// A hole's wall (normals towards the axis) over a third of its circle: the axis and radius
// from the normals alone.
TEST(Fits, ACylindersAxisAndRadiusFollowFromItsNormals) {
  const double radius = 12;
  const Vec3 axis = Vec3::UnitY(), centre(5, 0, -3);
  std::vector<Vec3> points, normals;
  for (int k = 0; k < 30; ++k)
    for (int h = 0; h < 4; ++h) {
      const double a = 2 * std::numbers::pi / 3 * k / 29;
      const Vec3 out(std::cos(a), 0, std::sin(a));
      points.push_back(centre + 5.0 * h * axis + radius * out);
      normals.push_back(-out);
    }
  const CylinderFit fit = cylinderFromNormals(points, normals);
  ASSERT_TRUE(fit.determined);
  EXPECT_GT(std::abs(fit.axis.dot(axis)), 1 - 1e-9);
  EXPECT_NEAR(fit.radius, radius, 1e-9);
  EXPECT_NEAR(axisDistance(fit, centre), 0, 1e-9);
  std::vector<Vec3> flat(points.size(), Vec3::UnitZ());
  EXPECT_FALSE(cylinderFromNormals(points, flat).determined);
}

// Points on a parabola w = k u^2 over u in [-50, 50] bow by k 50^2 = 0.05 mm; the minimum zone
// holds them between the line through its ends and the tangent at its vertex: 0.05, however
// the element is turned in its plane.
TEST(Fits, MinimumZoneStraightnessOfABowIsItsSagitta) {
  const double k = 0.05 / (50.0 * 50.0);
  for (const double turn : {0.0, 0.01, -0.2}) {
    std::vector<Vec3> points;
    for (double u = -50; u <= 50; u += 0.5) {
      const double w = k * u * u;
      points.push_back(
          {std::cos(turn) * u - std::sin(turn) * w, 3.0, std::sin(turn) * u + std::cos(turn) * w});
    }
    EXPECT_NEAR(minimumZoneStraightness(points, Vec3::UnitX(), Vec3::UnitZ()), 0.05, 1e-6)
        << "turned " << turn;
  }
  EXPECT_EQ(
      minimumZoneStraightness(std::vector<Vec3>(2, Vec3::Zero()), Vec3::UnitX(), Vec3::UnitZ()), 0);
}

// Seven points on a circle of radius 0.03 about (0.01, -0.02) and forty inside it: the
// smallest circle holding them is that circle. Two points: their distance; three on a line:
// the farthest two's.
TEST(Fits, TheSmallestEnclosingCircleOfPointsOnACircleIsThatCircle) {
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> unit(0, 1);
  const Eigen::Vector2d centre(0.01, -0.02);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 40; ++i) {
    const double a = 2 * std::numbers::pi * unit(random), r = 0.03 * std::sqrt(unit(random));
    points.push_back(centre + r * 0.99 * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  for (int i = 0; i < 7; ++i) {
    const double a = 2 * std::numbers::pi * i / 7;
    points.insert(points.begin() + 5 * i,
                  centre + 0.03 * Eigen::Vector2d(std::cos(a), std::sin(a)));
  }
  EXPECT_NEAR(enclosingCircleDiameter(points), 0.06, 1e-12);
  const std::vector<Eigen::Vector2d> two = {{0, 0}, {0.3, 0.4}};
  EXPECT_NEAR(enclosingCircleDiameter(two), 0.5, 1e-12);
  const std::vector<Eigen::Vector2d> line = {{0, 0}, {2, 0}, {1, 0}};
  EXPECT_NEAR(enclosingCircleDiameter(line), 2, 1e-12);
}

// A band 3 mm high of a Ø63 cylinder about (0.2, -0.1) (the rim of NIST FTC 11, say), its
// axis held along z: the fit finds the centre and the radius, and leaves the axis as it was
// started, tilted 0.01 rad off z as the start is. Without holding, the fit turns the axis.
TEST(Fits, AShortBandHeldOnItsAxisIsFittedAsACircle) {
  std::vector<Vec3> points;
  for (double z = 0; z <= 3; z += 0.5)
    for (int i = 0; i < 180; ++i) {
      const double a = 2 * std::numbers::pi * i / 180;
      points.push_back({0.2 + 31.5 * std::cos(a), -0.1 + 31.5 * std::sin(a), z});
    }
  CylinderFit start;
  start.axis = Vec3(0.01, 0, 1).normalized();
  start.radius = 31.4;
  const CylinderFit held = fitCylinder(points, start, true);
  ASSERT_TRUE(held.determined);
  EXPECT_NEAR((held.axis - start.axis).norm(), 0, 1e-12);
  EXPECT_NEAR(held.radius, 31.5, 0.01);  // about the tilted axis: the band's ellipse
  EXPECT_NEAR(held.point.x() - held.point.z() * start.axis.x() / start.axis.z(), 0.2, 0.02);
  EXPECT_NEAR(held.point.y(), -0.1, 1e-6);
  const CylinderFit free = fitCylinder(points, start);
  ASSERT_TRUE(free.determined);
  EXPECT_NEAR(free.axis.z(), 1, 1e-9);
  EXPECT_NEAR(free.radius, 31.5, 1e-9);
}
