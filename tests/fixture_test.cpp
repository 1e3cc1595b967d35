// Fixture models (the spec's fixtures:): a box part inside a frame loaded from its own STEP
// file, and a bar of a gantry above it in the world. They hide the part, the scanner
// stays clear of them, they are never sampled, they count as fixture faces, and markers
// on them register the views.

#include "occt_support.h"
#include "plan_support.h"

#include <scanplan/cad/import.h>
#include <scanplan/core/errors.h>
#include <scanplan/planning/poses.h>
#include <scanplan/registration/registration.h>
#include <scanplan/report/report.h>

#include <nlohmann/json.hpp>

#include <BRepAlgoAPI_Cut.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <gp_Pnt.hxx>

#include <cstring>
#include <fstream>
#include <iterator>

namespace scanplan {
namespace {

using test::TempDir;

// The part: a 200 x 150 x 40 mm box on the plane.
constexpr double kX = 200, kY = 150, kZ = 40;
// The frame around it, in the part's frame: walls 20 mm thick, 10 mm from the part, 70 mm
// high. Its 10 faces: 4 outside, 4 inside, top and bottom.
constexpr double kGap = 10, kWall = 20, kFrameZ = 70;
// The bar of a gantry, in the world, where the scanner stands to look down on the part.
const Box kBar{Vec3(-50, 55, 420), Vec3(250, 95, 460)};

TopoDS_Shape box(const Vec3& lo, const Vec3& hi) {
  return BRepPrimAPI_MakeBox(gp_Pnt(lo.x(), lo.y(), lo.z()), gp_Pnt(hi.x(), hi.y(), hi.z()))
      .Shape();
}

TopoDS_Shape frame() {
  const double in = kGap, out = kGap + kWall;
  return BRepAlgoAPI_Cut(box(Vec3(-out, -out, 0), Vec3(kX + out, kY + out, kFrameZ)),
                         box(Vec3(-in, -in, -1), Vec3(kX + in, kY + in, kFrameZ + 1)))
      .Shape();
}

// The part, the frame and the bar in `dir`, and the spec's fixtures.
struct FramedBox {
  TempDir dir;
  Part part;
  std::string fixtures;  // the spec's fixtures: section

  explicit FramedBox(const std::string& spec_fixtures) : fixtures(spec_fixtures) {
    part = importPart(test::writeStep(box(Vec3::Zero(), Vec3(kX, kY, kZ)), dir.file("part.step")));
    test::writeStep(frame(), dir.file("frame.step"));
    test::writeStep(box(kBar.min, kBar.max), dir.file("bar.step"));
  }

  Spec spec(const std::string& rest) const { return test::specWith(fixtures + rest, dir); }
};

const std::string kFrame = "fixtures:\n  - {file: frame.step}\n";
const std::string kFrameAndBar = kFrame + "  - {file: bar.step, frame: world}\n";

bool onSideFace(const PlannedSample& s) { return std::abs(s.sample.normal.z()) < 1e-6; }

// The plan of every face of the part, without registration, shared by the tests.
class FixturePlan : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    PlanningOptions options;
    options.registration = false;
    for (auto [plan, fixtures] :
         {std::pair{&planned_, kFrameAndBar}, {&framed_, kFrame}, {&bare_, std::string()}}) {
      const FramedBox scene(fixtures);
      *plan = new Plan(planViews(scene.part, scene.spec("tasks: [{type: global}]\n"), options));
    }
  }
  static void TearDownTestSuite() {
    delete planned_;
    delete framed_;
    delete bare_;
  }
  static Plan *planned_, *framed_, *bare_;  // with the frame and the bar, the frame, neither
};
Plan *FixturePlan::planned_, *FixturePlan::framed_, *FixturePlan::bare_;

