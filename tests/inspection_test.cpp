// The virtual inspection: characteristics evaluated from points against hand computations,
// and declared deviations of a simulated part found again.

#include "hole_plate.h"
#include "planning/evaluation.h"
#include "planning/simulated_icp.h"
#include "support.h"

#include <scanplan/cad/import.h>
#include <scanplan/planning.h>
#include <scanplan/planning/capability.h>
#include <scanplan/planning/inspection.h>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepPrimAPI_MakeCylinder.hxx>
#include <BRepTools.hxx>
#include <gp_Ax2.hxx>

#include <gtest/gtest.h>
#include <tbb/global_control.h>

#include <cmath>
#include <functional>
#include <limits>
#include <memory>
#include <numbers>
#include <random>

namespace scanplan {
namespace {

using test::HolePlate;
using test::holePlate;

// A part's faces as designed, 1 mm apart: the points the evaluation judges (on the B-Rep's
// surfaces), kept in `all` for the nominal too (on the mesh, as the simulation samples it).
detail::FacePoints designed(const Part& part, std::vector<SurfacePoint>& all) {
  SimulationOptions options;
  options.working_plane = false;
  all = Simulator(part, defaultSpec().scanner, options).surfacePoints(1, 1);
  const detail::Nominal nominal(part, all);
  detail::FacePoints points;
  for (const SurfacePoint& s : all)
    points[s.face].push_back(nominal.onDesigned(s.face, s.position, s.normal).position);
  return points;
}

// The value of `c` evaluated from `points`, failing the test when it has none.
double valueOf(const Characteristic& c, const Part& part, const detail::Nominal& nominal,
               const detail::FacePoints& points) {
  const detail::Evaluation e = detail::evaluate(c, part.gdt, nominal, points);
  EXPECT_TRUE(e.value) << e.why_not;
  return e.value.value_or(-1);
}

void shift(detail::FacePoints& points, const std::vector<int>& faces, const Vec3& by) {
  for (int f : faces)
    for (Vec3& q : points[f]) q += by;
}

// The hole moved by 0.1 mm in x lies 0.1 from its designed axis: a position zone of 0.2.
// The datums B and C found 0.03 and 0.04 mm out along their normals (-x, -y) move the frame
// so that the hole, where it was, lies (0.03, 0.04) from its axis: a zone of 2 x 0.05.
// Everything moved together moves the frame with it: the zone stays 0.
TEST(Inspection, AHolesPositionFollowsItsShiftAndTheFrameOfThreeFittedPlanes) {
  test::TempDir dir;
  const HolePlate p = holePlate(dir);
  ASSERT_TRUE(p.top && p.side_x && p.side_y && !p.hole.empty());
  std::vector<SurfacePoint> all;
  const detail::FacePoints exact = designed(p.part, all);
  const detail::Nominal nominal(p.part, all);
  const Characteristic& position = p.characteristics[0];
  const auto value = [&](const detail::FacePoints& points) {
    return valueOf(position, p.part, nominal, points);
  };
  EXPECT_NEAR(value(exact), 0, 1e-3);

  detail::FacePoints moved = exact;
  shift(moved, p.hole, {0.1, 0, 0});
  EXPECT_NEAR(value(moved), 0.2, 2e-3);

  detail::FacePoints datums_out = exact;
  shift(datums_out, {p.side_x}, {-0.03, 0, 0});
  shift(datums_out, {p.side_y}, {0, -0.04, 0});
  const detail::Alignment frame =
      detail::datumAlignment({"A", "B", "C"}, p.part.gdt, nominal, datums_out);
  ASSERT_TRUE(frame.motion);
  EXPECT_NEAR(frame.motion->tail<3>().x(), 0.03, 1e-3);
  EXPECT_NEAR(frame.motion->tail<3>().y(), 0.04, 1e-3);
  EXPECT_NEAR(frame.motion->head<3>().norm(), 0, 1e-5);
  EXPECT_NEAR(value(datums_out), 2 * 0.05, 2e-3);

  detail::FacePoints together = exact;
  for (auto& [face, list] : together)
    for (Vec3& q : list) q += Vec3(0.3, -0.2, 0.1);
  EXPECT_NEAR(value(together), 0, 2e-3);
}

// The two-bore plate: a plane and an axis leave the frame free to turn about the axis.
// Found 0.05 mm off in y, the first bore moves the frame by 0.05 in y and does not turn
// it, so the second bore, where it was, lies 0.05 from its axis: a zone of 0.1, wherever
// the coordinates' origin lies. (Explained by the least twist in the part's coordinates,
// the same shift turns the frame about the origin by 4e-4 rad and puts the second bore
// 0.25 off: a zone of 0.5.)
TEST(Inspection, AFrameFreeToTurnAboutItsDatumAxisIsHeldUnturned) {
  test::TempDir dir;
  const test::TwoBorePlate p = test::twoBorePlate(dir);
  ASSERT_TRUE(p.top && !p.first.empty() && !p.second.empty());
  std::vector<SurfacePoint> all;
  detail::FacePoints points = designed(p.part, all);
  const detail::Nominal nominal(p.part, all);
  EXPECT_NEAR(valueOf(p.position, p.part, nominal, points), 0, 1e-3);
  shift(points, p.first, {0, 0.05, 0});
  const detail::Alignment frame = detail::datumAlignment({"A", "B"}, p.part.gdt, nominal, points);
  ASSERT_TRUE(frame.motion);
  EXPECT_NEAR(frame.motion->head<3>().norm(), 0, 1e-7);
  EXPECT_NEAR(valueOf(p.position, p.part, nominal, points), 2 * 0.05, 2e-3);
}

// The hole plate, as read or (`brep` false) as its mesh alone, whose hole's wall is its
// flat facets.
HolePlate plateAs(const test::TempDir& dir, bool brep) {
  HolePlate p = holePlate(dir);
  if (!brep) p.part.brep.reset();
  return p;
}

// The hole plate's faces as designed but its hole's wall (`rest`), and the wall sampled again
// at other points than the nominal's own, 0.5 mm apart (`wall`), on the wall as designed.
struct ResampledWall {
  explicit ResampledWall(bool brep) : p(plateAs(dir, brep)) {
    for (int f : p.hole) rest.erase(f);
    SimulationOptions options;
    options.working_plane = false;
    for (const SurfacePoint& s :
         Simulator(p.part, defaultSpec().scanner, options).surfacePoints(0.5, 7))
      if (std::count(p.hole.begin(), p.hole.end(), s.face))
        wall.push_back(nominal.onDesigned(s.face, s.position, s.normal));
  }
  // The profile of the wall (datums A, B, C: the plate's faces), its points each moved by
  // `move`.
  double profile(const std::function<Vec3(const SurfacePoint&)>& move) const {
    detail::FacePoints points = rest;
    for (const SurfacePoint& s : wall) points[s.face].push_back(s.position + move(s));
    const Characteristic c{4, "profile_of_surface", false, 0.2, 0, 0.2, {"A", "B", "C"}, p.hole};
    return valueOf(c, p.part, nominal, points);
  }

