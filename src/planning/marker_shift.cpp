// Target shift towards markers (docs/planning.md): poses of the pool that see too few
// markers to register by, moved across their axis until they take in enough, while they
// still measure every sample they measured.

#include "planning/stages.h"
#include "registration/overlaps.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>

namespace scanplan::detail {
namespace {

// Shifts tried per pose, smallest first, after the quick count.
constexpr std::size_t kTries = 6;
// Steps of the shifts per field of view.
constexpr int kSteps = 16;

// Shifts across the axis, in the camera's x and y: a grid of a sixteenth of the field of
// view out to half of it each way, smallest first, without the null shift.
std::vector<Vec3> shiftGrid(const Scanner& scanner) {
  std::vector<Vec3> shifts;
  for (int i = -kSteps / 2; i <= kSteps / 2; ++i)
    for (int j = -kSteps / 2; j <= kSteps / 2; ++j)
      if (i != 0 || j != 0)
        shifts.emplace_back(i * scanner.fov_width / kSteps, j * scanner.fov_height / kSteps, 0);
  std::stable_sort(shifts.begin(), shifts.end(),
                   [](const Vec3& a, const Vec3& b) { return a.norm() < b.norm(); });
  return shifts;
}

class MarkerShift {
 public:
  MarkerShift(const Placement& at, const std::vector<Marker>& markers)
      : at_(at),
        options_(registrationOptions(at.spec.spec)),
        shifts_(shiftGrid(at.scanner())),
        samples_(at.points),
        markers_(markerPoints(markers)) {}

  // The markers each of `views` measures.
  std::vector<std::vector<int>> seen(std::span<const View> views) const {
    return markers_.measured(at_.simulator, views);
  }

  bool registers(const std::vector<int>& seen) const {
    std::vector<Vec3> positions;
    for (int m : seen) positions.push_back(markers_.points()[m].position);
    return markersRegister(positions, options_.min_markers, options_.marker_spread);
  }

  // `view` moved across its axis, by the least shift that lets it register by markers and
  // keeps its own samples (those of `measured` within a quarter of the field of view of its
  // target), with the samples it then measures; none if no shift tried does.
  std::optional<std::pair<View, std::vector<int>>> shifted(const View& view,
                                                           const std::vector<int>& measured) const {
    const std::vector<Vec3> near = nearMarkers(view);
    std::vector<int> own;
    for (int i : measured)
      if ((samples_.points()[i].position - view.target).norm() <= at_.scanner().fov_height / 4)
        own.push_back(i);
    std::size_t tries = 0;
    for (const Vec3& shift : shifts_) {
      if (tries == kTries) break;
      if (!mayRegister(near, shift)) continue;
      ++tries;
      const View moved = shiftedPose(view, view.camera_to_world.linear() * shift);
      if (!poseIsValid(at_.simulator, moved, at_.cell) || !registers(seen({&moved, 1}).front()))
        continue;
      std::vector<int> now = samples_.measured(at_.simulator, {&moved, 1}).front();
      if (std::includes(now.begin(), now.end(), own.begin(), own.end()))
        return std::pair{moved, std::move(now)};
    }
    return std::nullopt;
  }

 private:
  // The markers in the camera frame of `view` within its depth of field and a field of view
  // of it, where a shift may bring them in.
  std::vector<Vec3> nearMarkers(const View& view) const {
    const Scanner& s = at_.scanner();
    const Pose world_to_camera = view.camera_to_world.inverse();
    std::vector<Vec3> near;
    for (const SurfacePoint& m : markers_.points()) {
      const Vec3 p = world_to_camera * m.position;
      if (std::abs(p.z() - s.standoff) <= s.depth_of_field / 2 && std::abs(p.x()) <= s.fov_width &&
          std::abs(p.y()) <= s.fov_height)
        near.push_back(p);
    }
    return near;
  }

  // The quick count: enough markers of `near` (camera frame), spread out, within nine
  // tenths of the field of view moved by `shift`.
  bool mayRegister(const std::vector<Vec3>& near, const Vec3& shift) const {
    const Scanner& s = at_.scanner();
    std::vector<Vec3> inside;
    for (const Vec3& m : near) {
      const Vec3 p = m - shift;
      const double scale = p.z() / s.standoff;
      if (std::abs(p.x()) <= 0.45 * s.fov_width * scale &&
          std::abs(p.y()) <= 0.45 * s.fov_height * scale)
        inside.push_back(p);
    }
    return markersRegister(inside, options_.min_markers, options_.marker_spread);
  }

  const Placement& at_;
  const RegistrationOptions options_;
  const std::vector<Vec3> shifts_;
  const IndexedPoints samples_;
  const IndexedPoints markers_;
};

}  // namespace

void addMarkerShifts(const Placement& at, MeasuredViews& pool, const std::vector<Marker>& markers,
                     const Progress& progress) {
  if (markers.empty()) return;
  report(progress, "shifting poses towards markers", 0);
  const MarkerShift shift(at, markers);
  const std::vector<std::vector<int>> seen = shift.seen(pool.views);
  std::vector<std::optional<std::pair<View, std::vector<int>>>> moved(pool.size());
  tbb::parallel_for(std::size_t{0}, pool.size(), [&](std::size_t v) {
    if (!pool.samples[v].empty() && !shift.registers(seen[v]))
      moved[v] = shift.shifted(pool.views[v], pool.samples[v]);
  });
  for (auto& found : moved)
    if (found) pool.add(found->first, std::move(found->second));
  report(progress, "shifting poses towards markers", 1);
}

}  // namespace scanplan::detail
