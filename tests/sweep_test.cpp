// Sweep positioning: a plate much larger than the field of view, a curved panel of many
// B-spline faces under an interpolated patch, and a 1.9 m sheet-metal plate.

#include "plan_support.h"

#include <scanplan/cad/import.h>
#include <scanplan/cad/localization.h>
#include <scanplan/cad/patch.h>
#include <scanplan/io/patch_file.h>
#include <scanplan/io/plan_json.h>
#include <scanplan/planning.h>
#include <scanplan/planning/sweep_tiles.h>

#include <BRepBuilderAPI_MakeFace.hxx>
#include <BRepBuilderAPI_Sewing.hxx>
#include <BRepPrimAPI_MakeBox.hxx>
#include <BRepTools.hxx>
#include <GeomAPI_PointsToBSplineSurface.hxx>
#include <Geom_BSplineSurface.hxx>
#include <TColgp_Array2OfPnt.hxx>

#include <cmath>
#include <set>

namespace scanplan {
namespace {

using test::coverableAndMeasured;
using test::specWith;
using test::topFace;

PlanningOptions withoutRegistration() {
  PlanningOptions options;
  options.registration = false;
  return options;
}

TEST(Sweep, PlateTilesCoverWithTheOverlap) {
  test::TempDir dir;
  BRepTools::Write(BRepPrimAPI_MakeBox(1000, 600, 10).Shape(), dir.file("plate.brep").c_str());
  const Part part = importPart(dir.file("plate.brep"));
  const int top = topFace(part);
  ASSERT_GT(top, 0);
  const Spec spec =
      specWith("tasks:\n  - {type: surface, faces: [" + std::to_string(top) + "]}\n", dir);
  const Plan plan = planViews(part, spec, withoutRegistration());

  ASSERT_EQ(plan.sweeps.size(), 1u);
  const Sweep& sweep = plan.sweeps.front();
  EXPECT_EQ(sweep.faces, std::vector<int>{top});
  EXPECT_EQ(plan.measuredCount(), plan.samples.size());
  // Area-based count: the plate's area over a tile's, the field of view less the overlap.
  const double overlap = 0.3;
  const double tile =
      plan.scanner.fov_width * (1 - overlap) * plan.scanner.fov_height * (1 - overlap);
  const double area_count = std::ceil(1000.0 * 600.0 / tile);
  EXPECT_LE(std::abs(static_cast<double>(sweep.views.size()) - area_count), 1.0)
      << sweep.views.size() << " views, area-based " << area_count;
  EXPECT_EQ(plan.views.size(), sweep.views.size());  // nothing else was needed

  // Consecutive views of the sweep are neighbours whose fields of view overlap by at
  // least the set share, and they measure common points of the plate.
  SimulationOptions simulation;
  simulation.part_to_world = plan.part_to_world;
  const Simulator simulator(part, plan.scanner, simulation);
  std::vector<SurfacePoint> grid;
  for (double x = 5; x < 1000; x += 10)
    for (double y = 5; y < 600; y += 10)
      grid.push_back({plan.part_to_world * Vec3(x, y, 10), Vec3::UnitZ(), top});
  std::vector<char> measured(grid.size(), 0);
  for (std::size_t k = 0; k + 1 < sweep.views.size(); ++k) {
    const View& a = plan.views[sweep.views[k] - 1];
    const View& b = plan.views[sweep.views[k + 1] - 1];
    const Vec3 step = b.target - a.target;
    const double across = std::abs(step.dot(a.camera_to_world.linear().col(0)));
    const double along = std::abs(step.dot(a.camera_to_world.linear().col(1)));
    const bool same_row = along < across;
    const double step_limit =
        (same_row ? plan.scanner.fov_width : plan.scanner.fov_height) * (1 - overlap) + 1;
    EXPECT_LE(same_row ? across : along, step_limit) << "views " << a.id << ", " << b.id;
    const auto la = simulator.measure(a, grid), lb = simulator.measure(b, grid);
    std::size_t common = 0, in_a = 0;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      in_a += la[i] == Loss::Measured;
      common += la[i] == Loss::Measured && lb[i] == Loss::Measured;
    }
    EXPECT_GE(static_cast<double>(common), 0.15 * static_cast<double>(in_a))
        << "views " << a.id << ", " << b.id;
  }
  for (const View& view : plan.views) {
    const auto losses = simulator.measure(view, grid);
    for (std::size_t i = 0; i < grid.size(); ++i) measured[i] |= losses[i] == Loss::Measured;
  }
  // The whole plate, not only its samples, is measured.
  EXPECT_EQ(std::count(measured.begin(), measured.end(), 1), static_cast<long>(grid.size()));
}

// A doubly curved panel, z = 60 sin(pi x / 800) cos(pi y / 600) over 800 x 600 mm, as
// one B-spline surface cut into a 4 x 3 grid of faces, sewn into a shell.
Part curvedPanel(const test::TempDir& dir) {
  TColgp_Array2OfPnt points(1, 21, 1, 21);
  for (int i = 1; i <= 21; ++i)
    for (int j = 1; j <= 21; ++j) {
      const double x = 40.0 * (i - 1), y = 30.0 * (j - 1);
      points(i, j) = gp_Pnt(x, y, 60 * std::sin(M_PI * x / 800) * std::cos(M_PI * y / 600));
    }
  const Handle(Geom_BSplineSurface) surface = GeomAPI_PointsToBSplineSurface(points).Surface();
  double u0, u1, v0, v1;
  surface->Bounds(u0, u1, v0, v1);
  BRepBuilderAPI_Sewing sewing;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 3; ++b)
      sewing.Add(BRepBuilderAPI_MakeFace(surface, u0 + (u1 - u0) * a / 4,
                                         u0 + (u1 - u0) * (a + 1) / 4, v0 + (v1 - v0) * b / 3,
                                         v0 + (v1 - v0) * (b + 1) / 3, 1e-7)
                     .Face());
  sewing.Perform();
  BRepTools::Write(sewing.SewedShape(), dir.file("panel.brep").c_str());
  return importPart(dir.file("panel.brep"));
}

