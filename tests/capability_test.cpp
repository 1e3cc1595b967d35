// Characteristics against the STEP files' own PMI entities, and measurement capability
// against analytic least-squares results on a plane.

#include "hole_plate.h"
#include "planning/marker_adjustment.h"
#include "planning/registration_error.h"
#include "planning/simulated_registration.h"
#include "support.h"

#include <scanplan/cad/gdt.h>
#include <scanplan/cad/import.h>
#include <scanplan/cad/localization.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/planning.h>
#include <scanplan/planning/capability.h>
#include <scanplan/planning/inspection.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepAlgoAPI_Fuse.hxx>
#include <BRepBndLib.hxx>
#include <BRepFilletAPI_MakeFillet.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepPrimAPI_MakeSphere.hxx>
#include <BRepTools.hxx>
#include <Bnd_Box.hxx>
#include <TopExp_Explorer.hxx>
#include <TopoDS.hxx>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <iterator>
#include <string_view>

namespace scanplan {
namespace {

// Entity instances in a STEP file's text of one of `types` (a complex entity once).
std::size_t stepEntities(const std::string& path, const std::vector<std::string>& types) {
  std::ifstream in(path);
  const std::string text{std::istreambuf_iterator<char>(in), {}};
  std::size_t count = 0, start = 0;
  for (std::size_t end; (end = text.find(';', start)) != std::string::npos; start = end + 1) {
    const std::string_view instance(text.data() + start, end - start);
    count += std::any_of(types.begin(), types.end(), [&](const std::string& type) {
      const std::size_t at = instance.find(type + "(");
      return at != std::string_view::npos && at > 0 && !std::isalnum(instance[at - 1]) &&
             instance[at - 1] != '_';
    });
  }
  return count;
}

const std::vector<std::string> kTolerances = {
    "FLATNESS_TOLERANCE",        "POSITION_TOLERANCE",      "PERPENDICULARITY_TOLERANCE",
    "PARALLELISM_TOLERANCE",     "ANGULARITY_TOLERANCE",    "SURFACE_PROFILE_TOLERANCE",
    "LINE_PROFILE_TOLERANCE",    "CYLINDRICITY_TOLERANCE",  "ROUNDNESS_TOLERANCE",
    "STRAIGHTNESS_TOLERANCE",    "CONCENTRICITY_TOLERANCE", "SYMMETRY_TOLERANCE",
    "CIRCULAR_RUNOUT_TOLERANCE", "TOTAL_RUNOUT_TOLERANCE",  "COAXIALITY_TOLERANCE"};

// The union of the faces' bounds.
Box boundsOf(const Part& part, const std::vector<int>& faces) {
  Box box;
  for (int f : faces) box.add(part.faces[f - 1].bounds);
  return box;
}

// Tolerances as the file's tolerance entities, dimensions as its dimensional
// characteristic representations (a dimension with a value); each diameter on cylinders
// whose extent across is that diameter.
void expectCharacteristicsOfTheFile(const std::string& path, std::size_t tolerances,
                                    std::size_t dimensions) {
  const Part part = importPart(path);
  const std::vector<Characteristic> list = characteristics(part.gdt);
  EXPECT_EQ(stepEntities(path, kTolerances), tolerances);
  EXPECT_EQ(stepEntities(path, {"DIMENSIONAL_CHARACTERISTIC_REPRESENTATION"}), dimensions);
  ASSERT_EQ(list.size(), tolerances + dimensions);
  for (std::size_t k = 0; k < list.size(); ++k) {
    const Characteristic& c = list[k];
    EXPECT_EQ(c.id, static_cast<int>(k) + 1);
    EXPECT_EQ(c.dimension, k >= tolerances) << c.kind;
    EXPECT_FALSE(c.faces.empty()) << c.kind;
    if (c.kind != "diameter") continue;
    const Vec3 size = boundsOf(part, c.faces).size();
    int across = 0;  // extents equal to the diameter
    for (int a = 0; a < 3; ++a) across += std::abs(size[a] - c.value) < 0.01 * c.value;
    EXPECT_GE(across, 2) << "diameter " << c.value << " on faces of extent " << size.transpose();
    for (int f : c.faces) EXPECT_EQ(part.faces[f - 1].type, SurfaceType::Cylinder);
  }
}

TEST(Characteristics, MatchTheStepFilesPmi) {
  // CTC 01: 6 tolerances, 12 dimensions of which 8 carry a value; FTC 11: 4 and 6.
  expectCharacteristicsOfTheFile(test::example("parts/nist_ctc_01_asme1_ap242-e1.stp"), 6, 8);
  expectCharacteristicsOfTheFile(test::testData("nist_ftc_11_asme1_ap242-e1.stp"), 4, 6);
}

// P(R <= w) for R the range of n draws of the standard normal, by quadrature:
// n times the integral of phi(x) (Phi(x + w) - Phi(x))^(n - 1).
double rangeOfNormalsCdf(double w, double n) {
  const auto cdf = [](double x) { return 0.5 * std::erfc(-x / std::sqrt(2.0)); };
  double p = 0;
  const double dx = 1e-3;
  for (double x = -10 + dx / 2; x < 10; x += dx)
    p += std::exp(-x * x / 2) / std::sqrt(2 * M_PI) * std::pow(cdf(x + w) - cdf(x), n - 1) * dx;
  return n * p;
}

// Its 95th percentile.
double rangeOfNormals95(double n) {
  double lo = 0, hi = 20;
  for (int k = 0; k < 40; ++k)
    (rangeOfNormalsCdf((lo + hi) / 2, n) < 0.95 ? lo : hi) = (lo + hi) / 2;
  return (lo + hi) / 2;
}

// A view of id `id` straight down at (x, y) on a top 10 mm high, at the scanner's standoff.
View downAt(int id, const Scanner& scanner, double x, double y) {
  View view;
  view.id = id;
  view.camera_to_world.linear() = Vec3(1, -1, -1).asDiagonal();
  view.camera_to_world.translation() = Vec3(x, y, 10 + scanner.standoff);
  view.target = Vec3(x, y, 10);
  return view;
}

// The flatness `zone` of a 10 mm plate's top face.
Characteristic topFlatness(const Part& part, double zone) {
  Characteristic flatness;
  flatness.id = 1;
  flatness.kind = "flatness";
  flatness.value = flatness.upper = zone;
  for (const Face& f : part.faces)
    if (f.bounds.min.z() > 9.99) flatness.faces = {f.id};
  return flatness;
}

struct PlaneCase {
  double u = 0;
  Capability capability;
};

// The 100 x 100 mm top of a 10 mm plate with a flatness of 0.05, seen straight on at the
// standoff by a scanner of noise 0.01 mm and the given point spacing, read from points
// `evaluation` mm apart (planner.evaluation_spacing; 0: the default).
PlaneCase planeCase(const test::TempDir& dir, double spacing, double evaluation = 0) {
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 100, 10).Shape(), dir.file("plate.brep").c_str());
  const Part part = importPart(dir.file("plate.brep"));
  Spec spec = defaultSpec();
  spec.scanner.noise_sigma = 0.01;
  spec.scanner.point_spacing = spacing;
  spec.planner.capability.evaluation_spacing = evaluation;
  Plan plan;
  plan.scanner = spec.scanner;
  plan.views = {downAt(1, spec.scanner, 50, 50)};
  const Characteristic flatness = topFlatness(part, 0.05);
  const std::vector<Capability> result =
      capabilities(part, resolveSpec(part, spec), plan, {flatness});
  return {result.front().uncertainty, result.front()};
}

