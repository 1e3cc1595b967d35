// The planner's aim at characteristics (planner.aim: characteristics, docs/planning.md,
// "Aim"), against the capability model judged by brute force over a small pool of poses.

#include "hole_plate.h"
#include "planning/stages.h"
#include "support.h"

#include <scanplan/planning/capability.h>
#include <scanplan/planning/poses.h>
#include <scanplan/sampling/sampling.h>
#include <scanplan/spec/spec.h>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <map>
#include <optional>
#include <set>
#include <vector>

namespace scanplan {
namespace {

constexpr double kThickness = 5;  // a plate thin enough for tilted views to see the hole

// The plate's GD&T as its file gives it: the hole's position to A, B, C and the top's
// flatness.
test::HolePlate plateWithGdt(const test::TempDir& dir) {
  test::HolePlate p = test::holePlate(dir, kThickness);
  p.part.gdt.tolerances = {{"position", 0.5, {"A", "B", "C"}, p.hole},
                           {"flatness", 0.1, {}, {p.top}}};
  return p;
}

// Ten poses: straight above the plate's middle and above either half, four tilted 45° at
// the hole from +-x and +-y, one at each datum side (x = 0, y = 0) and at the far sides.
std::vector<View> smallPool(const Scanner& scanner) {
  std::vector<View> poses;
  const auto aim = [&](const Vec3& target, const Vec3& direction) {
    poses.push_back(aimedPoses(scanner, target, direction.normalized(), 1).front());
  };
  const Vec3 hole(100, 50, kThickness);
  aim(hole, Vec3::UnitZ());
  aim(Vec3(50, 50, kThickness), Vec3::UnitZ());
  aim(Vec3(150, 50, kThickness), Vec3::UnitZ());
  for (const Vec3& d : {Vec3(1, 0, 1), Vec3(-1, 0, 1), Vec3(0, 1, 1), Vec3(0, -1, 1)}) aim(hole, d);
  aim(Vec3(0, 50, kThickness / 2), Vec3(-1, 0, 0.6));
  aim(Vec3(100, 0, kThickness / 2), Vec3(0, -1, 0.6));
  aim(Vec3(200, 50, kThickness / 2), Vec3(1, 0, 0.6));
  return poses;
}

// What the planner plans the plate for, aiming at its characteristics: its characteristics' and
// datums' faces as the gdt task's targets, and the far side x = 200, which no characteristic needs.
Spec plateSpec(const test::HolePlate& p) {
  Spec spec = defaultSpec();
  spec.planner.aim = Aim::Characteristics;
  spec.planner.capability.draws = 50;
  Task gdt{TaskType::Gdt, {}, {}, {}};
  for (int face : p.hole) gdt.faces.push_back({face, {}, {}});
  for (int face : {p.top, p.side_x, p.side_y}) gdt.faces.push_back({face, {}, {}});
  for (const Face& f : p.part.faces)
    if (f.bounds.min.x() > 199.99) gdt.faces.push_back({f.id, {}, {}});
  spec.tasks = {gdt};
  return spec;
}

// Whether every characteristic of the plate is capable under the views `chosen` of
// `pool`, placed without registration error.
bool allCapable(const test::HolePlate& p, const ResolvedSpec& spec,
                const detail::MeasuredViews& pool, const std::vector<std::size_t>& chosen) {
  Plan plan;
  plan.scanner = spec.spec.scanner;
  for (std::size_t k = 0; k < chosen.size(); ++k) {
    View view = pool.views[chosen[k]];
    view.id = static_cast<int>(k) + 1;
    plan.views.push_back(view);
  }
  const std::vector<Capability> judged =
      capabilities(p.part, spec, plan, characteristics(p.part.gdt));
  return std::all_of(judged.begin(), judged.end(),
                     [](const Capability& k) { return k.verdict == Verdict::Capable; });
}

// The fewest views of `pool` under which every characteristic is capable, by trying every
// subset of each size in turn; nullopt when none is.
std::optional<std::size_t> fewestCapable(const test::HolePlate& p, const ResolvedSpec& spec,
                                         const detail::MeasuredViews& pool) {
  std::vector<std::size_t> chosen;
  const std::function<bool(std::size_t, std::size_t)> some = [&](std::size_t from,
                                                                 std::size_t left) {
    if (left == 0) return allCapable(p, spec, pool, chosen);
    for (std::size_t v = from; v + left <= pool.size(); ++v) {
      chosen.push_back(v);
      const bool found = some(v + 1, left - 1);
      chosen.pop_back();
      if (found) return true;
    }
    return false;
  };
  for (std::size_t size = 1; size <= pool.size(); ++size)
    if (some(0, size)) return size;
  return std::nullopt;
}

// The plate's samples, the small pool and the stages' view of them.
struct PlatePlanning {
  PlatePlanning(const test::HolePlate& p, const ResolvedSpec& spec)
      : simulator(p.part, spec.spec.scanner),
        samples(samplesOf(p, spec)),
        at{p.part, spec, simulator, CellCheck{}, pointsOf(samples), {}},
        pool(detail::candidatePool(at, {}, smallPool(spec.spec.scanner), {})) {}

  static std::vector<PlannedSample> samplesOf(const test::HolePlate& p, const ResolvedSpec& spec) {
    std::vector<PlannedSample> samples;
    for (const Sample& s :
         sampleTargets(p.part, spec.targets, samplingOptionsFor(spec.spec.scanner)))
      samples.push_back({s, {}, {}, {}});
    return samples;
  }
  static std::vector<SurfacePoint> pointsOf(const std::vector<PlannedSample>& samples) {
    Plan plan;
    plan.samples = samples;
    return plan.samplePoints();
  }

