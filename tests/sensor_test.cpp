// Scanner presets, parameter validation, views files: every bad input is a clear error.

#include "support.h"

#include <scanplan/core/errors.h>
#include <scanplan/io/spec_yaml.h>
#include <scanplan/io/views_json.h>
#include <scanplan/scanner/sensor.h>
#include <scanplan/spec/spec.h>

namespace scanplan {
namespace {

std::string reasonOf(const std::function<void()>& call) {
  try {
    call();
  } catch (const InputError& e) {
    return e.what();
  }
  ADD_FAILURE() << "no InputError";
  return {};
}

using test::contains;

TEST(Scanner, GenericPresetHasTheIssuedParameters) {
  Scanner s = scannerPreset("generic-structured-light");
  EXPECT_EQ(s.standoff, 400);
  EXPECT_EQ(s.depth_of_field, 200);
  EXPECT_EQ(s.fov_width, 300);
  EXPECT_EQ(s.fov_height, 225);
  EXPECT_EQ(s.triangulation_angle, 25);
  EXPECT_EQ(s.max_camera_angle, 60);
  EXPECT_EQ(s.max_projector_angle, 60);
  EXPECT_EQ(s.reflection_cone, 10);
  EXPECT_NEAR(s.baseline(), 400 * std::tan(radians(25)), 1e-12);
}

TEST(Scanner, LaserLinePresetIsValid) {
  Scanner s = scannerPreset("laser-line");
  EXPECT_EQ(s.name, "laser-line");
  EXPECT_NO_THROW(validate(s, "laser-line"));
}

TEST(Scanner, UnknownPresetListsTheKnownOnes) {
  std::string reason = reasonOf([] { scannerPreset("hyperscan-9000"); });
  EXPECT_TRUE(contains(reason, "unknown scanner preset")) << reason;
  EXPECT_TRUE(contains(reason, "generic-structured-light")) << reason;
}

// The presets are the library's own; $SCANPLAN_DATA/scanners adds presets and replaces one
// by its name.
TEST(Scanner, PresetsAreBuiltInAndScanplanDataAddsMore) {
  const std::vector<std::string> own = scannerPresetNames();
  EXPECT_EQ(own, (std::vector<std::string>{"generic-structured-light", "laser-line"}));
  test::TempDir dir;
  std::filesystem::create_directories(dir.file("scanners"));
  test::writeText(dir.file("scanners/laser-line.yaml"),
                  "standoff: 123\ndepth_of_field: 80\nfov_width: 90\nfov_height: 50\n");
  test::writeText(dir.file("scanners/bench-head.yaml"), "standoff: 250\n");
  ::setenv("SCANPLAN_DATA", dir.file("").c_str(), 1);
  const std::vector<std::string> names = scannerPresetNames();
  const double replaced = scannerPreset("laser-line").standoff;
  const double added = scannerPreset("bench-head").standoff;
  ::unsetenv("SCANPLAN_DATA");
  EXPECT_EQ(names,
            (std::vector<std::string>{"bench-head", "generic-structured-light", "laser-line"}));
  EXPECT_EQ(replaced, 123);
  EXPECT_EQ(added, 250);
  EXPECT_EQ(scannerPreset("laser-line").standoff, 150);  // the library's own again
}

// Added presets that name one another in a loop (one naming itself, or a -> b -> a) are an
// error naming the file and the loop, not an endless descent; those outside the loop read.
TEST(Scanner, PresetsNamingOneAnotherInALoopAreAnError) {
  test::TempDir dir;
  std::filesystem::create_directories(dir.file("scanners"));
  test::writeText(dir.file("scanners/self.yaml"), "preset: self\nstandoff: 300\n");
  test::writeText(dir.file("scanners/a.yaml"), "preset: b\n");
  test::writeText(dir.file("scanners/b.yaml"), "preset: a\n");
  test::writeText(dir.file("scanners/c.yaml"), "preset: laser-line\nstandoff: 140\n");
  ::setenv("SCANPLAN_DATA", dir.file("").c_str(), 1);
  std::string self, loop;
  try {
    scannerPreset("self");
  } catch (const InputError& e) {
    self = e.what();
  }
  try {
    scannerPreset("a");
  } catch (const InputError& e) {
    loop = e.what();
  }
  const double c = scannerPreset("c").standoff;
  ::unsetenv("SCANPLAN_DATA");
  EXPECT_TRUE(contains(self, "self.yaml")) << self;
  EXPECT_TRUE(contains(self, "self -> self")) << self;
  EXPECT_TRUE(contains(loop, "a -> b -> a")) << loop;
  EXPECT_EQ(c, 140);
}

// A spec of a few hundred bytes whose aliases repeat one another ten times over nine levels
// (a "billion laughs": 10^9 values once expanded) is refused at once, not walked, as is one
// nested a hundred levels deep; both errors name the source.
TEST(Spec, AliasesThatRepeatOneAnotherAndDeepNestingAreRefused) {
  std::string laughs = "a0: &a0 [lol]\n";
  for (int k = 1; k <= 9; ++k) {
    const std::string previous = "*a" + std::to_string(k - 1);
    laughs += "a" + std::to_string(k) + ": &a" + std::to_string(k) + " [";
    for (int r = 0; r < 10; ++r) laughs += (r ? ", " : "") + previous;
    laughs += "]\n";
  }
  ASSERT_LT(laughs.size(), 600u);
  const auto start = std::chrono::steady_clock::now();
  try {
    specFromText(laughs, "laughs.yaml");
    ADD_FAILURE() << "a billion laughs read as a spec";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "laughs.yaml")) << e.what();
    EXPECT_TRUE(contains(e.what(), "aliases")) << e.what();
  }
  EXPECT_LT(std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(), 10);
  const std::string deep = "tasks: " + std::string(100, '[') + std::string(100, ']') + "\n";
  try {
    specFromText(deep, "deep.yaml");
    ADD_FAILURE() << "a spec nested 100 levels deep read";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "deep.yaml")) << e.what();
    EXPECT_TRUE(contains(e.what(), "levels deep")) << e.what();
  }
}