  test::TempDir dir;
  HolePlate p;
  std::vector<SurfacePoint> all;
  detail::FacePoints rest = designed(p.part, all);
  detail::Nominal nominal{p.part, all};
  std::vector<SurfacePoint> wall;
};

// Points measured where the part's surface is lie on it, wherever they fall: the hole's
// wall, sampled again at other points than the nominal's own, has a profile of 0 in the
// frame of the plate's faces, on the B-Rep's cylinder and on the mesh's flat facets alone
// (the distance to the nearest facet, not along the nearest sample's normal, which puts
// points across a facet's edge off the wall); moved out along its normals by 0.05 mm, a
// profile of 2 x 0.05.
TEST(Inspection, APointOnTheWallBetweenTheNominalsSamplesLiesOnTheWall) {
  for (const bool brep : {true, false}) {
    const ResampledWall w(brep);
    EXPECT_NEAR(w.profile([](const SurfacePoint&) { return Vec3::Zero(); }), 0, 1e-6) << brep;
    EXPECT_NEAR(w.profile([](const SurfacePoint& s) { return Vec3(0.05 * s.normal); }), 0.1, 2e-3)
        << brep;
  }
}

// A hole's wall slid 0.3 mm along its own axis lies on the same cylinder: its profile is 0,
// though the points near the plate's top are carried past the wall's edge (measured to the
// nearest point of the wall, they would lie 0.3 mm off, a profile of 0.6). Slid 0.3 mm across
// the axis, the wall's profile is twice that, 0.6. On the B-Rep's cylinder and on the mesh's
// facets alike.
TEST(Inspection, AWallSlidAlongItselfPastItsEdgeKeepsItsProfile) {
  for (const bool brep : {true, false}) {
    const ResampledWall w(brep);
    ASSERT_GT(std::count_if(w.wall.begin(), w.wall.end(),
                            [](const SurfacePoint& s) { return s.position.z() > 20 - 0.3; }),
              10);
    EXPECT_NEAR(w.profile([](const SurfacePoint&) { return Vec3(0, 0, 0.3); }), 0, 1e-6) << brep;
    EXPECT_NEAR(w.profile([](const SurfacePoint&) { return Vec3(0.3, 0, 0); }), 0.6, 0.01) << brep;
  }
}

// A view moved by a known registration error moves what it measures by that error: the
// datums measured by one view, the hole by another whose points are moved by a rigid motion
// (detail::displacement, to first order the motion a registration's error gives). A translation
// of 0.1 mm in x puts the hole's axis 0.1 off: a zone of 0.2. A turn of 0.0005 rad about z
// through the origin carries the axis at (100, 50) by 0.0005 x |(100, 50)| = 0.0559: a zone
// of 0.1118.
TEST(Inspection, AViewMovedByAKnownRegistrationErrorMovesTheHoleByIt) {
  test::TempDir dir;
  const HolePlate p = holePlate(dir);
  std::vector<SurfacePoint> all;
  const detail::FacePoints exact = designed(p.part, all);
  const detail::Nominal nominal(p.part, all);
  const auto position = [&](const detail::Twist& error) {
    detail::FacePoints merged;
    for (const auto& [face, list] : exact) {
      const bool hole_view = std::count(p.hole.begin(), p.hole.end(), face) > 0;
      for (const Vec3& q : list)
        merged[face].push_back(hole_view ? Vec3(q + detail::displacement(error, q)) : q);
    }
    return valueOf(p.characteristics[0], p.part, nominal, merged);
  };
  detail::Twist shift = detail::Twist::Zero();
  shift.tail<3>() = Vec3(0.1, 0, 0);
  EXPECT_NEAR(position(shift), 0.2, 2e-3);
  detail::Twist turn = detail::Twist::Zero();
  turn.head<3>() = Vec3(0, 0, 0.0005);
  EXPECT_NEAR(position(turn), 2 * 0.0005 * std::hypot(100.0, 50.0), 2e-3);
}

// A position on a pattern of two holes (2X) holds each hole's axis in its own zone: with
// one hole moved 0.1 mm and the other 0.04 mm, the pattern's value is the first's, 0.2.
TEST(Inspection, APatternsPositionIsItsWorstFeatures) {
  test::TempDir dir;
  Part part = test::boredPlate(dir, 200, {50, 150});
  std::vector<int> left, right;
  for (const Face& f : part.faces)
    if (f.type == SurfaceType::Cylinder)
      (f.bounds.center().x() < 100 ? left : right).push_back(f.id);
  ASSERT_FALSE(left.empty() || right.empty());
  std::vector<int> both = left;
  both.insert(both.end(), right.begin(), right.end());
  std::sort(both.begin(), both.end());
  const Characteristic position{1, "position", false, 0.5, 0, 0.5, {}, both};
  std::vector<SurfacePoint> all;
  detail::FacePoints points = designed(part, all);
  const detail::Nominal nominal(part, all);
  shift(points, left, {0.1, 0, 0});
  shift(points, right, {0, 0.04, 0});
  EXPECT_NEAR(valueOf(position, part, nominal, points), 0.2, 0.004);
}

// Straightness by its definition. The plate's top bowed by 0.05 mm along x (its longest
// extent, 200 mm) has line elements of that bow, the minimum zone of each strip of it. A
// 120 mm bore of Ø30 through a block, its axis bent in x by 0.04 mm to a parabola, has a
// derived median line of straightness 0.04: its sections' centres lie on the parabola, less
// each section's own spread along it (at most k 1.5² = 0.00001 mm). As designed, both 0.
TEST(Inspection, StraightnessOfABowedFaceAndABentBoreIsTheBow) {
  test::TempDir dir;
  const HolePlate p = holePlate(dir);
  std::vector<SurfacePoint> all;
  detail::FacePoints points = designed(p.part, all);
  const detail::Nominal nominal(p.part, all);
  const Characteristic flat{4, "straightness", false, 0.1, 0, 0.1, {}, {p.top}};
  EXPECT_NEAR(valueOf(flat, p.part, nominal, points), 0, 1e-6);
  for (Vec3& q : points[p.top]) q.z() += 0.05 * (1 - std::pow((q.x() - 100) / 100, 2));
  EXPECT_NEAR(valueOf(flat, p.part, nominal, points), 0.05, 0.001);

  const TopoDS_Shape block = BRepPrimAPI_MakeBox(gp_Pnt(-30, -30, 0), 60, 60, 120).Shape();
  const TopoDS_Shape drill =
      BRepPrimAPI_MakeCylinder(gp_Ax2(gp_Pnt(0, 0, -1), gp_Dir(0, 0, 1)), 15, 122).Shape();
  BRepTools::Write(BRepAlgoAPI_Cut(block, drill).Shape(), dir.file("bore.brep").c_str());
  const Part bored = importPart(dir.file("bore.brep"));
  std::vector<SurfacePoint> samples;
  designed(bored, samples);
  const detail::Nominal drilled(bored, samples);
  Characteristic axis{5, "straightness", false, 0.1, 0, 0.1, {}, {}};
  for (const Face& f : bored.faces)
    if (f.type == SurfaceType::Cylinder) axis.faces.push_back(f.id);
  ASSERT_EQ(axis.faces.size(), 1u);
  // Points on the exact bore, 1 mm apart (the mesh's chords would bring their own).
  detail::FacePoints bore;
  for (double z = 0.5; z < 120; z += 1)
    for (int i = 0; i < 94; ++i) {
      const double a = 2 * std::numbers::pi * (i + 0.5 * (static_cast<int>(z) % 2)) / 94;
      bore[axis.faces.front()].push_back({15 * std::cos(a), 15 * std::sin(a), z});
    }
  EXPECT_NEAR(valueOf(axis, bored, drilled, bore), 0, 1e-6);
  for (auto& [face, list] : bore)
    for (Vec3& q : list) q.x() += 0.04 * std::pow((q.z() - 60) / 60, 2);
  EXPECT_NEAR(valueOf(axis, bored, drilled, bore), 0.04, 0.002);
}

// A plan of four views tilted 50° about the hole, the first the reference and the others
// placed by a robot of 0.01 mm; the plate inspected as designed and with deviations
// declared: the top bowed by 0.05, the hole moved by 0.2 in x, its diameter 0.1 over.
Plan fourViews(const HolePlate& p) {
  Plan plan;
  plan.part_faces = p.part.faces.size();
  plan.scanner = defaultSpec().scanner;
  plan.characteristics = p.characteristics;
  Registration registration;
  registration.method = RegistrationMode::Robot;
  registration.robot_accuracy = 0.01;
  const Vec3 target(100, 50, p.part.face(p.top).bounds.max.z());
  for (int k = 0; k < 4; ++k) {
    plan.views.push_back(
        test::tiltedView(k + 1, target, plan.scanner.standoff, k * std::numbers::pi / 2));
    ViewRegistration placed;
    placed.method = k == 0 ? RegistrationMethod::Reference : RegistrationMethod::Robot;
    registration.views.push_back(placed);
  }
  plan.registration = registration;
  return plan;
}

// The plate (`thickness` mm) and its plan of four views, inspected with `options`.
struct FourViewInspection {
  explicit FourViewInspection(double thickness = 20) : p(holePlate(dir, thickness)) {}
  test::TempDir dir;
  HolePlate p;
  Plan plan = fourViews(p);
  ResolvedSpec spec = resolveSpec(p.part, defaultSpec());
  Inspection operator()(const InspectionOptions& options) const {
    return inspectPlan(p.part, spec, plan, options);
  }
};

// The plan's characteristics `inspected` against the capability model's prediction: each
// predicted U within 20 % of the inspection's U + |bias| (its U uncertain by about 5 % over
// 200 runs), both recorded. The predictions, into `predicted`.
void expectPredictedAsInspected(const FourViewInspection& inspect, const Inspection& inspected,
                                std::vector<Capability>& predicted) {
  predicted =
      capabilities(inspect.p.part, inspect.spec, inspect.plan, inspect.plan.characteristics);
  ASSERT_EQ(inspected.characteristics.size(), predicted.size());
  for (std::size_t i = 0; i < predicted.size(); ++i) {
    const InspectedCharacteristic& k = inspected.characteristics[i];
    ASSERT_TRUE(k.evaluated) << k.not_evaluated;
    const std::string id = std::to_string(i + 1);
    testing::Test::RecordProperty("predicted_u_" + id, std::to_string(predicted[i].uncertainty));
    testing::Test::RecordProperty("inspected_u_bias_" + id,
                                  std::to_string(k.uncertainty) + " " + std::to_string(k.bias));
    EXPECT_NEAR(predicted[i].uncertainty / (k.uncertainty + std::abs(k.bias)), 1, 0.2) << id;
  }
}

TEST(Inspection, DeclaredDeviationsAreFoundWithinTheirUncertainty) {
  const FourViewInspection inspect;
  const HolePlate& p = inspect.p;
  InspectionOptions options;
  options.runs = 4;
  const Inspection nominal = inspect(options);
  options.deviations = {{Deviation::Kind::Bow, {p.top}, 0.05, Vec3::Zero()},
                        {Deviation::Kind::Move, p.hole, 0, Vec3(0.2, 0, 0)},
                        {Deviation::Kind::Diameter, p.hole, 0.1, Vec3::Zero()}};
  const Inspection deviated = inspect(options);
  ASSERT_EQ(deviated.characteristics.size(), 3u);
  for (const InspectedCharacteristic& k : deviated.characteristics)
    ASSERT_TRUE(k.evaluated) << k.characteristic << ": " << k.not_evaluated;
  // The part's own values: the deviations as declared.
  EXPECT_NEAR(deviated.characteristics[0].true_value, 2 * 0.2, 0.01);
  EXPECT_NEAR(deviated.characteristics[1].true_value, 0.05, 0.002);
  EXPECT_NEAR(deviated.characteristics[2].true_value - nominal.characteristics[2].true_value, 0.1,
              0.002);
  // Measured: each value the deviations give found within U, counting as uncertain the bias
  // the inspection finds on the part as designed (a form's zone widened by the noise and
  // the views' registration steps); and each deviation shows, the value moving by more
  // than half of it from the part as designed.
  const double declared[] = {0.4, 0.05, nominal.characteristics[2].true_value + 0.1};
  const double change[] = {0.4, 0.05, 0.1};
  for (std::size_t i = 0; i < 3; ++i) {
    const InspectedCharacteristic &a = nominal.characteristics[i], &b = deviated.characteristics[i];
    RecordProperty("measured_" + std::to_string(i + 1), std::to_string(b.mean));
    RecordProperty("u_" + std::to_string(i + 1), std::to_string(b.uncertainty));
    RecordProperty("bias_as_designed_" + std::to_string(i + 1), std::to_string(a.bias));
    EXPECT_NEAR(b.mean, declared[i], b.uncertainty + std::abs(a.bias))
        << "characteristic " << i + 1;
    EXPECT_GT(b.mean - a.mean, change[i] / 2) << "characteristic " << i + 1;
  }
}

// The angle between the plate's top and its side x = 0 (90 degrees), the top's flatness
// and the top's profile (without datums: about the plane fitted to it), seen by the four
// views all in one frame without error.
const FourViewInspection& angleAndZones() {
  static const std::unique_ptr<FourViewInspection> inspect = [] {
    auto made = std::make_unique<FourViewInspection>();
    const HolePlate& p = made->p;
    const Characteristic angle{4,    "angular_location",
                               true, 90,
                               89.5, 90.5,
                               {},   {std::min(p.top, p.side_x), std::max(p.top, p.side_x)}};
    const Characteristic profile{5, "profile_of_surface", false, 0.1, 0, 0.1, {}, {p.top}};
    made->plan.characteristics = {angle, p.characteristics[1], profile};
    made->plan.registration->robot_accuracy = 1e-9;
    return made;
  }();
  return *inspect;
}

// angleAndZones() inspected over 200 runs, once.
const Inspection& angleAndZonesInspected() {
  static const Inspection inspected = [] {
    InspectionOptions options;
    options.runs = 200;
    return angleAndZones()(options);
  }();
  return inspected;
}

// angleAndZones(): the capability model's U from the points' noise against the virtual
// inspection's, which fits a plane to each face's simulated points in each of 200 runs (its
// U uncertain by about 5 %). At 90 degrees the measured angle folds back below 90, so the
// inspection's spread shows as U and bias together, compared with the model's U. The
// flatness and the profile are zones read from the points: their own noise widens them.
TEST(Inspection, AnAngleAndZonesOfThePointsAreAsUncertainAsTheCapabilityModelPredicts) {
  std::vector<Capability> predicted;
  expectPredictedAsInspected(angleAndZones(), angleAndZonesInspected(), predicted);
  ASSERT_EQ(predicted.size(), 3u);
  for (const Capability& k : predicted) EXPECT_NEAR(k.budget.registration, 0, 1e-6);
}

// Run until each U + |bias| is known within 15 % of itself: it stops at a check of the
// precision, well before the 200 runs of angleAndZonesInspected(), each U + |bias| within
// 15 % of itself as it states, and within what both inspections state (1.3 times: 99 %)
// of the 200 runs' own, drawn apart from it (another seed).
TEST(Inspection, RunUntilPreciseItsUAndBiasAreWithinTheirStatedPrecisionOfManyMoreRuns) {
  InspectionOptions options;
  options.precision = 0.15;
  options.runs = 1000;
  options.seed = 2;
  const Inspection until = angleAndZones()(options);
  const Inspection& reference = angleAndZonesInspected();
  RecordProperty("runs", until.runs);
  EXPECT_GE(until.runs, kLeastRuns);
  EXPECT_LT(until.runs, 200);
  EXPECT_EQ(until.runs % kPrecisionBatch, 0);
  EXPECT_TRUE(until.imprecise.empty());
  ASSERT_EQ(until.characteristics.size(), reference.characteristics.size());
  for (std::size_t i = 0; i < until.characteristics.size(); ++i) {
    const InspectedCharacteristic &k = until.characteristics[i], &r = reference.characteristics[i];
    ASSERT_TRUE(k.evaluated && r.evaluated);
    ASSERT_EQ(k.values.size(), static_cast<std::size_t>(until.runs));
    const double spread = k.uncertainty + std::abs(k.bias), many = r.uncertainty + std::abs(r.bias);
    RecordProperty("spread_precision_reference_" + std::to_string(i + 1),
                   std::to_string(spread) + " " + std::to_string(k.precision) + " " +
                       std::to_string(many) + " " + std::to_string(r.precision));
    EXPECT_LE(k.precision, options.precision * spread) << i;
    EXPECT_GT(k.precision, 0) << i;
    EXPECT_LE(std::abs(spread - many), 1.3 * std::hypot(k.precision, r.precision)) << i;
  }
}

// The error 95 % of the runs stay under, as the capability model defines U: of the 200
// runs of angleAndZonesInspected(), at least 190 errors (|measured - true|) are at most it
// and fewer than 190 are under it. Where the bias dominates (the flatness and the profile,
// zones read from noisy points) it lies under U + |bias|, which adds two standard
// deviations to the whole bias.
TEST(Inspection, ItsError95IsWhatNineteenRunsInTwentyStayUnder) {
  const Inspection& inspected = angleAndZonesInspected();
  for (const InspectedCharacteristic& k : inspected.characteristics) {
    ASSERT_TRUE(k.evaluated);
    ASSERT_EQ(k.values.size(), 200u);
    std::size_t within = 0, under = 0;
    for (double v : k.values) {
      within += std::abs(v - k.true_value) <= k.error_95;
      under += std::abs(v - k.true_value) < k.error_95;
    }
    RecordProperty("error_95_u_bias_" + std::to_string(k.characteristic),
                   std::to_string(k.error_95) + " " + std::to_string(k.uncertainty) + " " +
                       std::to_string(k.bias));
    EXPECT_GE(within, 190u) << k.characteristic;
    EXPECT_LT(under, 190u) << k.characteristic;
    if (std::abs(k.bias) > k.uncertainty) {
      EXPECT_LT(k.error_95, k.uncertainty + std::abs(k.bias)) << k.characteristic;
    }
  }
}

// Over many independent sets of n normal draws, the spread of U + |bias| (twice the
// standard deviation, and the mean's distance from the part's value) against what the
// bootstrap of one set states: its precision is twice that spread, within 15 % on average
// over 100 sets, with the part's value at the draws' mean (no bias) and 3 standard deviations
// away (a bias as large as U's).
TEST(Inspection, ItsPrecisionIsTwiceTheSpreadOfUAndBiasOverIndependentInspections) {
  std::mt19937_64 random(17);
  std::normal_distribution<double> normal(0, 1);
  const auto draws = [&](int n) {
    std::vector<double> values(n);
    for (double& x : values) x = normal(random);
    return values;
  };
  for (int n : {20, 60, 200})
    for (double true_value : {0.0, -3.0}) {
      double sum = 0, squares = 0;
      const int sets = 4000;
      for (int k = 0; k < sets; ++k) {
        const double spread = spreadOf(draws(n), true_value);
        sum += spread;
        squares += spread * spread;
      }
      const double spread_sd = std::sqrt(squares / sets - (sum / sets) * (sum / sets));
      double stated = 0;
      const int stated_sets = 100;
      for (int k = 0; k < stated_sets; ++k)
        stated += spreadPrecision(draws(n), true_value, 1000 + k) / stated_sets;
      const std::string label = std::to_string(n) + " at " + std::to_string(true_value);
      RecordProperty("stated_against_twice_spread_" + label,
                     std::to_string(stated) + " " + std::to_string(2 * spread_sd));
      EXPECT_NEAR(stated / (2 * spread_sd), 1, 0.15) << label;
    }
}

// The bore of Ø20 as designed, not as its mesh's facets cut inside it (sampled densely,
// they fit a diameter 0.048 mm short): the part's own diameter is the B-Rep's, and the
// views' points, laid on part of the bore each, fit it without a bias beyond the noise's
// share of U.
TEST(Inspection, ABoresDiameterIsTheDesignedCylindersNotItsFacets) {
  FourViewInspection inspect;
  inspect.plan.registration->robot_accuracy = 1e-9;
  InspectionOptions options;
  options.runs = 20;
  const Inspection inspected = inspect(options);
  const InspectedCharacteristic& d = inspected.characteristics[2];
  ASSERT_TRUE(d.evaluated) << d.not_evaluated;
  RecordProperty("true_mean_u", std::to_string(d.true_value) + " " + std::to_string(d.mean) + " " +
                                    std::to_string(d.uncertainty));
  EXPECT_NEAR(d.true_value, 20, 1e-6);
  EXPECT_NEAR(d.mean, 20, d.uncertainty / 2);
}

// The bore's axis as the inspection fits it, from the four views' points each on part of
// the bore, placed by the robot to 0.01 mm: its position to A, B and C and its
// perpendicularity to A. The capability model's U against the virtual inspection's (200
// runs, its U uncertain by about 5 %): each is the fitted axis' ends moved across it, not
// the bore's wall moved along its normals, which would count a shift of the axis as a tilt
// and miss the shift the views' arcs leave least determined. In a plate `thickness` mm
// thick; the position only where `position`; the inspection's points `spacing` mm apart
// (0: its default, a hundredth of the field).
void expectBoresAxisAsPredicted(double thickness, bool position, double spacing) {
  FourViewInspection inspect(thickness);
  const HolePlate& p = inspect.p;
  const Characteristic perpendicularity{4, "perpendicularity", false, 0.05, 0, 0.05, {"A"}, p.hole};
  inspect.plan.characteristics = {perpendicularity};
  if (position) inspect.plan.characteristics.push_back(p.characteristics[0]);
  InspectionOptions options;
  options.runs = 200;
  options.spacing = spacing;
  std::vector<Capability> predicted;
  expectPredictedAsInspected(inspect, inspect(options), predicted);
}

TEST(Inspection, ABoresAxisIsAsUncertainAsTheCapabilityModelPredicts) {
  expectBoresAxisAsPredicted(20, true, 0);
}

// Through a plate 2 mm thick the bore's band is shorter than half its radius: its
// position would be fitted about the designed axis' direction, but its perpendicularity,
// which is that direction, is fitted free, and is as uncertain as the model predicts (held,
// both took it as exact: U 0). The inspection lays its points 1 mm apart: at its default
// 2.25 mm, one or two rows of them fall on the band, and its U is four times that at 1 or
// 0.5 mm, where it agrees with the model's. The model spreads each sample's points along
// the axis over its square, within the band (its samples' centres alone gave 1.3 times the
// inspection's U). The views see too little of the plate's sides to fit datums B and C for
// the position.
TEST(Inspection, AShortBoresAxisTurnsForItsPerpendicularityAsTheModelPredicts) {
  expectBoresAxisAsPredicted(2, false, 1);
}

// A 200 x 100 x 20 mm plate with Ø20 bores at (60, 50) and (140, 50): datum A its top, B
// the first bore; the second bore's position to A and B (0.5). Four views look down at
// (60, 40) 50° off the vertical, from azimuths 225°, 195°, 255° and 165°: each pair of
// neighbours sees the top, the sides x = 0 and y = 0 and arcs of the bores in common, which
// hold every direction of an ICP link. The first fixes the frame; the second and third are
// registered by ICP to it, the fourth to the second.
struct IcpPlate {
  explicit IcpPlate() : part(test::boredPlate(dir, 200, {60, 140})) {
    for (const Face& f : part.faces) {
      if (f.type == SurfaceType::Cylinder)
        (f.bounds.max.x() < 100 ? first : second).push_back(f.id);
      if (f.type == SurfaceType::Plane && f.bounds.min.z() > 19.99) top = f.id;
    }
    part.gdt.datums = {{"A", {top}}, {"B", first}};
    plan.part_faces = part.faces.size();
    plan.scanner = defaultSpec().scanner;
    plan.characteristics = {{1, "position", false, 0.5, 0, 0.5, {"A", "B"}, second}};
    Registration registration;
    registration.method = RegistrationMode::Geometry;
    const double azimuth[] = {225, 195, 255, 165};
    const int to[] = {0, 1, 1, 2};
    for (int k = 0; k < 4; ++k) {
      plan.views.push_back(
          test::tiltedView(k + 1, Vec3(100, 50, 20), plan.scanner.standoff, radians(azimuth[k])));
      ViewRegistration r;
      r.method = k == 0 ? RegistrationMethod::Reference : RegistrationMethod::Icp;
      r.to = to[k];
      registration.views.push_back(r);
    }
    plan.registration = registration;
    spec = resolveSpec(part, defaultSpec());
  }
  test::TempDir dir;
  Part part;
  int top = 0;
  std::vector<int> first, second;
  Plan plan;
  ResolvedSpec spec;
};

// The plate's top and bores as designed, in the part frame: every eighth of points 1 mm
// apart in the window x 40..160, the moved view's overlap with a view that measures the
// whole plate.
struct IcpClouds {
  explicit IcpClouds(const IcpPlate& p) {
    SimulationOptions options;
    options.working_plane = false;
    all = Simulator(p.part, p.plan.scanner, options).surfacePoints(1, 1);
    nominal = std::make_unique<detail::Nominal>(p.part, all);
    std::size_t count = 0;
    for (const SurfacePoint& s : all) {
      if (s.face != p.top && std::count(p.first.begin(), p.first.end(), s.face) == 0 &&
          std::count(p.second.begin(), p.second.end(), s.face) == 0)
        continue;
      const SurfacePoint on = nominal->onDesigned(s.face, s.position, s.normal);
      if (on.position.x() > 40 && on.position.x() < 160 && ++count % 8 == 0) moved.push_back(on);
    }
  }
  std::vector<SurfacePoint> all;
  std::unique_ptr<detail::Nominal> nominal;
  std::vector<SurfacePoint> moved;
};

// The largest displacement `motion` gives a point of `points`.
double largestMove(const Pose& motion, const std::vector<SurfacePoint>& points) {
  double largest = 0;
  for (const SurfacePoint& p : points)
    largest = std::max(largest, (motion * p.position - p.position).norm());
  return largest;
}

// Without noise, ICP from the robot's start (3 mm and 2° off, the registration's default)
// brings the moved cloud back onto the surface it was measured on: the link is the identity.
TEST(SimulatedIcp, WithoutNoiseItBringsTheViewBackFromTheRobotsStart) {
  const IcpPlate p;
  const IcpClouds c(p);
  const detail::SimulatedIcp icp(*c.nominal, RegistrationOptions{}, p.part.linear_deflection);
  const detail::FixedSurface exact = [](const Vec3&, const Vec3&) {
    return detail::SurfaceOffset{};
  };
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    const std::optional<Pose> link = icp.link(c.moved, exact, 2, seed);
    ASSERT_TRUE(link);
    EXPECT_LT(largestMove(*link, c.moved), 1e-5) << seed;
  }
}

// The fixed surface's noise (0.01 mm along the normal at each correspondence) moves the
// link as least squares predicts to first order: the covariance sigma² (JᵀJ)⁻¹ of the
// point-to-plane rows J of the moved points. Over 300 links, each point's mean squared
// displacement within 15 % of that prediction (a variance from 300 draws is uncertain by
// about 8 %).
TEST(SimulatedIcp, ItsSpreadIsTheFirstOrderCovarianceOfItsNoise) {
  const IcpPlate p;
  const IcpClouds c(p);
  const detail::SimulatedIcp icp(*c.nominal, RegistrationOptions{}, p.part.linear_deflection);
  constexpr double kSigma = 0.01;
  const detail::FixedSurface noisy = [](const Vec3&, const Vec3&) {
    return detail::SurfaceOffset{0, kSigma};
  };
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  for (std::size_t i = 0; i < c.moved.size(); ++i) {
    const Eigen::Matrix<double, 1, 6> row =
        detail::alongNormal(c.moved[i].position, c.moved[i].normal);
    information += row.transpose() * row;
  }
  const Eigen::Matrix<double, 6, 6> covariance = kSigma * kSigma * information.inverse();
  const std::vector<Vec3> probes = {Vec3(100, 50, 20), Vec3(0, 0, 0), Vec3(200, 100, 20)};
  std::vector<double> squares(probes.size(), 0);
  constexpr int kLinks = 300;
  for (int seed = 1; seed <= kLinks; ++seed) {
    const Pose link = icp.link(c.moved, noisy, 2, static_cast<std::uint64_t>(seed)).value();
    for (std::size_t k = 0; k < probes.size(); ++k)
      squares[k] += (link * probes[k] - probes[k]).squaredNorm() / kLinks;
  }
  for (std::size_t k = 0; k < probes.size(); ++k) {
    const Eigen::Matrix<double, 3, 6> at = detail::motionAt(probes[k]);
    const double predicted = (at * covariance * at.transpose()).trace();
    RecordProperty("ratio_" + std::to_string(k), std::to_string(squares[k] / predicted));
    EXPECT_NEAR(squares[k] / predicted, 1, 0.15) << k;
  }
}

// A fixed cloud on a cylinder of radius 5 mm, its points on a square grid h apart (arc
// length by height), met point to plane: over 20,000 points of the cylinder at random, the
// tangent plane at each one's nearest fixed point (brute force over the grid around it)
// stands off the cylinder by samplingShift on average, outward on a boss and inward on a bore.
TEST(SimulatedIcp, AFixedCloudsTangentPlanesStandOffACurvedSurfaceByItsSamplingShift) {
  constexpr double kRadius = 5;
  std::mt19937_64 random(7);
  std::uniform_real_distribution<double> unit(0, 1);
  for (const double h : {0.2, 0.5}) {
    double sum = 0;  // of the residuals n_f . (x - f), the boss's outward normal
    constexpr int kPoints = 20000;
    for (int k = 0; k < kPoints; ++k) {
      const double angle = 2 * std::numbers::pi * unit(random), z = 10 * unit(random);
      const Vec3 x(kRadius * std::cos(angle), kRadius * std::sin(angle), z);
      double nearest = std::numeric_limits<double>::infinity(), residual = 0;
      const long i0 = std::lround(kRadius * angle / h), j0 = std::lround(z / h);
      for (long i = i0 - 1; i <= i0 + 1; ++i)
        for (long j = j0 - 1; j <= j0 + 1; ++j) {
          const double a = static_cast<double>(i) * h / kRadius;
          const Vec3 normal(std::cos(a), std::sin(a), 0);
          const Vec3 f = kRadius * normal + static_cast<double>(j) * h * Vec3::UnitZ();
          if ((x - f).norm() >= nearest) continue;
          nearest = (x - f).norm();
          residual = normal.dot(x - f);
        }
      sum += residual;
    }
    const double off = -sum / kPoints;  // where the planes lie, along the boss's normal
    EXPECT_NEAR(off / detail::samplingShift(1 / kRadius, h * h), 1, 0.03) << h;
    // A bore's outward normal points to the axis, and its curvature is negative: the
    // planes stand off along that normal by -off.
    EXPECT_NEAR(-off / detail::samplingShift(-1 / kRadius, h * h), 1, 0.03) << h;
  }
}

// The plate's top and the halves of its bores (radius 10) away from y = 100, registered
// without noise onto fixed clouds of 2.4 mm² per point: the bores' tangent planes stand
// 0.01 mm off the bores, which pulls the view across them; ICP lands where least squares on
// the point-to-plane rows J puts it, (JᵀJ)⁻¹ Jᵀ s with s those 0.01 mm, to within 3 %. The
// moved points stand for squares 0.2 mm across, so that their curvature is their face's
// (the designed points lie 1 mm apart) and not, near the bores' rims, the top's too.
TEST(SimulatedIcp, ItRegistersOntoTheTangentPlanesOfTheFixedCloudsPoints) {
  const IcpPlate p;
  const IcpClouds c(p);
  constexpr double kBoreRadius = 10, kArea = 2.4;
  std::vector<SurfacePoint> moved;
  Eigen::Matrix<double, 6, 6> information = Eigen::Matrix<double, 6, 6>::Zero();
  detail::Twist pull = detail::Twist::Zero();
  for (const SurfacePoint& s : c.moved) {
    const bool bore = s.face != p.top;
    if (bore && s.normal.y() < 0) continue;  // not the halves towards y = 100
    moved.push_back(s);
    const Eigen::Matrix<double, 1, 6> row = detail::alongNormal(s.position, s.normal);
    information += row.transpose() * row;
    if (bore) pull += row.transpose() * (-kArea / (24 * kBoreRadius));  // inward, a bore
  }
  const detail::Twist expected = information.inverse() * pull;
  const detail::SimulatedIcp icp(*c.nominal, RegistrationOptions{}, p.part.linear_deflection);
  const detail::FixedSurface sampled = [](const Vec3&, const Vec3&) {
    return detail::SurfaceOffset{0, 0, kArea};
  };
  const Pose link = icp.link(moved, sampled, 0.2, 1).value();
  for (const Vec3& probe : {Vec3(100, 50, 20), Vec3(60, 50, 10), Vec3(140, 50, 10)}) {
    const Vec3 want = detail::motionAt(probe) * expected, got = link * probe - probe;
    EXPECT_GT(want.norm(), 0.005) << probe.transpose();
    EXPECT_LT((got - want).norm(), 0.03 * want.norm()) << probe.transpose();
  }
}

// A view of `target` from straight above, `distance` away.
View viewFromAbove(int id, const Vec3& target, double distance) {
  View view;
  view.id = id;
  view.target = target;
  view.camera_to_world.linear() << Vec3::UnitX(), -Vec3::UnitY(), -Vec3::UnitZ();
  view.camera_to_world.translation() = target + distance * Vec3::UnitZ();
  return view;
}

// The fixed surface a moved point meets is the mean of the fixed view's points within that
// point's share of the surface. From the scanner model (noise_sigma (z / standoff)² along
// the normal, cos(incidence) / (spacing z / standoff)² points per mm²): a fixed view 50° off
// the normal has cos 50° as many points there as a moved view along it, so its noise counts
// √(1 / cos 50°) times one point's; the other way round √(cos 50°) times; a fixed view
// along the normal 1.2 standoffs away, 1.2² times one point's noise at the standoff and
// 1.2 times sparser along each side: 1.2³ times.
TEST(SimulatedIcp, TheFixedSurfacesNoiseIsThatOfItsPointsWithinAMovedPointsShare) {
  const Scanner scanner = defaultSpec().scanner;
  const Vec3 at = Vec3::Zero(), up = Vec3::UnitZ();
  const View above = viewFromAbove(1, at, scanner.standoff),
             tilted = test::tiltedView(2, at, scanner.standoff, 0),
             farther = viewFromAbove(3, at, 1.2 * scanner.standoff);
  const double sigma = scanner.noise_sigma;
  EXPECT_NEAR(detail::fixedPoints(scanner, tilted, above, at, up).sigma,
              sigma * std::sqrt(1 / std::cos(radians(50))), 1e-12);
  EXPECT_NEAR(detail::fixedPoints(scanner, above, tilted, at, up).sigma,
              sigma * std::sqrt(std::cos(radians(50))), 1e-12);
  EXPECT_NEAR(detail::fixedPoints(scanner, farther, above, at, up).sigma, sigma * std::pow(1.2, 3),
              1e-12);
  EXPECT_NEAR(detail::fixedPoints(scanner, above, above, at, up).sigma, sigma, 1e-12);
}

// The plate's views inspected `runs` times with their ICP links registered, on clouds
// `spacing` apart (0: the default), by a scanner without noise or acceptance errors, and
// whose points lie five times closer together than the generic head's (0.04 mm): the
// tangent planes at the fixed view's points stand off the bores 25 times less.
Inspection inspectedWithoutNoise(IcpPlate& p, int runs, double spacing = 0) {
  p.plan.scanner.noise_sigma = p.plan.scanner.flatness_error = 0;
  p.plan.scanner.sphere_spacing = p.plan.scanner.probing_size = 0;
  p.plan.scanner.point_spacing /= 5;
  InspectionOptions options;
  options.runs = runs;
  options.spacing = spacing;
  options.icp = InspectionOptions::IcpLinks::Registered;
  return inspectPlan(p.part, p.spec, p.plan, options);
}

// The views registered by ICP in each run of the inspection, on clouds of a scanner without
// noise, acceptance errors or sampling, land where they belong: the second bore's position
// is the part's own, 0, in every run. Views left unregistered, or never moved from the
// robot's start (3 mm and 2° off), would give 0 or millimetres; the generic head's own
// spacing gives 0.0004 (the fixed clouds' tangent planes off the bores).
TEST(Inspection, ViewsRegisteredByIcpWithoutNoiseLandWhereTheyBelong) {
  IcpPlate p;
  const Inspection inspected = inspectedWithoutNoise(p, 4);
  EXPECT_EQ(inspected.icp_registered, 3u);
  const InspectedCharacteristic& k = inspected.characteristics.front();
  ASSERT_TRUE(k.evaluated) << k.not_evaluated;
  for (double value : k.values) EXPECT_LT(value, 1e-4);
}

// Without noise, a plate's top measured by four views is flat whatever registers them. On
// clouds 10 mm apart the bores' arcs get a point or two, and ICP from some starts lands a
// view off; registered again on those clouds alone, the top reads up to 0.014 mm out of
// flat (17 of 18 links off after three starts, 6 runs). Registered again on clouds four
// times denser, every run's top is flat to 1e-4 mm.
TEST(Inspection, ALinkOffOnTheRunsSparseCloudIsRegisteredAgainOnADenserOne) {
  IcpPlate p;
  p.plan.characteristics = {{1, "flatness", false, 0.1, 0, 0.1, {}, {p.top}}};
  const Inspection inspected = inspectedWithoutNoise(p, 6, 10);
  EXPECT_GT(inspected.icp_restarted, 0u);
  const InspectedCharacteristic& k = inspected.characteristics.front();
  ASSERT_TRUE(k.evaluated) << k.not_evaluated;
  for (double value : k.values) EXPECT_LT(value, 1e-3);
}

// The plate's characteristic as the budget predicts it, and as `runs` runs of the inspection
// with its ICP links registered find it.
std::pair<Capability, InspectedCharacteristic> predictedAndRegistered(const IcpPlate& p, int runs) {
  InspectionOptions options;
  options.runs = runs;
  options.icp = InspectionOptions::IcpLinks::Registered;
  Inspection inspected = inspectPlan(p.part, p.spec, p.plan, options);
  return {capabilities(p.part, p.spec, p.plan, p.plan.characteristics).front(),
          std::move(inspected.characteristics.front())};
}

// Without the scanner's noise the links move only by the fixed clouds' sampling, at the
// generic head's 0.2 mm: the tangent planes at the fixed views' points stand about 0.2 µm
// off the bores. The inspection's ICP lands each link where those planes put it; the
// budget draws each link's systematic motion, the least-squares motion onto them. The
// second bore's position reads 0.0004 mm in every run, and the budget predicts it to
// within 20 %. Either without the sampling would give 0.
TEST(Inspection, WithoutNoiseTheBoresPositionIsTheFixedCloudsSamplingAsTheBudgetPredicts) {
  IcpPlate p;
  p.plan.scanner.noise_sigma = 1e-7;
  const auto [predicted, k] = predictedAndRegistered(p, 3);
  ASSERT_TRUE(k.evaluated) << k.not_evaluated;
  RecordProperty("predicted_u", std::to_string(predicted.uncertainty));
  RecordProperty("inspected_mean", std::to_string(k.mean));
  EXPECT_GT(k.mean, 1e-4);
  EXPECT_NEAR(predicted.uncertainty / k.mean, 1, 0.2);
}

// With the scanner's noise, the views registered by ICP in each run move the second bore as
// the capability model's covariance of those links predicts, to within 30 % (50 runs; the
// inspection's U uncertain by about 10 %). Measured: the model predicts 1.25 times the
// inspection's U and bias, 1.16 over 70 runs (1.18 before both counted the fixed clouds'
// sampling). With the links' overlaps sampled at the registration's 5.6 mm it predicted 2.2
// times: the fourth view's link is held across the vertical only by the bores' arcs, which
// fell between the overlap's samples.
TEST(Inspection, ViewsRegisteredByIcpAreAsUncertainAsTheModelPredicts) {
  const IcpPlate p;
  const auto [predicted, k] = predictedAndRegistered(p, 50);
  ASSERT_TRUE(k.evaluated) << k.not_evaluated;
  RecordProperty("predicted_u", std::to_string(predicted.uncertainty));
  RecordProperty("inspected_u_bias", std::to_string(k.uncertainty) + " " + std::to_string(k.bias));
  EXPECT_NEAR(predicted.uncertainty / (k.uncertainty + std::abs(k.bias)), 1, 0.3);
}

// The inspection's values do not depend on how many threads simulate the views: each run's
// points are merged in the views' order.
TEST(Inspection, TheSameValuesOnOneThreadAndOnTwo) {
  const FourViewInspection inspect;
  InspectionOptions options;
  options.runs = 3;
  const auto on = [&](std::size_t threads) {
    const tbb::global_control limit(tbb::global_control::max_allowed_parallelism, threads);
    return inspect(options);
  };
  const Inspection one = on(1), two = on(2);
  ASSERT_EQ(one.characteristics.size(), two.characteristics.size());
  for (std::size_t i = 0; i < one.characteristics.size(); ++i)
    EXPECT_EQ(one.characteristics[i].values, two.characteristics[i].values) << i;
}

}  // namespace
}  // namespace scanplan