// The flatness is the minimum zone of the points read (docs/capability.md, "Error
// budget"): here each scanner's point, its spacing wider than the evaluation's 2.25 mm.
// Their noise spans it: U is the 95th percentile of the range of N draws of the noise,
// which the fitted plane's own tilt (L (|db| + |dc|), slopes of variance 12 sigma² /
// (N L²): 0.0044 mm at 625 points) hardly widens. Fewer points span less.
TEST(Capability, APlanesFlatnessIsTheRangeOfItsPointsNoise) {
  test::TempDir dir;
  const double sigma = 0.01;
  const PlaneCase full = planeCase(dir, 4);                   // 625 points
  const PlaneCase half = planeCase(dir, 4 * std::sqrt(2.0));  // half as many
  const PlaneCase sparse = planeCase(dir, 10);                // 100 points
  RecordProperty("u_625_points", std::to_string(full.u));
  RecordProperty("u_625_points_analytic", std::to_string(sigma * rangeOfNormals95(625)));
  RecordProperty("u_312_points", std::to_string(half.u));
  RecordProperty("u_100_points", std::to_string(sparse.u));
  EXPECT_NEAR(full.capability.covered, 1, 0.01);
  EXPECT_NEAR(full.capability.points, 625, 0.03 * 625);  // less only by the incidence
  for (const auto& [u, n] : {std::pair{full.u, 625.0}, {half.u, 312.5}, {sparse.u, 100.0}})
    EXPECT_NEAR(u, sigma * rangeOfNormals95(n), 0.05 * sigma * rangeOfNormals95(n)) << n;
  EXPECT_LT(sparse.u, half.u);
  EXPECT_LT(half.u, full.u);
  // The verdict follows from the ratio 0.05 / (2 U), about 0.35: the noise alone spans
  // more than the zone.
  EXPECT_NEAR(full.capability.ratio, 0.05 / (2 * full.u), 1e-12);
  EXPECT_EQ(full.capability.verdict, Verdict::NotCapable);
  EXPECT_EQ(full.capability.reason, Shortfall::TooUncertain);
}

// Read from points 8 mm apart (planner.evaluation_spacing), each the mean of four of the
// scanner's points 4 mm apart: 156 points of half the noise, whose range is U.
TEST(Capability, PointsReadFartherApartAverageTheNoiseOfAZone) {
  test::TempDir dir;
  const double sigma = 0.01 / 2, analytic = sigma * rangeOfNormals95(625.0 / 4);
  const PlaneCase averaged = planeCase(dir, 4, 8);
  RecordProperty("u_156_points", std::to_string(averaged.u));
  RecordProperty("u_156_points_analytic", std::to_string(analytic));
  EXPECT_NEAR(averaged.u, analytic, 0.05 * analytic);
}

// Four markers at (+-a, +-a, 0), centres measured with sigma per axis: the rigid fit's
// translation has the variance sigma^2 / 4 on each axis, its turn about z sigma^2 / (8 a^2)
// and about x or y sigma^2 / (4 a^2) (sum |p|^2 and sum y^2 of the markers).
TEST(ErrorBudget, TheRigidFitOfFourMarkersHasTheClosedFormCovariance) {
  const double a = 50, sigma = 0.01;
  const std::vector<Vec3> markers = {{a, a, 0}, {-a, a, 0}, {a, -a, 0}, {-a, -a, 0}};
  const detail::TwistCovariance c = detail::rigidFitCovariance(markers, sigma);
  for (int axis = 3; axis < 6; ++axis)
    EXPECT_NEAR(c(axis, axis), sigma * sigma / 4, 1e-6 * sigma * sigma);
  EXPECT_NEAR(c(2, 2), sigma * sigma / (8 * a * a), 1e-6 * sigma * sigma / (a * a));
  EXPECT_NEAR(c(0, 0), sigma * sigma / (4 * a * a), 1e-6 * sigma * sigma / (a * a));
}

// Three views, the first the reference and each of the others registered to the one before
// by markers; `seen`, the markers each sees: indices into the corners of a 400 mm square
// (0 to 3), of a 200 mm square (4 to 7) and of a 300 mm square turned 45 degrees (8 to 11),
// all about the origin.
Plan markerViews(const std::vector<std::vector<int>>& seen) {
  Plan plan;
  plan.scanner = defaultSpec().scanner;
  for (const double a : {200.0, 100.0})
    for (const Vec3& d : {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)})
      plan.markers.push_back({a * d, Vec3::UnitZ()});
  for (const Vec3& d : {Vec3(-1, 0, 0), Vec3(0, -1, 0), Vec3(1, 0, 0), Vec3(0, 1, 0)})
    plan.markers.push_back({150 * std::sqrt(2.0) * d, Vec3::UnitZ()});
  Registration registration;
  registration.method = RegistrationMode::Markers;
  for (int k = 0; k < 3; ++k) {
    plan.views.push_back(downAt(k + 1, plan.scanner, 0, 0));
    ViewRegistration r;
    r.method = k == 0 ? RegistrationMethod::Reference : RegistrationMethod::Markers;
    r.to = k;
    r.markers = seen[static_cast<std::size_t>(k)];
    registration.views.push_back(r);
  }
  plan.registration = registration;
  return plan;
}

// The model's registration errors of `plan`'s views, marker centres measured with `sigma`.
std::vector<detail::ViewError> markerErrors(const Plan& plan, double sigma) {
  ResolvedSpec spec;
  spec.spec = defaultSpec();
  spec.spec.registration.marker_sigma = sigma;
  return detail::registrationErrors(Part{}, spec, plan);
}

// The variance, over `draws` runs of the simulated registration, of where the last view
// puts the point `p` along `n`.
double simulatedVariance(const Plan& plan, double sigma, const Vec3& p, const Vec3& n, int draws) {
  const detail::SimulatedRegistration registration(plan, markerErrors(plan, sigma), sigma);
  std::mt19937_64 random(7);
  double sum = 0, squares = 0;
  for (int k = 0; k < draws; ++k) {
    const double d = n.dot(registration.draw(random).back() * p - p);
    sum += d;
    squares += d * d;
  }
  return squares / draws - (sum / draws) * (sum / draws);
}

// The model's variance of where the last view of `plan` puts `p` along `n`.
double modelVariance(const Plan& plan, double sigma, const Vec3& p, const Vec3& n) {
  const auto row = detail::alongNormal(p, n);
  return (row * markerErrors(plan, sigma).back().covariance * row.transpose())(0);
}