// A spec given as text (a Python dict as JSON, say) reads as the same spec from a file,
// and its errors name the source given.
TEST(Spec, TextReadsAsTheFile) {
  test::TempDir dir;
  const std::string yaml =
      "scanner: laser-line\ntasks:\n  - {type: trim, faces: [2, 3]}\nplanner: {most_views: 50}\n";
  test::writeText(dir.file("spec.yaml"), yaml);
  const Spec file = loadSpec(dir.file("spec.yaml"));
  const Spec json = specFromText(
      R"({"scanner": "laser-line", "tasks": [{"type": "trim", "faces": [2, 3]}],
          "planner": {"most_views": 50}})",
      "<dict>");
  EXPECT_EQ(json.scanner.name, file.scanner.name);
  EXPECT_EQ(json.scanner.standoff, file.scanner.standoff);
  ASSERT_EQ(json.tasks.size(), 1u);
  EXPECT_EQ(json.tasks[0].type, TaskType::Trim);
  EXPECT_EQ(json.tasks[0].faces.size(), file.tasks[0].faces.size());
  EXPECT_EQ(json.planner.most_views, 50);
  EXPECT_EQ(reasonOf([] { specFromText("{\"tasks\": []}", "<dict>"); }),
            "<dict>: tasks must be a non-empty list");
  EXPECT_TRUE(
      contains(reasonOf([] { specFromText("{tasks: [", "<dict>"); }), "<dict>: not valid YAML"));
}

TEST(Scanner, ValidationNamesTheParameter) {
  auto check = [](auto mutate, const std::string& parameter) {
    Scanner s;
    mutate(s);
    std::string reason = reasonOf([&] { validate(s, "spec.yaml"); });
    EXPECT_TRUE(contains(reason, parameter)) << reason;
    EXPECT_TRUE(contains(reason, "spec.yaml")) << reason;
  };
  check([](Scanner& s) { s.standoff = -1; }, "standoff");
  check([](Scanner& s) { s.fov_width = 0; }, "fov_width");
  check([](Scanner& s) { s.fov_height = NAN; }, "fov_height");
  check([](Scanner& s) { s.triangulation_angle = 95; }, "triangulation_angle");
  check([](Scanner& s) { s.max_camera_angle = 0; }, "max_camera_angle");
  check([](Scanner& s) { s.max_projector_angle = 90; }, "max_projector_angle");
  check([](Scanner& s) { s.reflection_cone = -2; }, "reflection_cone");
  check([](Scanner& s) { s.depth_of_field = 800; }, "twice the standoff");
  check([](Scanner& s) { s.point_spacing = 0; }, "point_spacing");
  check([](Scanner& s) { s.noise_sigma = -0.1; }, "noise_sigma");
  check([](Scanner& s) { s.noise_sigma = 1e300; }, "noise_sigma");
  check([](Scanner& s) { s.body_margin = -1; }, "body_margin");
  check([](Scanner& s) { s.body_depth = 0; }, "body_depth");
  // Absurd sizes: rays far beyond the ray caster's precision, clouds beyond memory.
  check([](Scanner& s) { s.standoff = 1e30; }, "at most 100,000");
  check([](Scanner& s) { s.body_margin = 1e30; }, "body_margin");
  check([](Scanner& s) { s.point_spacing = 0.001; }, "more than 100 million points");
  EXPECT_NO_THROW(validate(Scanner{}, "defaults"));
}

