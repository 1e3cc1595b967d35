// The registration-aware cover joins groups it left apart through a connector pose, or a
// chain of them: on a plate studded with pyramids, two clusters of samples too far apart for
// one view, and poses between them that measure nothing new but overlap stably.

#include "planning/stages.h"
#include "registration/overlaps.h"
#include "support.h"

#include <scanplan/planning/bridging.h>
#include <scanplan/planning/poses.h>
#include <scanplan/scanner/visibility.h>

#include <algorithm>
#include <map>
#include <mutex>
#include <string>

namespace scanplan {
namespace {

// The whole cover at one view a pose: what the selection aims at by default.
detail::SelectionAim everySample(const detail::Placement& at, const detail::MeasuredViews& pool,
                                 const std::vector<PlannedSample>& samples) {
  return {detail::coverageNeed(at, pool, 0, samples), std::vector<double>(pool.size(), 1.0)};
}

// Adds a square pyramid of 45° sides on the plate's top, its base from `lo` 30 mm wide.
void addPyramid(TriangleMesh& mesh, const Vec3& lo, int face) {
  const int base = static_cast<int>(mesh.vertices.size());
  for (const Vec3& corner : {Vec3(0, 0, 0), Vec3(30, 0, 0), Vec3(30, 30, 0), Vec3(0, 30, 0)})
    mesh.vertices.push_back(lo + corner);
  mesh.vertices.push_back(lo + Vec3(15, 15, 15));
  for (int k = 0; k < 4; ++k) {
    mesh.triangles.emplace_back(base + k, base + (k + 1) % 4, base + 4);
    mesh.triangle_faces.push_back(face);
  }
}

// A `length` x 300 x 10 mm plate with pyramids on it every 50 mm: any overlap of views from
// above is constrained in every direction.
Part studdedPlate(double length = 700) {
  TriangleMesh mesh;
  int face = 1;
  test::addRectangle(mesh, Vec3(length / 2, 150, 10), Vec3(length / 2, 0, 0), Vec3(0, 150, 0),
                     face++);
  for (double x = 10; x < length; x += 50)
    for (double y = 10; y < 300; y += 50) addPyramid(mesh, Vec3(x, y, 10), face++);
  return test::meshPart(mesh);
}

// A view straight down on `(x, y)` of the plate's top, its width along x.
View above(const Scanner& scanner, double x, double y) {
  return aimedPoses(scanner, Vec3(x, y, 10), Vec3::UnitZ(), 1).front();
}

// Samples on the studded plate's top between the pyramids (whose bases span x and y of
// 10 to 40 mm, every 50 mm), none measured yet.
std::vector<PlannedSample> plateSamples(const std::vector<Vec3>& positions) {
  std::vector<PlannedSample> samples;
  for (const Vec3& p : positions) {
    PlannedSample s;
    s.sample.position = p;
    s.sample.normal = Vec3::UnitZ();
    s.sample.face = 1;
    samples.push_back(s);
  }
  return samples;
}

std::vector<SurfacePoint> pointsOf(const std::vector<PlannedSample>& samples) {
  std::vector<SurfacePoint> points;
  for (const PlannedSample& s : samples) points.push_back({s.sample.position, Vec3::UnitZ(), 1});
  return points;
}

// Samples on the plate between the pyramids: cluster A about x = 150, cluster B about
// x = 550, one of each within the connector's reach; one sample only A reaches, one only
// a view of A shifted along y (A2) reaches. Markers that A and A2 both see, C none. The
// pool: A, A2, B, and the connector C between A and B, which measures nothing the others
// miss.
struct TwoClusters {
  TwoClusters()
      : part(studdedPlate()),
        spec(resolveSpec(part, defaultSpec())),
        simulator(part, spec.spec.scanner),
        samples(plateSamples({Vec3(50, 150, 10), Vec3(100, 150, 10), Vec3(150, 150, 10),
                              Vec3(250, 150, 10), Vec3(150, 280, 10), Vec3(450, 150, 10),
                              Vec3(550, 150, 10), Vec3(600, 150, 10), Vec3(650, 150, 10),
                              Vec3(150, 50, 10)})),
        at{part, spec, simulator, CellCheck{}, pointsOf(samples), {}} {
    for (const Vec3& p :
         {Vec3(50, 100, 10), Vec3(100, 200, 10), Vec3(150, 100, 10), Vec3(50, 200, 10)})
      markers.push_back({p, Vec3::UnitZ()});
    const Scanner& scanner = simulator.scanner();
    const std::vector<View> views = {above(scanner, 150, 150), above(scanner, 150, 180),
                                     above(scanner, 550, 150), above(scanner, 350, 150)};
    const auto measured = measuredPoints(simulator, views, at.points);
    for (std::size_t v = 0; v < views.size(); ++v) pool.add(views[v], measured[v]);
  }