// The inspection's registration fits every view's pose and every marker's position to the
// noisy centres at once, by alternating rigid fits (Umeyama), not by the model's first
// order covariance. Where each marker set is seen by two views in a row, the adjustment is
// the chain's: the last view spreads as the two links' covariances added, within 8 % over
// 4000 runs, at the centre and 150 mm off it. Where all three views see the same four
// markers, the last view lies as if fitted to the first directly: one link's variance, in
// the model and in the fits (the middle view's centres cancel).
TEST(SimulatedRegistration, AChainOfMarkerFitsSpreadsAsTheLinksCovariancesAdded) {
  const double sigma = 0.02;
  const Plan apart = markerViews({{0, 1, 2, 3}, {0, 1, 2, 3, 4, 5, 6, 7}, {4, 5, 6, 7}});
  const auto square = [](double a) {
    return std::vector<Vec3>{{-a, -a, 0}, {a, -a, 0}, {a, a, 0}, {-a, a, 0}};
  };
  const detail::TwistCovariance links =
      detail::rigidFitCovariance(square(200), std::sqrt(2.0) * sigma) +
      detail::rigidFitCovariance(square(100), std::sqrt(2.0) * sigma);
  for (const Vec3& p : {Vec3(0, 0, 10), Vec3(150, 0, 10)})
    for (const Vec3& n : {Vec3(0, 0, 1), Vec3(1, 0, 0)}) {
      const auto row = detail::alongNormal(p, n);
      const double model = (row * links * row.transpose())(0);
      EXPECT_NEAR(modelVariance(apart, sigma, p, n), model, 1e-6 * model);
      EXPECT_NEAR(simulatedVariance(apart, sigma, p, n, 4000), model, 0.08 * model)
          << p.transpose() << " along " << n.transpose();
    }
  const Plan shared = markerViews({{0, 1, 2, 3}, {0, 1, 2, 3}, {0, 1, 2, 3}});
  const Vec3 centre(0, 0, 10), up(0, 0, 1);
  const auto row = detail::alongNormal(centre, up);
  const double one_link =
      (row * detail::rigidFitCovariance(square(200), std::sqrt(2.0) * sigma) * row.transpose())(0);
  EXPECT_NEAR(modelVariance(shared, sigma, centre, up), one_link, 1e-6 * one_link);
  EXPECT_NEAR(simulatedVariance(shared, sigma, centre, up, 4000), one_link, 0.08 * one_link);
}

// A loop of marker sets: the first two views share the 400 mm square, the last two the
// 200 mm one, the last and the first the turned 300 mm one. Along the normal at the
// centre each link fits its four markers' heights alone, of variance 2 sigma² / 4, and
// the adjustment is that of three equal resistors in a ring: the last view lies from the
// first as the direct link in parallel with the two others, 2/3 of one link's variance,
// where the chain through the middle view would give two links'. The model gives it to
// first order, the alternating fits within 8 % over 4000 runs.
TEST(SimulatedRegistration, ALoopOfMarkerSetsHoldsTheLastViewTighterThanAnyChain) {
  const double sigma = 0.02;
  const Plan loop = markerViews(
      {{0, 1, 2, 3, 8, 9, 10, 11}, {0, 1, 2, 3, 4, 5, 6, 7}, {4, 5, 6, 7, 8, 9, 10, 11}});
  const Vec3 centre(0, 0, 0), up(0, 0, 1);
  const double link = 2 * sigma * sigma / 4;
  EXPECT_NEAR(modelVariance(loop, sigma, centre, up), 2.0 / 3 * link, 1e-6 * link);
  EXPECT_NEAR(simulatedVariance(loop, sigma, centre, up, 4000), 2.0 / 3 * link,
              0.08 * 2.0 / 3 * link);
}

// Four views in a chain by markers over two setups (two views each), the third registered
// to the second by markers on the part: each setup's views form a group of their own, the
// third its second group's root, since the two setups' markers lie in frames of their own.
// The third keeps its own link to the second, the rigid fit of the markers they share.
TEST(MarkerGroups, StayWithinASetup) {
  Plan plan = markerViews({{0, 1, 2, 3}, {0, 1, 2, 3}, {0, 1, 2, 3}});
  plan.views.push_back(downAt(4, plan.scanner, 0, 0));
  ViewRegistration fourth;
  fourth.method = RegistrationMethod::Markers;
  fourth.to = 3;
  fourth.markers = {0, 1, 2, 3};
  plan.registration->views.push_back(fourth);
  plan.orientations.resize(2);
  plan.orientations[0].views = {1, 2};
  plan.orientations[1].views = {3, 4};
  for (PlannedOrientation& o : plan.orientations) o.markers = plan.markers;
  const std::vector<std::optional<std::size_t>> parents = {std::nullopt, 0, 1, 2};
  const std::vector<detail::MarkerGroup> groups =
      detail::markerGroups(plan, parents, std::vector<char>(4, 1));
  ASSERT_EQ(groups.size(), 2u);
  EXPECT_EQ(groups[0].root, 0u);
  EXPECT_EQ(groups[0].members, std::vector<std::size_t>{1});
  EXPECT_EQ(groups[1].root, 2u);
  EXPECT_EQ(groups[1].members, std::vector<std::size_t>{3});
  const std::vector<detail::ViewError> errors = markerErrors(plan, 0.02);
  EXPECT_FALSE(errors[2].adjusted);
  EXPECT_EQ(errors[2].parent, std::optional<std::size_t>(1));
  EXPECT_TRUE(errors[3].adjusted);
  EXPECT_EQ(errors[3].parent, std::optional<std::size_t>(2));
}

// ICP on three orthogonal planes through the origin, each a centred grid of m points of
// variance v along its normal: a translation along x is fixed by the plane x = 0 alone,
// variance v / m; the turns do not mix in, since each grid is centred.
TEST(ErrorBudget, IcpOnACornerOfThreePlanesHasTheClosedFormCovariance) {
  std::vector<Vec3> points, normals;
  const double v = 1e-4;
  int m = 0;
  for (int axis = 0; axis < 3; ++axis)
    for (int i = -5; i <= 5; ++i)
      for (int j = -5; j <= 5; ++j) {
        Vec3 p = Vec3::Zero();
        p[(axis + 1) % 3] = 10.0 * i;
        p[(axis + 2) % 3] = 10.0 * j;
        points.push_back(p);
        normals.push_back(Vec3::Unit(axis));
        m += axis == 0;
      }
  const std::vector<double> variances(points.size(), v);
  const detail::TwistCovariance c = detail::icpCovariance(points, normals, variances);
  for (int axis = 3; axis < 6; ++axis) EXPECT_NEAR(c(axis, axis), v / m, 1e-6 * v / m);
}

// Views straight down at (x, 50) for each of `xs`, the first the reference, the others
// placed by a robot of accuracy 0.1 mm.
Plan robotPlacedViews(const Scanner& scanner, const std::vector<double>& xs) {
  Plan plan;
  plan.scanner = scanner;
  Registration registration;
  registration.method = RegistrationMode::Robot;
  registration.robot_accuracy = 0.1;
  for (std::size_t k = 0; k < xs.size(); ++k) {
    plan.views.push_back(downAt(static_cast<int>(k) + 1, scanner, xs[k], 50));
    ViewRegistration placed;
    placed.method = k == 0 ? RegistrationMethod::Reference : RegistrationMethod::Robot;
    registration.views.push_back(placed);
  }
  plan.registration = registration;
  return plan;
}