TEST_F(FixturePlan, TheFrameHidesTheSideFaces) {
  // Seen 10 mm from a wall 30 mm higher than the part, a side face would need a camera
  // more than 60 degrees off its normal: nothing measures it inside the frame.
  std::size_t side = 0, measured_bare = 0;
  for (std::size_t i = 0; i < framed_->samples.size(); ++i) {
    if (!onSideFace(framed_->samples[i])) continue;
    ++side;
    EXPECT_TRUE(framed_->samples[i].measured_by.empty()) << "sample " << i;
  }
  for (const PlannedSample& s : bare_->samples)
    measured_bare += onSideFace(s) && !s.measured_by.empty();
  EXPECT_GT(side, 20u);
  EXPECT_GT(measured_bare, side / 2) << "without the frame, the side faces are measured";
}

TEST_F(FixturePlan, ViewsStayClearOfTheBar) {
  // Where the scanner stands to look down on the part in the frame, the bar stands now.
  Box grown = kBar;
  const double margin = planned_->scanner.body_margin;
  grown.min -= Vec3::Constant(margin);
  grown.max += Vec3::Constant(margin);
  auto inBar = [&](const View& v) {
    const Vec3 c = v.camera_to_world.translation();
    return (c.array() >= grown.min.array()).all() && (c.array() <= grown.max.array()).all();
  };
  EXPECT_TRUE(std::any_of(framed_->views.begin(), framed_->views.end(), inBar));
  for (const View& v : planned_->views) EXPECT_FALSE(inBar(v)) << "view " << v.id;
  // The planner's own check rejects those views once the bar is in the scene.
  const FramedBox scene(kFrameAndBar);
  const ResolvedSpec resolved = resolveSpec(scene.part, scene.spec(""));
  const Simulator simulator(scene.part, planned_->scanner,
                            simulationOptionsFor(resolved, scene.part, planned_->part_to_world));
  for (const View& v : framed_->views)
    if (inBar(v)) {
      EXPECT_FALSE(poseIsValid(simulator, v, {})) << "view " << v.id;
    }
  // The top face is measured all the same.
  for (const PlannedSample& s : planned_->samples)
    if (s.sample.normal.z() > 0.99) {
      EXPECT_FALSE(s.measured_by.empty());
    }
}

TEST_F(FixturePlan, FixturesAreNeverSampledAndCountAsFixtureFaces) {
  for (const PlannedSample& s : planned_->samples) {
    const Vec3 p = planned_->part_to_world.inverse() * s.sample.position;
    EXPECT_TRUE((p.array() >= -1e-6).all() && (p.array() <= Vec3(kX, kY, kZ).array() + 1e-6).all())
        << p.transpose();
  }
  EXPECT_EQ(planned_->samples.size(), bare_->samples.size());
  EXPECT_EQ(planned_->part_faces, 6u);
  EXPECT_EQ(planned_->fixture_faces, 10u + 6u);  // the frame's and the bar's
  EXPECT_EQ(bare_->fixture_faces, 0u);
}

TEST_F(FixturePlan, TheReportDrawsTheFixtures) {
  const FramedBox scene(kFrameAndBar);
  const Spec spec = scene.spec("roles: {fixture: [1]}\n");
  ReportOptions options;
  options.clouds = options.visibility_maps = false;
  writeReport(*planned_, scene.part, spec, scene.dir.file("report.html"), options);
  std::ifstream in(scene.dir.file("report.html"));
  const std::string page{std::istreambuf_iterator<char>(in), {}};
  const std::string open = R"(<script type="application/json" id="scanplan-data">)";
  const std::size_t begin = page.find(open) + open.size();
  const auto data =
      nlohmann::json::parse(page.substr(begin, page.find("</script>", begin) - begin));
  // Base64 of 3 floats per vertex: the frame's and the bar's.
  const ResolvedSpec resolved = resolveSpec(scene.part, spec);
  const std::size_t vertices =
      resolved.fixture_meshes[0].vertices.size() + resolved.fixture_meshes[1].vertices.size();
  EXPECT_EQ(data["fixtures"]["positions"].get<std::string>().size(), (vertices * 12 + 2) / 3 * 4);
  EXPECT_EQ(data["palette"]["fixture"], nlohmann::json(kFixtureColour));
  for (const auto& face : data["faces"]) EXPECT_EQ(face["fixture"], face["id"] == 1);
}