  const Simulator simulator;
  const std::vector<PlannedSample> samples;
  const detail::Placement at;
  const detail::MeasuredViews pool;
};

// The plate with its GD&T planned under planner.aim characteristics, the small pool, and
// the fewest views of it under which every characteristic is capable, by brute force:
// made once for the suite.
class Aim : public ::testing::Test {
 protected:
  struct Shared {
    Shared()
        : plate(plateWithGdt(dir)),
          spec(resolveSpec(plate.part, plateSpec(plate))),
          planning(plate, spec),
          fewest(fewestCapable(plate, spec, planning.pool)) {}
    test::TempDir dir;
    const test::HolePlate plate;
    const ResolvedSpec spec;
    const PlatePlanning planning;
    const std::optional<std::size_t> fewest;
  };
  static void SetUpTestSuite() { shared_ = new Shared(); }
  static void TearDownTestSuite() {
    delete shared_;
    shared_ = nullptr;
  }

  const test::HolePlate& p = shared_->plate;
  const ResolvedSpec& spec = shared_->spec;
  const PlatePlanning& planning = shared_->planning;
  const detail::MeasuredViews& pool = planning.pool;
  const std::optional<std::size_t>& fewest = shared_->fewest;

 private:
  static inline Shared* shared_ = nullptr;
};

// Under planner.aim characteristics the selection takes the fewest views of the pool with
// which the capability model judges the hole's position and the top's flatness capable:
// the minimum a brute force over every subset of the pool finds.
TEST_F(Aim, CharacteristicsTakeTheFewestViewsThatMakeEveryCharacteristicCapable) {
  ASSERT_EQ(pool.size(), 10u);
  const std::vector<std::size_t> chosen =
      detail::selectViews(planning.at, pool, 0, planning.samples, std::nullopt, {}, {}).views;
  ASSERT_TRUE(fewest.has_value());
  EXPECT_TRUE(allCapable(p, spec, pool, chosen));
  EXPECT_EQ(chosen.size(), *fewest);

  RecordProperty("views_and_fewest",
                 std::to_string(chosen.size()) + " and " + std::to_string(*fewest));
}

// Markers every 20 mm on the working plane around the plate, where every pose of the small
// pool sees enough of them to register.
std::vector<Marker> markersAroundThePlate() {
  std::vector<Marker> markers;
  for (double x = -60; x <= 260; x += 20)
    for (double y = -60; y <= 160; y += 20)
      if (x < -5 || x > 205 || y < -5 || y > 105) markers.push_back({Vec3(x, y, 0)});
  return markers;
}

// With registration, as plans are made by default, the selection is the registration-aware
// cover: with markers that every pose sees, it too takes the fewest views of the pool with
// which every characteristic is capable, as the brute force finds.
TEST_F(Aim, RegisteredCharacteristicsTakeTheFewestViewsThatMakeEveryCharacteristicCapable) {
  ASSERT_EQ(pool.size(), 10u);
  const detail::SelectionAim aim{detail::coverageNeed(planning.at, pool, 0, planning.samples),
                                 std::vector<double>(pool.size(), 1.0)};
  const std::vector<std::size_t> chosen = detail::connectedCover(
      planning.at, pool, 0, planning.samples, aim, markersAroundThePlate(), {});
  ASSERT_TRUE(fewest.has_value());
  ASSERT_FALSE(chosen.empty());  // the views register to one another
  EXPECT_TRUE(allCapable(p, spec, pool, chosen));
  EXPECT_EQ(chosen.size(), *fewest);
}

// What the selection asks under planner.aim characteristics, counted by hand over the
// samples the pool measures: nine in ten of each hole face's and of the top's (the
// position's and the flatness's faces), half of each datum side's, and none of the far
// side's, which no characteristic needs.
TEST_F(Aim, EachCharacteristicsFaceNeedsNineTenthsOfItsSamplesAndEachDatumSideHalf) {
  std::map<int, int> coverable;  // per face, the samples some pose of the pool measures
  std::set<int> measured;
  for (const std::vector<int>& samples : planning.pool.samples)
    measured.insert(samples.begin(), samples.end());
  for (int i : measured) ++coverable[planning.samples[i].sample.face];
  const detail::CoverageNeed need =
      detail::coverageNeed(planning.at, planning.pool, 0, planning.samples);
  std::map<int, double> asked;  // per face, the need of its samples' group
  for (std::size_t i = 0; i < planning.samples.size(); ++i) {
    const int face = planning.samples[i].sample.face;
    const int group = need.group[i];
    if (group < 0) {
      asked.emplace(face, 0);
      continue;
    }
    const auto [it, added] = asked.emplace(face, need.need[group]);
    EXPECT_TRUE(added || it->second == need.need[group]) << "face " << face << " in two groups";
  }
  std::vector<int> own = p.hole;
  own.push_back(p.top);
  for (int face : own) EXPECT_EQ(asked[face], std::ceil(0.9 * coverable[face])) << face;
  for (int face : {p.side_x, p.side_y})
    EXPECT_EQ(asked[face], std::ceil(0.5 * coverable[face])) << face;
  int far = 0;
  for (const Face& f : p.part.faces)
    if (f.bounds.min.x() > 199.99) far = f.id;
  ASSERT_GT(coverable[far], 0);
  EXPECT_EQ(asked[far], 0);
}

}  // namespace
}  // namespace scanplan