TEST(Scanner, SpecWithPresetOrMapping) {
  test::TempDir dir;
  test::writeText(dir.file("a.yaml"), "scanner: laser-line\n");
  EXPECT_EQ(loadSpec(dir.file("a.yaml")).scanner.name, "laser-line");
  test::writeText(dir.file("b.yaml"),
                  "scanner:\n  preset: generic-structured-light\n  standoff: 500\n"
                  "roles:\n  specular: [3, 4]\ncell:\n  working_plane: false\n");
  Spec spec = loadSpec(dir.file("b.yaml"));
  EXPECT_EQ(spec.scanner.standoff, 500);
  EXPECT_EQ(spec.scanner.fov_width, 300);
  ASSERT_EQ(spec.specular.size(), 2u);
  EXPECT_EQ(spec.specular[1].id, 4);
  EXPECT_FALSE(spec.working_plane);
  EXPECT_EQ(defaultSpec().scanner.name, "generic-structured-light");
}

TEST(Scanner, BadSpecs) {
  test::TempDir dir;
  auto reason = [&](const std::string& text) {
    test::writeText(dir.file("s.yaml"), text);
    return reasonOf([&] { loadSpec(dir.file("s.yaml")); });
  };
  EXPECT_TRUE(contains(reason("scanner: {standof: 3}\n"), "unknown scanner parameter 'standof'"));
  EXPECT_TRUE(contains(reason("scanner: {standoff: far}\n"), "must be a number"));
  EXPECT_TRUE(contains(reason("scanner: {depth_of_field: 900}\n"), "twice the standoff"));
  EXPECT_TRUE(contains(reason("scanner: nope\n"), "unknown scanner preset"));
  EXPECT_TRUE(contains(reason("roles: {specular: [0]}\n"), "face ids start at 1"));
  EXPECT_TRUE(contains(reason("sanner: x\n"), "unknown key 'sanner'"));
  EXPECT_TRUE(contains(reason("scanner: [1, 2\n"), "not valid YAML"));
  EXPECT_TRUE(contains(reason("markers: {grid: 0}\n"), "markers.grid must be a positive"));
  EXPECT_TRUE(contains(reason("markers: {grid: 50, on: floor}\n"),
                       "expected plate, table, part, both or fixture"));
  EXPECT_TRUE(contains(reason("markers: {grid: 50, on: [plate, table]}\n"), "give one"));
  EXPECT_TRUE(contains(reason("markers: {grid: 50, diameter: -1}\n"), "from 0 to 100 mm"));
  test::writeText(dir.file("m.csv"), "x,y,z\n0,0,0\n");
  EXPECT_TRUE(contains(reason("markers: {file: m.csv, on: floor}\n"), "plate, table or part"));
  EXPECT_TRUE(contains(reason("markers: {file: m.csv, grid: 5}\n"), "unknown key 'grid'"));
  EXPECT_TRUE(contains(reason("markers: {margin: 50}\n"), "needs grid"));
  EXPECT_TRUE(contains(reason("registration: {min_overlap: 2}\n"), "min_overlap must be in"));
  EXPECT_TRUE(contains(reason("registration: {min_markers: 2}\n"), "at least 3"));
  EXPECT_TRUE(contains(reason("registration: {perturbation: 3}\n"), "[mm, degrees]"));
  EXPECT_TRUE(contains(reason("registration: {tolerence: 1}\n"), "unknown key 'tolerence'"));
  EXPECT_TRUE(contains(reasonOf([] { loadSpec("/nonexistent/spec.yaml"); }), "no such file"));
}