TEST_F(FixturePlan, TheGlbAndThePictureShowTheFixtures) {
  const FramedBox scene(kFrameAndBar);
  const ResolvedSpec resolved = resolveSpec(scene.part, scene.spec(""));
  const PlanScene placed = planScene(*planned_, scene.part, resolved);
  const std::size_t triangles =
      resolved.fixture_meshes[0].triangles.size() + resolved.fixture_meshes[1].triangles.size();
  ASSERT_EQ(placed.fixtures.triangles.size(), triangles);
  // The glTF scene: a mesh of the fixtures, three vertices a triangle, in their colour.
  writeGlb(placed, scene.dir.file("plan.glb"));
  std::ifstream in(scene.dir.file("plan.glb"), std::ios::binary);
  const std::string bytes{std::istreambuf_iterator<char>(in), {}};
  std::uint32_t length = 0;
  std::memcpy(&length, bytes.data() + 12, 4);
  const auto gltf = nlohmann::json::parse(bytes.substr(20, length));
  bool found = false;
  for (const auto& mesh : gltf["meshes"]) {
    if (mesh["name"] != "fixtures") continue;
    found = true;
    const auto& primitive = mesh["primitives"][0];
    EXPECT_EQ(gltf["accessors"][primitive["attributes"]["POSITION"].get<int>()]["count"],
              3 * triangles);
    const auto& factor = gltf["materials"][primitive["material"].get<int>()]["pbrMetallicRoughness"]
                             ["baseColorFactor"];
    EXPECT_NEAR(factor[0].get<double>(), kFixtureColour[0] / 255.0, 0.01);
    EXPECT_NEAR(factor[2].get<double>(), kFixtureColour[2] / 255.0, 0.01);
  }
  EXPECT_TRUE(found);
  // The picture: pixels in the fixtures' colour (shaded), none without them.
  auto fixturePixels = [](const Image& image) {
    std::size_t n = 0;
    for (std::size_t i = 0; i + 2 < image.rgb.size(); i += 3) {
      const double r = image.rgb[i], g = image.rgb[i + 1], b = image.rgb[i + 2];
      n += b > 40 && std::abs(r / b - 96.0 / 168) < 0.02 && std::abs(g / b - 122.0 / 168) < 0.02;
    }
    return n;
  };
  EXPECT_GT(fixturePixels(renderScene(placed, 320, 240)), 500u);
  EXPECT_EQ(fixturePixels(renderScene(planScene(*planned_, scene.part), 320, 240)), 0u);
}

TEST(Fixtures, PlacedInThePartFrameTheyFollowThePart) {
  const FramedBox cell(kFrameAndBar);
  const Spec spec =
      cell.spec("part: {rest: [[1, 0, 0, 500], [0, 1, 0, 0], [0, 0, 1, 0], [0, 0, 0, 1]]}\n");
  const ResolvedSpec resolved = resolveSpec(cell.part, spec);
  const auto meshes = fixturesInWorld(resolved, *spec.rest_pose);
  ASSERT_EQ(meshes.size(), 2u);
  Box frame, bar;
  for (const Vec3& v : meshes[0].vertices) frame.add(v);
  for (const Vec3& v : meshes[1].vertices) bar.add(v);
  EXPECT_TRUE(frame.min.isApprox(Vec3(500 - kGap - kWall, -kGap - kWall, 0), 1e-9));
  EXPECT_TRUE(bar.min.isApprox(kBar.min, 1e-9)) << "the bar stays in the world";
}

