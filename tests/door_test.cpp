// The car-door case (bench/door_panel.h) at a test's size: a door-like panel of about 300
// B-spline faces in a marker frame, its 107 control points planned with the markers on
// the frame; what the plan claims checked by simulating its views again.

#include "door_panel.h"
#include "plan_support.h"
#include "registration/overlaps.h"

#include <scanplan/cad/import.h>
#include <scanplan/io/spec_yaml.h>

#include <map>

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
      simulationOptionsFor(resolveSpec(part, loadSpec(door.spec)), part, plan.part_to_world);
  const Simulator simulator(part, plan.scanner, placed);
  const std::vector<SurfacePoint> points = plan.samplePoints();
  const std::vector<char> coverable = coverableByDenseCandidates(simulator, points);
  EXPECT_EQ(std::count(coverable.begin(), coverable.end(), 1),
            static_cast<std::ptrdiff_t>(points.size()));
  // The plan's views, simulated again, measure every one of them.
  EXPECT_EQ(points.size(), 107u);
  const auto losses = simulator.measure(plan.views, points);
  for (std::size_t i = 0; i < points.size(); ++i) {
    bool measured = false;
    for (std::size_t v = 0; v < plan.views.size(); ++v)
      measured = measured || losses[v][i] == Loss::Measured;
    EXPECT_TRUE(measured) << "control point " << i;
  }
  EXPECT_EQ(plan.resultsRow().fixture_faces, 10u);

  // At least 95% of the views register by the markers on the frame: each one registered
  // by markers sees, simulated again, three or more of the markers its partner sees.
  ASSERT_TRUE(plan.registration);
  const std::vector<SurfacePoint> markers = detail::markerPoints(plan.markers);
  const auto seen = simulator.measure(plan.views, markers);
  std::map<int, std::size_t> index;
  for (std::size_t v = 0; v < plan.views.size(); ++v) index[plan.views[v].id] = v;
  std::size_t by_markers = 0;
  for (std::size_t v = 0; v < plan.views.size(); ++v) {
    const ViewRegistration& r = plan.registration->views[v];
    if (r.method == RegistrationMethod::Reference) ++by_markers;
    if (r.method != RegistrationMethod::Markers) continue;
    std::size_t shared = 0;
    for (std::size_t m = 0; m < markers.size(); ++m)
      shared += seen[v][m] == Loss::Measured && seen[index.at(r.to)][m] == Loss::Measured;
    EXPECT_GE(shared, 3u) << "view " << plan.views[v].id << " to " << r.to;
    by_markers += shared >= 3;
  }
  EXPECT_GE(static_cast<double>(by_markers), 0.95 * static_cast<double>(plan.views.size()))
      << by_markers << " of " << plan.views.size();
}

}  // namespace
}  // namespace scanplan