TEST(Scanner, SpecMarkersAndRegistration) {
  test::TempDir dir;
  test::writeText(dir.file("markers.csv"), "x,y,z\n0,0,0\n");
  test::writeText(dir.file("a.yaml"),
                  "markers: markers.csv\n"
                  "registration: {min_overlap: 0.3, max_condition: 50, perturbation: [5, 3],\n"
                  "               verify: false, bridging: false, max_bridging_views: 4}\n");
  const Spec a = loadSpec(dir.file("a.yaml"));
  EXPECT_EQ(a.markers_file, dir.file("markers.csv"));
  EXPECT_DOUBLE_EQ(a.registration.min_overlap, 0.3);
  EXPECT_DOUBLE_EQ(a.registration.max_condition, 50);
  EXPECT_DOUBLE_EQ(a.registration.perturbation, 5);
  EXPECT_DOUBLE_EQ(a.registration.perturbation_angle, 3);
  EXPECT_FALSE(a.registration.verify);
  EXPECT_FALSE(a.registration.bridging);
  EXPECT_EQ(a.registration.max_bridging_views, 4);
  test::writeText(dir.file("b.yaml"), "markers: {grid: 40, margin: 80, on: part}\n");
  const Spec b = loadSpec(dir.file("b.yaml"));
  EXPECT_DOUBLE_EQ(b.marker_grid, 40);
  EXPECT_DOUBLE_EQ(b.marker_margin, 80);
  EXPECT_TRUE(b.markers_on_part);
  EXPECT_FALSE(b.markers_on_plate);
  EXPECT_DOUBLE_EQ(b.marker_diameter, 8);
  test::writeText(dir.file("c.yaml"), "markers: {file: markers.csv, on: part, diameter: 5}\n");
  const Spec c = loadSpec(dir.file("c.yaml"));
  EXPECT_EQ(c.markers_file, dir.file("markers.csv"));
  EXPECT_EQ(c.markers_file_on, MarkerCarrier::Part);
  EXPECT_DOUBLE_EQ(c.marker_diameter, 5);
}

TEST(ViewsFile, PlanFormatAndBareArray) {
  test::TempDir dir;
  const std::string matrix = "[[1,0,0,10],[0,-1,0,0],[0,0,-1,500],[0,0,0,1]]";
  test::writeText(dir.file("plan.json"),
                  "{\"format\":\"scanplan.plan\",\"part\":{\"part_to_world\":[[1,0,0,0],[0,1,0,0],["
                  "0,0,1,100],[0,0,0,1]]},"
                  "\"views\":[{\"id\":4,\"camera_to_world\":" +
                      matrix + ",\"target\":[10,0,100],\"task\":\"gdt\"}]}");
  ViewsFile plan = readViews(dir.file("plan.json"));
  ASSERT_EQ(plan.views.size(), 1u);
  EXPECT_EQ(plan.views[0].id, 4);
  EXPECT_EQ(plan.views[0].task, "gdt");
  EXPECT_TRUE(plan.views[0].camera().isApprox(Vec3(10, 0, 500)));
  EXPECT_TRUE(plan.views[0].axis().isApprox(Vec3(0, 0, -1)));
  EXPECT_TRUE(plan.part_to_world.translation().isApprox(Vec3(0, 0, 100)));
  test::writeText(dir.file("bare.json"),
                  "[{\"camera_to_world\":" + matrix + "}, {\"camera_to_world\":" + matrix + "}]");
  ViewsFile bare = readViews(dir.file("bare.json"));
  ASSERT_EQ(bare.views.size(), 2u);
  EXPECT_EQ(bare.views[1].id, 2);
}

TEST(ViewsFile, BadFiles) {
  test::TempDir dir;
  auto reason = [&](const std::string& text) {
    test::writeText(dir.file("v.json"), text);
    return reasonOf([&] { readViews(dir.file("v.json")); });
  };
  EXPECT_TRUE(contains(reason("{views: ["), "not valid JSON"));
  EXPECT_TRUE(contains(reason("{\"plan\": 1}"), "no 'views' array"));
  EXPECT_TRUE(contains(reason("[{\"id\": 3}]"), "view 1 (id 3): no camera_to_world"));
  EXPECT_TRUE(
      contains(reason("[{\"camera_to_world\": [[1,0,0],[0,1,0],[0,0,1]]}]"), "4 rows of 4"));
  // A scaled matrix is not rigid.
  EXPECT_TRUE(contains(reason("[{\"camera_to_world\": [[2,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]"),
                       "not a rigid transform"));
  // A reflection (determinant -1) is not a rotation.
  EXPECT_TRUE(
      contains(reason("[{\"camera_to_world\": [[1,0,0,0],[0,1,0,0],[0,0,-1,0],[0,0,0,1]]}]"),
               "not a rigid transform"));
  EXPECT_TRUE(contains(reason("[{\"camera_to_world\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,1,1]]}]"),
                       "not a rigid transform"));
  EXPECT_TRUE(
      contains(reason("[{\"id\":1,\"camera_to_world\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]},"
                      "{\"id\":1,\"camera_to_world\": [[1,0,0,0],[0,1,0,0],[0,0,1,0],[0,0,0,1]]}]"),
               "used twice"));
  EXPECT_TRUE(contains(reasonOf([] { readViews("/nonexistent/views.json"); }), "no such file"));
}

}  // namespace
}  // namespace scanplan