TEST(Fixtures, MarkersGivenInTheFixturesFrameAreCarriedIntoTheWorld) {
  const FramedBox cell("");
  test::writeText(cell.dir.file("bar-markers.csv"), "x,y,z,nx,ny,nz\n10,0,0,0,0,1\n0,20,0,1,0,0\n");
  // The bar turned 90 degrees about z and raised, in the world; the part placed 500 mm along x.
  const Spec spec = cell.spec(
      "fixtures:\n"
      "  - {file: bar.step, frame: world, markers: bar-markers.csv,\n"
      "     placement: {position: [0, 0, 100], rotation: [0, 0, 90]}}\n"
      "  - {file: frame.step, placement: {position: [0, 0, 5]}}\n"
      "markers: {grid: 40, on: fixture}\n");
  const ResolvedSpec resolved = resolveSpec(cell.part, spec);
  Pose part_to_world = Pose::Identity();
  part_to_world.translation() = Vec3(500, 0, 0);
  const std::vector<Marker> markers = specMarkers(resolved, cell.part, part_to_world);
  ASSERT_GE(markers.size(), 2u);
  const Marker& first = markers[markers.size() - 2];
  const Marker& second = markers.back();
  EXPECT_TRUE(first.position.isApprox(Vec3(0, 10, 100), 1e-9)) << first.position.transpose();
  EXPECT_TRUE(first.normal.isApprox(Vec3(0, 0, 1), 1e-9));
  EXPECT_TRUE(second.position.isApprox(Vec3(-20, 0, 100), 1e-9)) << second.position.transpose();
  EXPECT_TRUE(second.normal.isApprox(Vec3(0, 1, 0), 1e-9)) << second.normal.transpose();
  // The grid lies on the tops of the fixtures: the bar's at z = 460 + 100, the frame's at
  // 70 + 5, moved with the part.
  for (std::size_t m = 0; m + 2 < markers.size(); ++m) {
    const double z = markers[m].position.z();
    EXPECT_TRUE(std::abs(z - 560) < 1e-6 || std::abs(z - 75) < 1e-6) << z;
    const double x = markers[m].position.x(), out = kGap + kWall;
    EXPECT_TRUE(std::abs(z - 75) > 1e-6 || (x > 500 - out && x < 500 + kX + out)) << x;
  }
}

TEST(Fixtures, BadFixturesAreInputErrors) {
  const FramedBox cell(kFrameAndBar);
  EXPECT_THROW(resolveSpec(cell.part, test::specWith("fixtures: [{file: none.step}]\n", cell.dir)),
               InputError);
  EXPECT_THROW(test::specWith("fixtures: {file: frame.step}\n", cell.dir), InputError);
  EXPECT_THROW(test::specWith("fixtures: [{placement: [1, 2]}]\n", cell.dir), InputError);
  EXPECT_THROW(test::specWith("fixtures: [{file: frame.step, frame: cell}]\n", cell.dir),
               InputError);
  EXPECT_THROW(
      resolveSpec(cell.part, test::specWith("markers: {grid: 10, on: fixture}\n", cell.dir)),
      InputError);
  test::writeText(cell.dir.file("broken.step"), "ISO-10303-21;\nHEADER;\n");
  EXPECT_THROW(
      resolveSpec(cell.part, test::specWith("fixtures: [{file: broken.step}]\n", cell.dir)),
      InputError);
}

// A 700 x 520 x 5 mm panel flush in a frame 40 mm wide, 5 mm from it, with markers every
// 10 mm on the frame; control points every 50 mm over the panel.
class MarkerFrame : public ::testing::Test {
 protected:
  static constexpr double kW = 700, kH = 520, kT = 5, kIn = 5, kOut = 45;

  static std::string points() {
    std::string csv;
    for (double x = 25; x < kW; x += 50)
      for (double y = 25; y < kH; y += 50)
        csv += std::to_string(x) + "," + std::to_string(y) + "," + std::to_string(kT) + ",0,0,1\n";
    return csv;
  }