// The 200 x 100 mm top of a plate (flatness 0.2), seen straight on by a scanner of a
// 100 x 100 mm field, noise 0.01 mm and a flatness error of 0.02 mm: by `views` views spread
// along x, the first the reference and the others placed by a robot of accuracy 0.1 mm.
// `field`: the fields' side, mm (at 250 each view sees the whole top).
Capability twoHalvesCase(const test::TempDir& dir, int views, double field = 100) {
  BRepTools::Write(BRepPrimAPI_MakeBox(200, 100, 10).Shape(), dir.file("plate.brep").c_str());
  const Part part = importPart(dir.file("plate.brep"));
  Spec spec = defaultSpec();
  spec.scanner.fov_width = spec.scanner.fov_height = field;
  spec.scanner.point_spacing = 2;
  spec.scanner.flatness_error = 0.02;
  std::vector<double> xs;
  for (int k = 0; k < views; ++k) xs.push_back(views == 1 || field > 200 ? 100 : 45 + 110 * k);
  const Plan plan = robotPlacedViews(spec.scanner, xs);
  return capabilities(part, resolveSpec(part, spec), plan, {topFlatness(part, 0.2)}).front();
}

// The registration's share of U. Two views, each on one half of the face, the second
// placed by the robot: their offset along the normal, sigma s = 0.1 / 2.7955 (95% of the
// robot's position errors within its accuracy), shows as a step. A least-squares plane
// leaves residuals spanning 0.81 of the step over four sample columns a half (as the
// surface sampler lays them on this face, 25 mm apart) and the whole step over a continuous
// surface, so the flatness' U from the registration is 0.81 to 1 times 1.96 s. One view,
// moved as a whole, leaves the form as it is: none. The scanner's
// flatness error (0.02) is a uniform error within it: U = 2 x 0.02 / sqrt 3, and the whole
// U is never below it.
TEST(Capability, ARegistrationStepBetweenTwoViewsShowsInTheFlatnessAndOneViewLeavesIt) {
  test::TempDir dir;
  const Capability two = twoHalvesCase(dir, 2);
  const Capability one = twoHalvesCase(dir, 1);
  const double s = 0.1 / 2.7955;
  RecordProperty("registration_u_two_views", std::to_string(two.budget.registration));
  EXPECT_NEAR(two.covered, 1, 0.02);
  EXPECT_GT(two.budget.registration, 0.81 * 1.96 * s * 0.9);  // the draws' own spread: 10%
  EXPECT_LT(two.budget.registration, 1.96 * s * 1.1);
  EXPECT_NEAR(one.budget.registration, 0, 1e-9);
  EXPECT_NEAR(two.budget.scanner, 2 * 0.02 / std::sqrt(3.0), 1e-12);
  EXPECT_GE(one.uncertainty, 0.02);
  EXPECT_NEAR(two.uncertainty,
              std::hypot(two.budget.noise, two.budget.registration, two.budget.scanner), 1e-12);
  EXPECT_LT(two.ratio, one.ratio);
}

// Two views that both see the whole top, the second placed by the robot: their points lie
// in two layers its offset along the normal apart, and the flatness spans both. The fitted
// plane lies between them, so U from the registration is 1.96 s, the 95% of |offset|,
// though each sample's mean position lies on one plane.
TEST(Capability, TwoOverlappingViewsLeaveTheirOffsetInTheFlatness) {
  test::TempDir dir;
  const Capability both = twoHalvesCase(dir, 2, 250);
  // The robot's sigma per axis: its accuracy, 0.1 mm, is the radius holding 95 % of a 3-D
  // Gaussian's draws, 2.7955 sigmas (the chi distribution with 3 degrees of freedom).
  const double s = 0.1 / 2.7955;
  RecordProperty("registration_u_overlapping", std::to_string(both.budget.registration));
  EXPECT_NEAR(both.covered, 1, 0.02);
  EXPECT_NEAR(both.budget.registration, 1.96 * s, 0.1 * 1.96 * s);  // the draws' own spread
}

// The generic head with a field of 250 mm (a view sees all of a 200 x 100 mm plate) and
// points 2 mm apart; `draws` Monte Carlo draws.
Spec wholePlateSpec(int draws) {
  Spec spec = defaultSpec();
  spec.scanner.fov_width = spec.scanner.fov_height = 250;
  spec.scanner.point_spacing = 2;
  spec.planner.capability.draws = draws;
  return spec;
}

// A 200 x 100 x 10 mm plate with a 3 mm deep slot across its middle 100 mm: the step's
// height from the slot's floor (one face) to the top (two faces of one plane, one each
// side), seen straight down by `views` views at one place, which see all of both (field
// 250, point spacing 2, noise 0.01), the first the reference and the others placed by a
// robot of accuracy 0.1 mm. Without `floor`, the height is linked to the top alone.
Capability stepCase(const test::TempDir& dir, int views, bool floor = true) {
  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(200, 100, 10).Shape();
  const TopoDS_Shape slot = BRepPrimAPI_MakeBox(gp_Pnt(50, -1, 7), gp_Pnt(150, 101, 11)).Shape();
  BRepTools::Write(BRepAlgoAPI_Cut(plate, slot).Shape(), dir.file("step.brep").c_str());
  const Part part = importPart(dir.file("step.brep"));
  Spec spec = wholePlateSpec(4000);  // the 95th percentile within about 2 %
  spec.scanner.noise_sigma = 0.01;
  Characteristic step{1, "linear_distance", true, 3, 2.9, 3.1, {}, {}};
  for (const Face& f : part.faces)
    if (f.type == SurfaceType::Plane && f.bounds.size().z() < 1e-6 &&
        (f.bounds.min.z() > 9.99 || (floor && std::abs(f.bounds.min.z() - 7) < 1e-6)))
      step.faces.push_back(f.id);
  EXPECT_EQ(step.faces.size(), floor ? 3u : 2u);
  const Plan plan = robotPlacedViews(spec.scanner, std::vector<double>(views, 100));
  return capabilities(part, resolveSpec(part, spec), plan, {step}).front();
}

// The step is two features, each fitted whole, as the inspection fits them: the noise
// moves each by sigma / sqrt(its points), 2500 on the top's two faces together and 2500 on
// the floor, and the height by their difference, so its U is 1.96 x 0.01 x sqrt(2 / 2500)
// = 0.00055 mm (the floor's points 3 mm deeper are 1.5 % noisier). Face by face, the top's
// two halves would each count with 1250 points. Two views at one place see every patch
// alike, so the second view's registration error moves the top and the floor alike, and
// the height keeps: none, where adding the features' offsets along their normals (right
// for a thickness, whose sides face away from each other) gives the whole offset, 1.96 x
// 0.1 / 2.7955.
TEST(Capability, AStepsHeightIsTwoFeaturesApartWhateverTheirFaces) {
  test::TempDir dir;
  const Capability one = stepCase(dir, 1), two = stepCase(dir, 2);
  const double analytic = 1.96 * 0.01 * std::sqrt(2.0 / 2500);
  RecordProperty("noise_u", std::to_string(one.budget.noise));
  RecordProperty("registration_u_two_views", std::to_string(two.budget.registration));
  EXPECT_NEAR(one.points, 5000, 0.03 * 5000);
  EXPECT_NEAR(one.budget.noise, analytic, 0.1 * analytic);
  EXPECT_NEAR(one.budget.registration, 0, 1e-12);
  EXPECT_LT(two.budget.registration, 0.01 * 1.96 * 0.1 / 2.7955);
}