  const Part part;
  const ResolvedSpec spec;
  const Simulator simulator;
  const std::vector<PlannedSample> samples;
  const detail::Placement at;
  std::vector<Marker> markers;
  detail::MeasuredViews pool;
};

TEST(ConnectedCover, JoinsTwoGroupsThroughAConnectorAndStopsWhereATargetIsMet) {
  const TwoClusters c;
  const Simulator& simulator = c.simulator;
  const detail::Placement& at = c.at;
  const detail::MeasuredViews& pool = c.pool;
  const std::vector<PlannedSample>& samples = c.samples;
  const std::vector<Marker>& markers = c.markers;
  ASSERT_EQ(simulator.scanner().fov_width, 300);
  ASSERT_EQ(pool.samples[0], (std::vector<int>{0, 1, 2, 3, 9}));
  ASSERT_EQ(pool.samples[1], (std::vector<int>{0, 1, 2, 3, 4}));
  ASSERT_EQ(pool.samples[2], (std::vector<int>{5, 6, 7, 8}));
  ASSERT_EQ(pool.samples[3], (std::vector<int>{3, 5}));

  // A first, A2 registering to it by the markers, then B on its own: no pose with
  // anything new registers to A or A2. C joins B to them.
  std::vector<std::size_t> cover =
      detail::connectedCover(at, pool, 0, samples, everySample(at, pool, samples), markers, {});
  std::sort(cover.begin(), cover.end());
  EXPECT_EQ(cover, (std::vector<std::size_t>{0, 1, 2, 3})) << ::testing::PrintToString(cover);

  // The registration stage registers all of them to one another.
  std::vector<View> chosen;
  for (std::size_t v : cover) chosen.push_back(pool.views[v]);
  for (std::size_t k = 0; k < chosen.size(); ++k) chosen[k].id = static_cast<int>(k + 1);
  RegistrationOptions options = registrationOptions(c.spec.spec);
  options.bridging = false;
  const Registration registration =
      registerWithBridging(simulator, chosen, markers, options, {}, {});
  EXPECT_EQ(registration.registered(), chosen.size());

  // Six of the ten samples: A, then A2 registering to it by the markers; B and C are not
  // needed.
  detail::SelectionAim six = everySample(at, pool, samples);
  std::fill(six.needs.need.begin(), six.needs.need.end(), 0.0);
  six.needs.need[six.needs.group[0]] = 6;
  EXPECT_EQ(detail::connectedCover(at, pool, 0, samples, six, markers, {}),
            (std::vector<std::size_t>{0, 1}));
}

// A sample the aim does not ask for gains a pose nothing (planner.aim characteristics asks
// only for the faces its characteristics are judged on): asked for B's four samples and for
// sample 3, the cover is B, which measures the four, and C, which registers to B by markers
// both see and measures 3; not A, which measures 3 and four samples more, none of them asked
// for, nor A2.
TEST(ConnectedCover, SamplesNothingAsksForGainNothing) {
  TwoClusters c;
  for (const Vec3& p : {Vec3(450, 100, 10), Vec3(450, 200, 10), Vec3(500, 150, 10)})
    c.markers.push_back({p, Vec3::UnitZ()});
  detail::SelectionAim asked = everySample(c.at, c.pool, c.samples);
  ASSERT_GT(asked.needs.need.size(), 1u);
  for (std::size_t i = 0; i < c.samples.size(); ++i)
    asked.needs.group[i] = i == 3 ? 1 : (i >= 5 && i <= 8 ? 0 : -1);
  std::fill(asked.needs.need.begin(), asked.needs.need.end(), 0.0);
  asked.needs.need[0] = 4;
  asked.needs.need[1] = 1;
  std::vector<std::size_t> cover =
      detail::connectedCover(c.at, c.pool, 0, c.samples, asked, c.markers, {});
  std::sort(cover.begin(), cover.end());
  EXPECT_EQ(cover, (std::vector<std::size_t>{2, 3}));
}

// The chain case: a 1000 mm studded plate, samples on the four sides of five rows of pyramids
// and on the plate between them, pending about A (x < 170) and B (x > 830) and measured before
// in between, so that the poses between A and B measure nothing new. The last row is beyond
// the reach of views along y = 150. The pool: A, B, three poses 175 mm apart between them
// (each overlaps the next, none both A and B, and so no single connector joins them), and
// A2 beside A, which measures the last row there.
struct ChainPlate {
  explicit ChainPlate(double tolerance = 0)
      : part(studdedPlate(1000)),
        spec(withTolerance(resolveSpec(part, defaultSpec()), tolerance)),
        simulator(part, spec.spec.scanner) {
    for (double x = 10; x < 1000; x += 50)
      for (double y : {60.0, 110.0, 160.0, 210.0, 260.0})
        for (const auto& [at, normal] :
             {std::pair{Vec3(15, 5, 5), Vec3(0, -1, 1)}, std::pair{Vec3(5, 15, 5), Vec3(-1, 0, 1)},
              std::pair{Vec3(15, 25, 5), Vec3(0, 1, 1)}, std::pair{Vec3(25, 15, 5), Vec3(1, 0, 1)},
              std::pair{Vec3(40, 40, 0), Vec3(0, 0, 1)}}) {
          PlannedSample s;
          s.sample.position = Vec3(x, y, 10) + at;
          s.sample.normal = normal.normalized();
          s.sample.face = 1;
          s.sample.weight = 100;
          samples.push_back(s);
          points.push_back({s.sample.position, s.sample.normal, 1});
          done.push_back(x + at.x() >= 170 && x + at.x() <= 830);
        }
    const Scanner& scanner = simulator.scanner();
    const std::vector<View> views = {above(scanner, 150, 150), above(scanner, 850, 150),
                                     above(scanner, 325, 150), above(scanner, 500, 150),
                                     above(scanner, 675, 150), above(scanner, 150, 260)};
    const auto measured = measuredPoints(simulator, views, points);
    for (std::size_t v = 0; v < views.size(); ++v) pool.add(views[v], measured[v]);
  }