  // The plan of the control points, registered by the markers on the frame (or without
  // them: by geometry).
  static Plan plan(const TempDir& dir, const Part& part, bool markers) {
    return planViews(part,
                     test::specWith(std::string("fixtures: [{file: frame.step}]\n") +
                                        (markers ? "markers: {grid: 10, on: fixture}\n" : "") +
                                        "tasks: [{type: points, file: points.csv}]\n",
                                    dir));
  }

  static void SetUpTestSuite() {
    const TempDir dir;
    panel_ = new Part(
        importPart(test::writeStep(box(Vec3::Zero(), Vec3(kW, kH, kT)), dir.file("panel.step"))));
    test::writeStep(BRepAlgoAPI_Cut(box(Vec3(-kOut, -kOut, 0), Vec3(kW + kOut, kH + kOut, kT)),
                                    box(Vec3(-kIn, -kIn, -1), Vec3(kW + kIn, kH + kIn, kT + 1)))
                        .Shape(),
                    dir.file("frame.step"));
    test::writeText(dir.file("points.csv"), points());
    frame_ = new Part(importPart(dir.file("frame.step")));
    with_ = new Plan(plan(dir, *panel_, true));
    without_ = new Plan(plan(dir, *panel_, false));
  }
  static void TearDownTestSuite() {
    delete with_;
    delete without_;
    delete panel_;
  }
  static Part* panel_;
  static Part* frame_;
  static Plan *with_, *without_;
};
Part* MarkerFrame::panel_;
Part* MarkerFrame::frame_;
Plan *MarkerFrame::with_, *MarkerFrame::without_;

TEST_F(MarkerFrame, MarkersOnTheFrameRegisterViewsOfAPlane) {
  ASSERT_TRUE(with_->registration && without_->registration);
  for (const PlannedSample& s : with_->samples) EXPECT_FALSE(s.measured_by.empty());
  EXPECT_GT(with_->views.size(), 1u);
  EXPECT_EQ(with_->registration->registered(), with_->views.size());
  for (const ViewRegistration& v : with_->registration->views)
    EXPECT_NE(v.method, RegistrationMethod::Icp);
  // The results row: every control point acquired, every view alignable.
  const Plan::ResultsRow row = with_->resultsRow();
  EXPECT_EQ(row.model_faces, 6u);
  EXPECT_EQ(row.fixture_faces, 10u);
  EXPECT_TRUE(row.control_points);
  EXPECT_EQ(row.points, 14u * 10u);
  EXPECT_EQ(row.acquired, row.points);
  EXPECT_EQ(row.alignable, with_->views.size());
  // By its geometry, a plane registers nothing to the reference view.
  EXPECT_GT(without_->views.size(), 1u);
  EXPECT_EQ(without_->registration->registered(), 1u);
}

TEST_F(MarkerFrame, EveryViewSeesThreeMarkers) {
  // Every control point lies within 250 mm of the frame's markers, less than the width of
  // the field of view (300 mm): a view can take in a point and markers beyond it.
  ASSERT_FALSE(with_->markers.empty());
  std::vector<SurfacePoint> markers;
  for (const Marker& m : with_->markers) markers.push_back({m.position, m.normal, 0});
  SimulationOptions placed;
  placed.part_to_world = with_->part_to_world;
  placed.fixtures.push_back(frame_->mesh);
  const Simulator simulator(*panel_, with_->scanner, placed);
  const auto seen = measuredPoints(simulator, with_->views, markers);
  for (std::size_t v = 0; v < seen.size(); ++v) {
    std::vector<Vec3> positions;
    for (int m : seen[v]) positions.push_back(markers[m].position);
    EXPECT_TRUE(markersRegister(positions, 3, 10))
        << "view " << with_->views[v].id << " sees " << positions.size() << " markers";
  }
}

}  // namespace
}  // namespace scanplan