// `c` on `part`, seen by four views tilted 50° from four sides into (100, 50, 20), the
// reference far off, placed by a robot of 0.01 mm: capable, and its inspection (200 runs)
// finds `designed` and a U + |bias| the model's U agrees with within 20 %.
void expectFourSidesAsInspected(const Part& part, const Characteristic& c, double designed) {
  const ResolvedSpec spec = resolveSpec(part, defaultSpec());
  Plan plan = robotPlacedViews(spec.spec.scanner, std::vector<double>(5, 2000));
  plan.part_faces = part.faces.size();
  plan.characteristics = {c};
  plan.registration->robot_accuracy = 0.01;
  for (std::size_t v = 1; v < 5; ++v)
    plan.views[v] = test::tiltedView(plan.views[v].id, {100, 50, 20}, plan.scanner.standoff,
                                     static_cast<double>(v) * M_PI / 2);
  const Capability k = capabilities(part, spec, plan, {c}).front();
  EXPECT_EQ(k.verdict, Verdict::Capable) << toString(k.reason);
  InspectionOptions options;
  options.runs = 200;
  const InspectedCharacteristic inspected =
      inspectPlan(part, spec, plan, options).characteristics[0];
  ASSERT_TRUE(inspected.evaluated) << inspected.not_evaluated;
  testing::Test::RecordProperty("predicted_u_inspected_u_bias",
                                std::to_string(k.uncertainty) + " " +
                                    std::to_string(inspected.uncertainty) + " " +
                                    std::to_string(inspected.bias));
  EXPECT_NEAR(inspected.true_value, designed, 1e-3);
  EXPECT_NEAR(k.uncertainty / (inspected.uncertainty + std::abs(inspected.bias)), 1, 0.2);
}

// A Ø30 spherical pocket 10 mm deep in a plate's top (its centre 5 mm above it), seen from
// four sides: its spherical diameter is capable, the inspection fits a sphere to its faces
// and finds the designed 30 mm, and the model's U agrees with the inspection's.
TEST(Capability, ASphericalDiameterIsAsUncertainAsItsInspectionFindsIt) {
  test::TempDir dir;
  const TopoDS_Shape plate = BRepPrimAPI_MakeBox(200, 100, 20).Shape();
  const TopoDS_Shape ball = BRepPrimAPI_MakeSphere(gp_Pnt(100, 50, 25), 15).Shape();
  BRepTools::Write(BRepAlgoAPI_Cut(plate, ball).Shape(), dir.file("pocket.brep").c_str());
  const Part part = importPart(dir.file("pocket.brep"));
  std::vector<int> pocket;
  for (const Face& f : part.faces)
    if (f.type == SurfaceType::Sphere) pocket.push_back(f.id);
  ASSERT_FALSE(pocket.empty());
  expectFourSidesAsInspected(part, {1, "spherical_diameter", true, 30, 29.9, 30.1, {}, pocket}, 30);
}

// A 200 x 100 x 20 mm plate with a Ø30 through hole at (100, 50) whose top edge is
// rounded to R3 (a torus), seen from four sides: the fillet's radius is capable, the
// inspection finds the designed 3 mm from the torus' offset fitted to its points, and the
// model's U agrees with the inspection's.
TEST(Capability, AFilletsRadiusIsAsUncertainAsItsInspectionFindsIt) {
  test::TempDir dir;
  const TopoDS_Shape holed =
      BRepAlgoAPI_Cut(
          BRepPrimAPI_MakeBox(200, 100, 20).Shape(),
          BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(100, 50, -1), gp_Dir(0, 0, 1)), 15, 22).Shape())
          .Shape();
  BRepFilletAPI_MakeFillet rounded(holed);
  for (TopExp_Explorer e(holed, TopAbs_EDGE); e.More(); e.Next()) {
    Bnd_Box box;
    BRepBndLib::Add(e.Current(), box);
    double x0, y0, z0, x1, y1, z1;
    box.Get(x0, y0, z0, x1, y1, z1);
    if (z0 > 19.9 && x1 - x0 < 31 && x1 - x0 > 29) rounded.Add(3, TopoDS::Edge(e.Current()));
  }
  ASSERT_GT(rounded.NbContours(), 0);
  BRepTools::Write(rounded.Shape(), dir.file("fillet.brep").c_str());
  const Part part = importPart(dir.file("fillet.brep"));
  std::vector<int> fillet;
  for (const Face& f : part.faces)
    if (f.type == SurfaceType::Torus) fillet.push_back(f.id);
  ASSERT_FALSE(fillet.empty());
  expectFourSidesAsInspected(part, {1, "radius", true, 3, 2.9, 3.1, {}, fillet}, 3);
}

// A distance the file links to faces of one feature alone (NIST FTC 06 and 07 have six,
// each on one face) has no second feature to be measured from, and the inspection cannot
// evaluate it ("its faces are not two features"): it is not linked, and not capable,
// however well its faces are measured; the step's height from its two features is capable.
TEST(Capability, ADistanceLinkedToOneFeatureIsNotLinked) {
  test::TempDir dir;
  const Capability top = stepCase(dir, 1, false), step = stepCase(dir, 1);
  EXPECT_EQ(top.verdict, Verdict::NotCapable);
  EXPECT_EQ(top.reason, Shortfall::NotLinked);
  EXPECT_GT(top.covered, 0.99);
  EXPECT_EQ(step.verdict, Verdict::Capable) << toString(step.reason);
}

// A plate's top (flatness 0.2) seen whole by two views: the first placed by a robot of
// accuracy `robot` mm, the second registered to it by four markers shared in a 2000 mm
// square around the plate (marker sigma 0.02 mm); the reference view sees nothing of the
// plate. Both views move by the robot's error; only the markers' link moves one against
// the other.
Capability chainedLayersCase(const test::TempDir& dir, double robot) {
  BRepTools::Write(BRepPrimAPI_MakeBox(200, 100, 10).Shape(), dir.file("plate.brep").c_str());
  const Part part = importPart(dir.file("plate.brep"));
  Spec spec = wholePlateSpec(2000);  // the 95th percentile within about 2 %
  spec.registration.marker_sigma = 0.02;
  Plan plan;
  plan.scanner = spec.scanner;
  for (const Vec3& d : {Vec3(-1, -1, 0), Vec3(1, -1, 0), Vec3(1, 1, 0), Vec3(-1, 1, 0)})
    plan.markers.push_back({Vec3(100, 50, 0) + 1000 * d, Vec3::UnitZ()});
  Registration registration;
  registration.method = RegistrationMode::Markers;
  registration.robot_accuracy = robot;
  const RegistrationMethod methods[] = {RegistrationMethod::Reference, RegistrationMethod::Robot,
                                        RegistrationMethod::Markers};
  for (int k = 0; k < 3; ++k) {
    plan.views.push_back(downAt(k + 1, spec.scanner, k == 0 ? 2000 : 100, 50));
    ViewRegistration r;
    r.method = methods[k];
    r.to = k == 2 ? 2 : 1;
    r.markers = {0, 1, 2, 3};
    registration.views.push_back(r);
  }
  plan.registration = registration;
  return capabilities(part, resolveSpec(part, spec), plan, {topFlatness(part, 0.2)}).front();
}