  // `spec` with the registration's tolerance `tolerance` (0: as it is).
  static ResolvedSpec withTolerance(ResolvedSpec spec, double tolerance) {
    if (tolerance > 0) spec.spec.registration.tolerance = tolerance;
    return spec;
  }

  // How many samples pool poses `a` and `b` both measure.
  std::size_t shares(std::size_t a, std::size_t b) const {
    std::vector<int> both;
    std::set_intersection(pool.samples[a].begin(), pool.samples[a].end(), pool.samples[b].begin(),
                          pool.samples[b].end(), std::back_inserter(both));
    return both.size();
  }

  // The connected cover, sorted.
  std::vector<std::size_t> cover(const Progress& progress = {}) const {
    const detail::Placement at{part, spec, simulator, CellCheck{}, points, done};
    std::vector<std::size_t> chosen =
        detail::connectedCover(at, pool, 0, samples, everySample(at, pool, samples), {}, progress);
    std::sort(chosen.begin(), chosen.end());
    return chosen;
  }

  Part part;
  ResolvedSpec spec;
  Simulator simulator;
  std::vector<PlannedSample> samples;
  std::vector<SurfacePoint> points;
  std::vector<char> done;
  detail::MeasuredViews pool;
};

TEST(ConnectedCover, JoinsTwoGroupsThroughAChain) {
  const ChainPlate plate;
  for (std::size_t v = 2; v < 5; ++v)
    ASSERT_FALSE(plate.shares(0, v) > 0 && plate.shares(1, v) > 0);
  ASSERT_GE(plate.shares(0, 2), 6u);
  ASSERT_GE(plate.shares(2, 3), 6u);
  ASSERT_GE(plate.shares(3, 4), 6u);
  ASSERT_GE(plate.shares(4, 1), 6u);

  // A with A2 registering to it, and B on its own; the chain of the three joins them.
  const std::vector<std::size_t> cover = plate.cover();
  EXPECT_EQ(cover, (std::vector<std::size_t>{0, 1, 2, 3, 4, 5})) << ::testing::PrintToString(cover);

  // The registration stage registers all of them to one another by their geometry.
  std::vector<View> chosen;
  for (std::size_t v : cover) chosen.push_back(plate.pool.views[v]);
  for (std::size_t k = 0; k < chosen.size(); ++k) chosen[k].id = static_cast<int>(k + 1);
  RegistrationOptions options = registrationOptions(plate.spec.spec);
  options.bridging = false;
  const Registration registration =
      registerWithBridging(plate.simulator, chosen, {}, options, {}, {});
  EXPECT_EQ(registration.registered(), chosen.size());
}

// Progress shows the share of the samples covered, growing to the end, then the groups
// apart joined.
TEST(ConnectedCover, ShowsProgress) {
  const ChainPlate plate;
  std::map<std::string, std::vector<double>> shown;  // per stage
  std::mutex mutex;
  plate.cover([&](std::string_view stage, double fraction) {
    const std::lock_guard lock(mutex);
    shown[std::string(stage)].push_back(fraction);
  });
  const std::vector<double>& covering = shown["selection: covering the samples"];
  ASSERT_FALSE(covering.empty());
  EXPECT_TRUE(std::is_sorted(covering.begin(), covering.end()));
  EXPECT_DOUBLE_EQ(covering.back(), 1);
  EXPECT_EQ(shown["selection: joining 1 group apart"], (std::vector<double>{0, 1}));
}

// With a tolerance no ICP check can meet, every chain the search finds fails verification:
// the search goes on around the failed links, ends, and adds no pose.
TEST(ConnectedCover, AddsNoChainWhoseLinksFailIcp) {
  const ChainPlate plate(1e-6);
  EXPECT_EQ(plate.cover(), (std::vector<std::size_t>{0, 1, 5}))
      << ::testing::PrintToString(plate.cover());
}

// The rescue pass over three samples of the studded plate, with the planner's settings
// of `settings`.
struct PlateRescue {
  PlateRescue(const Part& part, const Spec& settings)
      : spec(resolveSpec(part, settings)),
        simulator(part, spec.spec.scanner),
        samples(plateSamples({Vec3(50, 50, 10), Vec3(350, 150, 10), Vec3(650, 250, 10)})),
        at{part, spec, simulator, CellCheck{}, pointsOf(samples), {}} {
    detail::rescueViews(at, samples, added);
  }
  const ResolvedSpec spec;
  const Simulator simulator;
  std::vector<PlannedSample> samples;
  const detail::Placement at;
  detail::MeasuredViews added;
};

// The rescue pass gives each sample left a view that measures it: every sample of the plate
// ends measured, and each view added measures, simulated again, the samples it is said to.
TEST(Stages, RescueMeasuresEverySampleADensePoseCanMeasure) {
  const Part part = studdedPlate();
  const PlateRescue rescue(part, defaultSpec());
  for (const PlannedSample& s : rescue.samples)
    EXPECT_FALSE(s.measured_by.empty()) << s.sample.position.transpose();
  ASSERT_FALSE(rescue.added.views.empty());
  for (std::size_t v = 0; v < rescue.added.size(); ++v)
    EXPECT_EQ(rescue.added.samples[v],
              detail::measuredBy(rescue.simulator, rescue.added.views[v], rescue.at.points))
        << v;
}

// planner.rescue sets the rescue's search: each view it adds looks along a direction of
// the grid of `planner.rescue.step`, and another step gives other views.
TEST(Stages, RescueTriesTheDirectionsOfItsStep) {
  const Part part = studdedPlate();
  std::map<double, std::vector<Vec3>> axes;  // per step, the added views' directions
  for (const double step : {10.0, 25.0}) {
    Spec settings = defaultSpec();
    settings.planner.rescue_step = step;
    settings.planner.rescue_rotations = 1;
    const PlateRescue rescue(part, settings);
    ASSERT_EQ(rescue.added.size(), 3u) << step;
    const VisibilityMap grid(step);
    for (const View& view : rescue.added.views) {
      const Vec3 back = -view.camera_to_world.linear().col(2);  // the target to the camera
      double nearest = -1;
      for (int c = 0; c < grid.cells(); ++c)
        nearest = std::max(nearest, back.dot(grid.direction(c)));
      EXPECT_GT(nearest, 1 - 1e-9) << "step " << step << ": " << back.transpose();
      axes[step].push_back(back);
    }
  }
  bool differ = false;
  for (std::size_t k = 0; k < 3; ++k) differ = differ || axes[10][k].dot(axes[25][k]) < 1 - 1e-6;
  EXPECT_TRUE(differ);
}

// A pose that sees no marker, shifted across its axis towards three just outside its
// field, is added to the pool: moved no more than half the field of view, seeing the three
// (simulated again) and still measuring the samples near its target.
TEST(Stages, MarkerShiftMovesAPoseUntilItSeesEnoughMarkers) {
  const Part part = studdedPlate();
  const ResolvedSpec spec = resolveSpec(part, defaultSpec());
  const Simulator simulator(part, spec.spec.scanner);
  const Scanner& scanner = simulator.scanner();
  const std::vector<PlannedSample> samples =
      plateSamples({Vec3(150, 150, 10), Vec3(200, 150, 10), Vec3(150, 100, 10)});
  const detail::Placement at{part, spec, simulator, CellCheck{}, pointsOf(samples), {}};
  const View pose = above(scanner, 160, 150);
  detail::MeasuredViews pool;
  pool.add(pose, detail::measuredBy(simulator, pose, at.points));
  ASSERT_EQ(pool.samples[0], (std::vector<int>{0, 1, 2}));
  std::vector<Marker> markers;
  for (const Vec3& p : {Vec3(350, 100, 10), Vec3(400, 150, 10), Vec3(350, 200, 10)})
    markers.push_back({p, Vec3::UnitZ()});
  const std::vector<SurfacePoint> marker_points = detail::markerPoints(markers);
  ASSERT_TRUE(detail::measuredBy(simulator, pose, marker_points).empty());
  detail::addMarkerShifts(at, pool, markers, {});
  ASSERT_EQ(pool.size(), 2u);
  const View& shifted = pool.views[1];
  const double moved = (shifted.target - pose.target).norm();
  EXPECT_GT(moved, 0);
  EXPECT_LE(moved, scanner.fov_width / 2 + 1e-9);
  EXPECT_EQ(detail::measuredBy(simulator, shifted, marker_points), (std::vector<int>{0, 1, 2}));
  EXPECT_EQ(pool.samples[1], detail::measuredBy(simulator, shifted, at.points));
  for (int i : {0, 1, 2}) {
    if ((at.points[i].position - pose.target).norm() > scanner.fov_height / 4) continue;
    EXPECT_TRUE(std::count(pool.samples[1].begin(), pool.samples[1].end(), i)) << i;
  }
}

// Framed poses: of two samples a metre apart on the plate, the first has three markers 200
// to 240 mm away, beyond the field of the pose above it but within that of a pose with the
// sample off its centre; the second has them 610 mm away, farther than the measuring
// volume's diameter (about 510 mm), so no pose measures it while seeing them. Poses that
// measure the first and see all three markers (simulated again) are added, at most four,
// and none for the second.
TEST(Stages, FramedPosesMeasureTheirSampleWhileSeeingTheMarkers) {
  const Part part = studdedPlate(1000);
  Spec settings = defaultSpec();
  settings.registration.method = RegistrationMode::ReferencePoints;
  const ResolvedSpec spec = resolveSpec(part, settings);
  const Simulator simulator(part, spec.spec.scanner);
  const std::vector<PlannedSample> samples = plateSamples({Vec3(100, 150, 10), Vec3(950, 150, 10)});
  const detail::Placement at{part, spec, simulator, CellCheck{}, pointsOf(samples), {}};
  std::vector<Marker> markers;
  for (const Vec3& p : {Vec3(300, 100, 10), Vec3(340, 150, 10), Vec3(300, 200, 10)})
    markers.push_back({p, Vec3::UnitZ()});
  const std::vector<SurfacePoint> marker_points = detail::markerPoints(markers);
  detail::MeasuredViews pool;
  for (const double x : {100.0, 950.0}) {
    const View pose = above(simulator.scanner(), x, 150);
    ASSERT_TRUE(detail::measuredBy(simulator, pose, marker_points).empty()) << x;
    pool.add(pose, detail::measuredBy(simulator, pose, at.points));
  }
  ASSERT_EQ(pool.samples[0], std::vector<int>{0});
  ASSERT_EQ(pool.samples[1], std::vector<int>{1});
  detail::addFramedPoses(at, pool, markers, std::vector<char>(pool.size(), 0), {});
  ASSERT_GT(pool.size(), 2u);
  EXPECT_LE(pool.size(), 2u + 4u);
  for (std::size_t v = 2; v < pool.size(); ++v) {
    const View& pose = pool.views[v];
    EXPECT_EQ(detail::measuredBy(simulator, pose, marker_points), (std::vector<int>{0, 1, 2}));
    EXPECT_EQ(pool.samples[v], detail::measuredBy(simulator, pose, at.points));
    EXPECT_EQ(pool.samples[v], std::vector<int>{0});
  }
}

}  // namespace
}  // namespace scanplan
