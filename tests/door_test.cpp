// The car-door case (bench/door_panel.h) at a test's size: a door-like panel of about 300
// B-spline faces in a marker frame, its 107 control points planned with the markers on
// the frame.

#include "door_panel.h"
#include "plan_support.h"

#include <scanplan/cad/import.h>
#include <scanplan/io/spec_yaml.h>

namespace scanplan {
namespace {

TEST(Door, ControlPointsAllAcquiredAndViewsAlignableByTheFrameMarkers) {
  const test::TempDir dir;
  bench::DoorOptions options;
  options.width = 700;
  options.height = 400;
  options.columns = 24;
  options.rows = 16;
  const bench::DoorCase door = bench::writeDoorCase(dir.file(""), options);
  const Part part = importPart(door.part);
  EXPECT_EQ(part.faces.size(), static_cast<std::size_t>(door.faces));
  EXPECT_GT(door.faces, 250);
  const Plan plan = planViews(part, loadSpec(door.spec));

  // Every control point can be measured (an independent dense search), and is.
  SimulationOptions placed =
      simulationOptionsFor(resolveSpec(part, loadSpec(door.spec)), plan.part_to_world);
  const Simulator simulator(part, plan.scanner, placed);
  const std::vector<SurfacePoint> points = plan.samplePoints();
  const std::vector<char> coverable = coverableByDenseCandidates(simulator, points);
  EXPECT_EQ(std::count(coverable.begin(), coverable.end(), 1),
            static_cast<std::ptrdiff_t>(points.size()));
  const Plan::ResultsRow row = plan.resultsRow();
  EXPECT_TRUE(row.control_points);
  EXPECT_EQ(row.points, 107u);
  EXPECT_EQ(row.acquired, 107u);
  EXPECT_EQ(row.fixture_faces, 10u);

  // At least 95% of the views register by the markers on the frame.
  ASSERT_TRUE(plan.registration);
  std::size_t by_markers = 0;
  for (const ViewRegistration& v : plan.registration->views)
    by_markers +=
        v.method == RegistrationMethod::Markers || v.method == RegistrationMethod::Reference;
  EXPECT_GE(static_cast<double>(by_markers), 0.95 * static_cast<double>(plan.views.size()))
      << by_markers << " of " << plan.views.size();
  EXPECT_EQ(row.alignable, plan.registration->registered());
}

}  // namespace
}  // namespace scanplan