// The second view's layer lies off the first's by the markers' link alone: the rigid fit
// of four markers, each centre noisy in both views (sigma 0.02 sqrt 2), moves the plate's
// top by sigma 0.02 sqrt 2 / 2 along its normal (the square's tilt adds under 1 %), so U
// from the registration is 1.96 times that. The robot's error moves both views alike: ten
// times the robot's error leaves U as it is.
TEST(Capability, ViewsRegisteredThroughTheSameLinkMoveTogetherAndLeaveOnlyTheirOwnLinksOffset) {
  test::TempDir dir;
  const Capability precise = chainedLayersCase(dir, 0.1);
  const Capability rough = chainedLayersCase(dir, 1.0);
  const double link = 0.02 * std::sqrt(2.0) / 2;
  RecordProperty("registration_u", std::to_string(precise.budget.registration));
  EXPECT_NEAR(precise.covered, 1, 0.02);
  EXPECT_NEAR(precise.budget.registration, 1.96 * link, 0.1 * 1.96 * link);  // the draws' spread
  EXPECT_NEAR(rough.budget.registration, precise.budget.registration, 1e-9);
}

// The parallelism of a step's lower top (x 100 to 300, z 10) to its upper top, datum A (x 0
// to 100, z 20), each seen straight down in a 100 mm field: the datum by the reference view,
// the lower top's halves by two views the robot places (accuracy 0.1 mm, sigma s per axis).
// The zone's planes keep the datum's orientation and are free in place, so it spans the two
// halves' offsets apart, |d2 - d3|, of sigma s sqrt 2: U = 1.96 s sqrt 2. (A fit of the
// lower top turns with the step between its halves; its turn and the halves' residuals
// about it, added, come to over twice that.)
TEST(Capability, AParallelismSpansTheLayersOfItsFaceInTheDatumsFrame) {
  test::TempDir dir;
  const TopoDS_Shape base = BRepPrimAPI_MakeBox(300, 100, 10).Shape();
  const TopoDS_Shape block = BRepPrimAPI_MakeBox(gp_Pnt(0, 0, 10), 100, 100, 10).Shape();
  BRepTools::Write(BRepAlgoAPI_Fuse(base, block).Shape(), dir.file("step.brep").c_str());
  Part part = importPart(dir.file("step.brep"));
  Characteristic parallelism;
  parallelism.id = 1;
  parallelism.kind = "parallelism";
  parallelism.value = parallelism.upper = 0.2;
  parallelism.datums = {"A"};
  for (const Face& f : part.faces) {
    if (f.type != SurfaceType::Plane || f.bounds.max.z() - f.bounds.min.z() > 0.01) continue;
    if (f.bounds.min.z() > 19.99) part.gdt.datums = {{"A", {f.id}}};
    if (std::abs(f.bounds.min.z() - 10) < 0.01 && f.bounds.min.x() > 99.99)
      parallelism.faces = {f.id};
  }
  ASSERT_EQ(part.gdt.datums.size(), 1u);
  ASSERT_EQ(parallelism.faces.size(), 1u);
  Spec spec = defaultSpec();
  spec.scanner.fov_width = spec.scanner.fov_height = 100;
  spec.scanner.point_spacing = 2;
  const Plan plan = robotPlacedViews(spec.scanner, {50, 150, 250});
  const Capability k = capabilities(part, resolveSpec(part, spec), plan, {parallelism}).front();
  const double s = 0.1 / 2.7955;  // as in TwoOverlappingViewsLeaveTheirOffsetInTheFlatness
  RecordProperty("registration_u", std::to_string(k.budget.registration));
  EXPECT_NEAR(k.covered, 1, 0.02);
  EXPECT_NEAR(k.budget.registration, 1.96 * s * std::sqrt(2.0), 0.1 * 1.96 * s * std::sqrt(2.0));
}

// View `view` of `plan` aimed 50° off the vertical at `target`, from +x, at the scanner's
// standoff.
void tiltInto(Plan& plan, std::size_t view, const Vec3& target) {
  plan.views[view] = test::tiltedView(plan.views[view].id, target, plan.scanner.standoff, 0);
}

// The normal equations of frames their datums leave partly free, each datum row weighing 1
// (a twist: turn, then shift). `motion` the frame's true motion; the solution of the
// equations for the rows' displacements under it.
detail::Twist heldSolution(const std::vector<std::pair<Vec3, Vec3>>& rows,
                           const detail::Twist& motion) {
  detail::TwistCovariance normal = detail::TwistCovariance::Zero();
  detail::Twist pull = detail::Twist::Zero();
  for (const auto& [at, along] : rows) {
    const Eigen::Matrix<double, 1, 6> row = detail::alongNormal(at, along);
    normal += row.transpose() * row;
    pull += row.transpose() * (row * motion)(0);
  }
  return detail::heldInverse(normal) * pull;
}

// Two short parallel axes 200 mm apart, each held by its two ends 1.9 mm apart across it,
// leave the frame free to slide along them only: the solution is the true motion with no
// slide along them, where that free direction, whose turn is rounding's worth, would
// otherwise turn the frame by the solution's turn over it. A plane at z = 5 off the origin
// leaves a slide along it and a turn about its normal free: none of either, its lift and
// tilts found exactly.
TEST(ErrorBudget, DirectionsTheDatumsLeaveFreeNeitherTurnNorSlide) {
  detail::Twist motion;
  motion << 1e-4, -2e-4, 3e-4, 0.01, -0.02, 0.03;
  const Eigen::Matrix3d r = Eigen::AngleAxisd(0.3, Vec3(1, 2, 3).normalized()).toRotationMatrix();
  std::vector<std::pair<Vec3, Vec3>> axes;  // along r z
  for (const double x : {100.0, 300.0})
    for (const double z : {0.0, 1.9})
      for (const Vec3& e : {Vec3(Vec3::UnitX()), Vec3(Vec3::UnitY())})
        axes.push_back({r * Vec3(x, 40, z), r * e});
  detail::Twist expected = motion;
  const Vec3 along = r * Vec3::UnitZ();
  expected.tail<3>() -= along.dot(motion.tail<3>()) * along;
  EXPECT_LT((heldSolution(axes, motion) - expected).norm(), 1e-9);
  std::vector<std::pair<Vec3, Vec3>> plane;
  for (const double x : {100.0, 200.0})
    for (const double y : {50.0, 150.0}) plane.push_back({Vec3(x, y, 5), Vec3::UnitZ()});
  const detail::Twist found = heldSolution(plane, motion);
  EXPECT_NEAR(found[0], motion[0], 1e-12);
  EXPECT_NEAR(found[1], motion[1], 1e-12);
  EXPECT_NEAR(found[5], motion[5], 1e-9);
  EXPECT_NEAR(found[2], 0, 1e-12);
  EXPECT_NEAR(found[3], 0, 1e-12);
  EXPECT_NEAR(found[4], 0, 1e-12);
}

// The hole plate's bore (Ø20, 20 deep) and its top, datum A, seen by one view tilted 50°
// into the bore, which a robot of accuracy `robot` mm places; the reference view sees
// nothing of the plate. The bore's perpendicularity to A.
Capability tiltedBoreCase(const test::TempDir& dir, double robot) {
  const test::HolePlate p = test::holePlate(dir);
  const Characteristic perpendicularity{1, "perpendicularity", false, 0.05, 0, 0.05, {"A"}, p.hole};
  Spec spec = defaultSpec();
  spec.planner.capability.draws = 2000;
  Plan plan = robotPlacedViews(spec.scanner, {2000, 100});
  tiltInto(plan, 1, {100, 50, 20});
  plan.registration->robot_accuracy = robot;
  return capabilities(p.part, resolveSpec(p.part, spec), plan, {perpendicularity}).front();
}