TEST(Sweep, CurvedPanelUnderAnInterpolatedPatch) {
  test::TempDir dir;
  const Part part = curvedPanel(dir);
  ASSERT_EQ(part.faces.size(), 12u);
  std::vector<int> all;
  for (const Face& face : part.faces) all.push_back(face.id);

  // One set: the panel's normals stay within 15 degrees of +Z.
  const auto sets = segmentByNormal(part, all);
  ASSERT_EQ(sets.size(), 1u);
  EXPECT_EQ(sets.front(), all);

  // The patch follows the faces: every surface sample of the faces lies within the fit
  // tolerance of it, measured along the patch direction (never less than the distance).
  const InterpolatedPatch patch = interpolatedPatch(part, all, 20, 15, 0.05);
  EXPECT_GT(patch.frame.linear().col(2).z(), 0.95);
  EXPECT_LT(patch.max_deviation, 0.05);
  const Pose to_patch = patch.frame.inverse();
  double worst = 0;
  for (const Sample& s : sampleSurface(part, all, Role::Normal, TaskType::Surface)) {
    const Vec3 p = to_patch * s.position;
    worst = std::max(worst, std::abs(patch.height(p.x(), p.y()) - p.z()));
  }
  EXPECT_LT(worst, 0.05);

  // Exported as STEP and BREP, it reads back as faces over most of the panel.
  for (const std::string name : {"patch.step", "patch.brep"}) {
    writePatch(patchShape(patch), dir.file(name));
    const Part exported = importPart(dir.file(name));
    EXPECT_GT(exported.area(), 0.8 * part.area()) << name;
    EXPECT_LT(exported.area(), 1.01 * part.area()) << name;
  }

  // A surface plan sweeps the patch and measures what can be measured.
  std::string ids;
  for (int id : all) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
  const Spec spec = specWith("tasks:\n  - {type: surface, faces: [" + ids + "]}\n", dir);
  const Plan plan = planViews(part, spec, withoutRegistration());
  ASSERT_EQ(plan.sweeps.size(), 1u);
  ASSERT_TRUE(plan.sweeps.front().patch);
  EXPECT_FALSE(plan.sweeps.front().views.empty());
  const auto [can, measured] = coverableAndMeasured(part, plan);
  ASSERT_GT(can, 0u);
  EXPECT_GE(static_cast<double>(measured), 0.99 * static_cast<double>(can));

  // The library writes the plan with its patch beside it, named in plan.json, and removes
  // an earlier plan's patch files there.
  std::filesystem::create_directories(dir.file("out"));
  test::writeText(dir.file("out/patch-7.step"), "an earlier plan's patch");
  Plan written = plan;
  writePlanFiles(written, dir.file("out/plan.json"));
  EXPECT_EQ(written.sweeps.front().patch_file, "patch-1.step");
  EXPECT_EQ(readPlan(dir.file("out/plan.json")).part_faces, part.faces.size());
  EXPECT_EQ(planJson(written)["sweeps"][0]["patch"]["file"], "patch-1.step");
  EXPECT_GT(importPart(dir.file("out/patch-1.step")).area(), 0.8 * part.area());
  EXPECT_FALSE(std::filesystem::exists(dir.file("out/patch-7.step")));
}

}  // namespace
}  // namespace scanplan

namespace scanplan {
namespace {

// The 1.9 m sheet-metal base plate: a surface plan of its largest face, resting flat. Of
// every fourth of its 4,333 samples, those the dense reference reaches are measured.
TEST(Sweep, SheetMetalBasePlate) {
  SHARED_DATA_OR_SKIP(path, "mech/asitx_sheetmetal_base_plate_46004-252-23D.stp");
  const Part part = importPart(path);
  // Its largest face facing up when it rests on its steadiest side.
  const Pose rest = restOrientations(part).front().part_to_world;
  int largest = 0;
  for (const Face& face : part.faces) {
    const Vec3 up = rest.linear() * part.mesh.normal(face.first_triangle);
    if (up.z() > 0.99 && (largest == 0 || face.area > part.face(largest).area)) largest = face.id;
  }
  ASSERT_GT(largest, 0);
  test::TempDir dir;
  const Spec spec = specWith(
      "part: {rest: auto}\ntasks:\n  - {type: surface, faces: [" + std::to_string(largest) + "]}\n",
      dir);
  const Plan plan = planViews(part, spec, withoutRegistration());
  ASSERT_EQ(plan.sweeps.size(), 1u);
  const auto [can, measured] = coverableAndMeasured(part, plan, 4);
  ASSERT_GT(can, 1000u);
  EXPECT_GE(static_cast<double>(measured), 0.95 * static_cast<double>(can));
}

}  // namespace
}  // namespace scanplan