// The robot's error moves the bore and its datum together, and a motion of the whole turns
// no axis against its datum: the registration leaves the perpendicularity as it is, U 0,
// however far the robot is off. The noise's share does not depend on
// the robot. (Taken as the bore's wall moved along its normals, the robot's shift across the axis,
// which the top does not hold, showed as a tilt.)
TEST(Capability, ARigidMotionOfABoreAndItsDatumLeavesItsPerpendicularity) {
  test::TempDir dir;
  const Capability precise = tiltedBoreCase(dir, 0.01), rough = tiltedBoreCase(dir, 1);
  RecordProperty("noise_u", std::to_string(rough.budget.noise));
  RecordProperty("registration_u", std::to_string(rough.budget.registration));
  EXPECT_GT(rough.points, 1000);
  EXPECT_GT(rough.budget.noise, 0);
  EXPECT_NEAR(rough.budget.registration, 0, 1e-6);
  EXPECT_NEAR(rough.budget.noise, precise.budget.noise, 1e-12);
}

// The two-bore plate's second bore's position to A and B, each bore seen by a view tilted
// 50° into it, which a robot of accuracy 0.1 mm places (sigma s = 0.1 / 2.7955 per axis;
// the reference view sees nothing of the plate). The first bore's view slides the frame
// by its shift and turns it not (a plane and an axis leave the turn free), the second's
// slides the second bore, so the bore lies off its axis by the two shifts apart across it:
// two normal components of sigma s sqrt 2, whose length 95 % of the draws stay under is
// 2.4477 s sqrt 2 (the Rayleigh distribution), and the zone twice that. The top, seen by
// both views, also tilts the frame by their shifts apart along z over 500 mm; with it the
// model comes to 0.2453 against the analytic 0.2477.
TEST(Capability, ABoresPositionToAnotherBoreSpansBothViewsShiftsAndNoTurn) {
  test::TempDir dir;
  const test::TwoBorePlate p = test::twoBorePlate(dir);
  Spec spec = defaultSpec();
  spec.planner.capability.draws = 4000;  // the 95th percentile within about 2 %
  Plan plan = robotPlacedViews(spec.scanner, {2000, 100, 600});
  tiltInto(plan, 1, {100, 50, 20});
  tiltInto(plan, 2, {600, 50, 20});
  const Capability k = capabilities(p.part, resolveSpec(p.part, spec), plan, {p.position}).front();
  const double s = 0.1 / 2.7955, analytic = 2 * 2.4477 * s * std::sqrt(2.0);
  RecordProperty("registration_u", std::to_string(k.budget.registration));
  EXPECT_NEAR(k.budget.registration, analytic, 0.05 * analytic);
}

// A diameter on the two-bore plate's pattern of two Ø20 bores (2X) holds each bore within
// its limits, so each bore's own wall must be measured. With four views tilted 50° into
// each bore from four sides (placed by a robot of 0.01 mm), it is capable, and the virtual
// inspection evaluates it:
// its U, each bore's diameter fitted to its own points, the largest, agrees with the
// model's within 20 % (200 runs); the second bore made 0.1 mm larger is found so, within
// that U. With the views into the first bore alone, half the pattern unmeasured, it is not
// capable, and the inspection names the bore it cannot fit.
TEST(Capability, APatternsDiameterNeedsEachOfItsCylindersMeasured) {
  test::TempDir dir;
  const test::TwoBorePlate p = test::twoBorePlate(dir);
  std::vector<int> both = p.first;
  both.insert(both.end(), p.second.begin(), p.second.end());
  std::sort(both.begin(), both.end());
  const Characteristic diameter{2, "diameter", true, 20, 19.9, 20.1, {}, both};
  const ResolvedSpec spec = resolveSpec(p.part, defaultSpec());
  // The reference far off; then four views tilted into each bore, 90° apart about it.
  Plan plan = robotPlacedViews(spec.spec.scanner, std::vector<double>(9, 2000));
  plan.part_faces = p.part.faces.size();
  plan.characteristics = {diameter};
  plan.registration->robot_accuracy = 0.01;
  for (std::size_t v = 1; v < 9; ++v)
    plan.views[v] = test::tiltedView(plan.views[v].id, {v < 5 ? 100.0 : 600.0, 50, 20},
                                     plan.scanner.standoff, static_cast<double>(v % 4) * M_PI / 2);
  const Capability k = capabilities(p.part, spec, plan, {diameter}).front();
  EXPECT_EQ(k.verdict, Verdict::Capable) << toString(k.reason);
  InspectionOptions options;
  options.runs = 200;
  const InspectedCharacteristic inspected =
      inspectPlan(p.part, spec, plan, options).characteristics[0];
  ASSERT_TRUE(inspected.evaluated) << inspected.not_evaluated;
  RecordProperty("predicted_u_inspected_u_bias", std::to_string(k.uncertainty) + " " +
                                                     std::to_string(inspected.uncertainty) + " " +
                                                     std::to_string(inspected.bias));
  EXPECT_NEAR(k.uncertainty / (inspected.uncertainty + std::abs(inspected.bias)), 1, 0.2);
  options.runs = 4;
  options.deviations = {{Deviation::Kind::Diameter, p.second, 0.1, Vec3::Zero()}};
  const InspectedCharacteristic larger =
      inspectPlan(p.part, spec, plan, options).characteristics[0];
  ASSERT_TRUE(larger.evaluated) << larger.not_evaluated;
  EXPECT_NEAR(larger.true_value, 20.1, 0.002);
  EXPECT_NEAR(larger.mean, 20.1, inspected.uncertainty + std::abs(inspected.bias));

  plan.views.resize(5);
  plan.registration->views.resize(5);
  const Capability half = capabilities(p.part, spec, plan, {diameter}).front();
  EXPECT_EQ(half.verdict, Verdict::NotCapable);
  EXPECT_TRUE(half.reason == Shortfall::Uncovered || half.reason == Shortfall::TooSparse)
      << toString(half.reason);
  options.deviations.clear();
  const InspectedCharacteristic unfit = inspectPlan(p.part, spec, plan, options).characteristics[0];
  EXPECT_FALSE(unfit.evaluated);
  EXPECT_NE(unfit.not_evaluated.find("a cylinder of its pattern is not measured enough to fit"),
            std::string::npos)
      << unfit.not_evaluated;
}

// The capability curve of two views, each on one half of a plate's top (flatness 0.3),
// without registration: the first view alone measures half the face, not capable; both
// measure it all, capable. Registered by four shared markers to a third view, the
// reference, the two halves are placed only once it is among the first views.
TEST(Capability, TheFirstViewsCountTheCharacteristicsTheyMakeCapable) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(200, 100, 10).Shape(), dir.file("plate.brep").c_str());
  const Part part = importPart(dir.file("plate.brep"));
  Spec spec = defaultSpec();
  spec.scanner.fov_width = spec.scanner.fov_height = 100;
  Plan plan;
  plan.scanner = spec.scanner;
  for (int k = 0; k < 2; ++k) plan.views.push_back(downAt(k + 1, spec.scanner, 45 + 110 * k, 50));
  const Characteristic flatness = topFlatness(part, 0.3);
  const ResolvedSpec resolved = resolveSpec(part, spec);
  const CapabilityJudgement apart = judgeCapability(part, resolved, plan, {flatness}, 2);
  ASSERT_EQ(apart.capabilities.front().verdict, Verdict::Capable);
  const std::vector<CapableCount>& curve = apart.by_views;
  ASSERT_EQ(curve.size(), 2u);
  EXPECT_EQ(curve[0].views, 1u);
  EXPECT_EQ(curve[0].capable, 0u);
  EXPECT_EQ(curve[1].views, 2u);
  EXPECT_EQ(curve[1].capable, 1u);

  for (const Vec3& p : {Vec3(-50, -50, 0), Vec3(250, -50, 0), Vec3(250, 150, 0), Vec3(-50, 150, 0)})
    plan.markers.push_back({p, Vec3::UnitZ()});
  View reference = plan.views[0];
  reference.id = 3;
  plan.views.push_back(reference);
  Registration registration;
  registration.method = RegistrationMode::Markers;
  for (int k = 0; k < 3; ++k) {
    ViewRegistration r;
    r.method = k == 2 ? RegistrationMethod::Reference : RegistrationMethod::Markers;
    r.to = k == 2 ? 0 : 3;
    r.markers = {0, 1, 2, 3};
    registration.views.push_back(r);
  }
  plan.registration = registration;
  const CapabilityJudgement registered = judgeCapability(part, resolved, plan, {flatness}, 3);
  ASSERT_EQ(registered.capabilities.front().verdict, Verdict::Capable);
  const std::vector<CapableCount>& chained = registered.by_views;
  ASSERT_EQ(chained.size(), 3u);
  EXPECT_EQ(chained[1].views, 2u);
  EXPECT_EQ(chained[1].capable, 0u);  // both halves register through the third view
  EXPECT_EQ(chained[2].capable, 1u);
}

// A characteristic the import linked to no face is not "uncovered": it is "not linked".
TEST(Capability, ACharacteristicWithoutFacesIsNotLinked) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(100, 100, 10).Shape(), dir.file("plate.brep").c_str());
  const Part part = importPart(dir.file("plate.brep"));
  Plan plan;
  plan.scanner = defaultSpec().scanner;
  Characteristic straightness;
  straightness.id = 1;
  straightness.kind = "straightness";
  straightness.value = straightness.upper = 0.1;
  const Capability k =
      capabilities(part, resolveSpec(part, defaultSpec()), plan, {straightness}).front();
  EXPECT_EQ(k.verdict, Verdict::NotCapable);
  EXPECT_EQ(k.reason, Shortfall::NotLinked);
  EXPECT_EQ(toString(k.reason), "not_linked");
}

// FTC 11 stands on its datum A face (flatness 0.3): no view measures it, and the plan says
// which rest orientation turns it up; plan.json carries it; planning every rest
// orientation measures it.
TEST(Capability, TheFaceThePartStandsOnNamesTheRestThatReachesIt) {
  const Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  const Plan plan = planViews(part, defaultSpec(), PlanningOptions{.registration = false});
  ASSERT_EQ(plan.characteristics.size(), plan.capabilities.size());
  const auto flatness = std::find_if(plan.characteristics.begin(), plan.characteristics.end(),
                                     [](const Characteristic& c) { return c.kind == "flatness"; });
  ASSERT_NE(flatness, plan.characteristics.end());
  const Capability& k = plan.capabilities[flatness - plan.characteristics.begin()];
  EXPECT_EQ(k.covered, 0);
  EXPECT_EQ(k.verdict, Verdict::NotCapable);
  EXPECT_EQ(k.reason, Shortfall::Uncovered);
  ASSERT_TRUE(k.rest);
  // That rest turns the face (outward normal -z as planned) up.
  const Face& face = part.faces[flatness->faces.front() - 1];
  EXPECT_LT(face.bounds.max.z() - face.bounds.min.z(), 1e-6);
  const RestOrientation rest = restOrientations(part)[*k.rest];
  EXPECT_GT((rest.part_to_world.linear() * -Vec3::UnitZ()).z(), 0.9);
  // plan.json: the characteristics with their capability, each sample with its own.
  const nlohmann::json json = planJson(plan);
  const nlohmann::json& entry = json["characteristics"][flatness - plan.characteristics.begin()];
  EXPECT_EQ(entry["capability"]["reason"], "uncovered");
  EXPECT_EQ(entry["capability"]["rest_orientation"], *k.rest + 1);
  test::TempDir dir;
  writePlan(plan, dir.file("plan.json"));
  const Plan back = readPlan(dir.file("plan.json"));
  ASSERT_EQ(back.capabilities.size(), plan.capabilities.size());
  EXPECT_EQ(back.capabilities[flatness - plan.characteristics.begin()].rest, k.rest);
  EXPECT_EQ(back.characteristics[0].faces, plan.characteristics[0].faces);
  // part: {rest: all} plans that orientation too, and the flatness is measured.
  Spec every_rest = defaultSpec();
  every_rest.rest_all = true;
  const Plan all = planViews(part, every_rest, PlanningOptions{.registration = false});
  const Capability& turned = all.capabilities[flatness - plan.characteristics.begin()];
  EXPECT_GT(all.orientations.size(), 1u);
  EXPECT_GT(turned.covered, 0.9);
  EXPECT_NE(turned.reason, Shortfall::Uncovered);
  for (std::size_t i = 0; i < plan.samples.size(); ++i) {
    if (plan.samples[i].sample.face != flatness->faces.front()) continue;
    const nlohmann::json& ids = json["samples"][i]["characteristics"];
    EXPECT_NE(std::find(ids.begin(), ids.end(), flatness->id), ids.end());
  }
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

std::size_t capable(const Plan& plan) {
  return static_cast<std::size_t>(
      std::count_if(plan.capabilities.begin(), plan.capabilities.end(),
                    [](const Capability& k) { return k.verdict == Verdict::Capable; }));
}

// FTC 11 planned for its whole shape leaves its runout and a diameter partly covered
// (marginal, too sparse); with planner.lift_capability the plan aims at every
// characteristic's faces too, and more of them are capable.
TEST(Capability, LiftingPlansAgainForTheCharacteristicsFaces) {
  const Part part = importPart(test::testData("nist_ftc_11_asme1_ap242-e1.stp"));
  Spec spec = defaultSpec();
  const Plan plain = planViews(part, spec, PlanningOptions{.registration = false});
  ASSERT_TRUE(std::any_of(plain.capabilities.begin(), plain.capabilities.end(),
                          [](const Capability& k) { return k.reason == Shortfall::TooSparse; }));
  spec.planner.lift_capability = true;
  const Plan lifted = planViews(part, spec, PlanningOptions{.registration = false});
  EXPECT_GT(capable(lifted), capable(plain));
  for (const Capability& k : lifted.capabilities)
    EXPECT_NE(k.reason, Shortfall::TooSparse) << "characteristic " << k.characteristic;
}

}  // namespace
}  // namespace scanplan
