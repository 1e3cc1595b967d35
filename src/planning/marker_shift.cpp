// Target shift towards markers (docs/planning.md): poses of the pool that see too few
// markers to register by, moved across their axis until they take in enough, while they
// still measure every sample they measured; and poses aimed at the samples that no pose of
// the pool measures while seeing enough markers (framed poses).

#include "planning/stages.h"
#include "registration/overlaps.h"

#include <tbb/parallel_for.h>

#include <algorithm>
#include <optional>
#include <span>

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

// The markers views register by: those each view measures, and whether they register it.
class KnownMarkers {
 public:
  KnownMarkers(const Placement& at, const std::vector<Marker>& markers)
      : at_(at), options_(registrationOptions(at.spec.spec)), markers_(markerPoints(markers)) {}

  // The markers each of `views` measures.
  std::vector<std::vector<int>> seen(std::span<const View> views) const {
    return markers_.measured(at_.simulator, views);
  }
  // Whether the markers `seen` register a view: enough of them, off one line.
  bool registers(const std::vector<int>& seen) const {
    std::vector<Vec3> positions;
    for (int m : seen) positions.push_back(markers_.points()[m].position);
    return markersRegister(positions, options_.min_markers, options_.marker_spread);
  }
  const std::vector<SurfacePoint>& points() const { return markers_.points(); }
  const RegistrationOptions& options() const { return options_; }

 private:
  const Placement& at_;
  const RegistrationOptions options_;
  const IndexedPoints markers_;
};

class MarkerShift : public KnownMarkers {
 public:
  MarkerShift(const Placement& at, const std::vector<Marker>& markers)
      : KnownMarkers(at, markers), at_(at), shifts_(shiftGrid(at.scanner())), samples_(at.points) {}

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
      const View moved = shiftedInView(view, shift);
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
    for (const SurfacePoint& m : points()) {
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
    return markersRegister(inside, options().min_markers, options().marker_spread);
  }

  const Placement& at_;
  const std::vector<Vec3> shifts_;
  const IndexedPoints samples_;
};

// Framed poses: for a sample, poses aimed at it from the directions of a `kFramedStep`
// grid within the camera's glancing cone, each moved so that the sample lies off the centre
// of the field (across by 0.35 of it, along by a fifth of the depth of field), that measure
// it while seeing enough markers.
constexpr double kFramedStep = 20;      // degrees
constexpr int kFramedRotations = 4;     // about the view axis
constexpr std::size_t kFramedKept = 4;  // framed poses kept per sample
constexpr std::size_t kFramedBatch = 256;

class FramedSearch : public KnownMarkers {
 public:
  FramedSearch(const Placement& at, const std::vector<Marker>& markers)
      : KnownMarkers(at, markers), at_(at), grid_(kFramedStep), offsets_(offsets(at.scanner())) {}

  // Up to kFramedKept valid poses measuring `sample` that register by the markers.
  std::vector<View> posesFor(const SurfacePoint& sample) const {
    std::vector<View> aimed;
    for (const View& view : densePoses(at_.scanner(), sample, grid_, kFramedRotations))
      for (const Vec3& offset : offsets_) aimed.push_back(shiftedInView(view, offset));
    const std::vector<SurfacePoint> points(aimed.size(), sample);
    const std::vector<Loss> losses = at_.simulator.measurePairs(aimed, points);
    std::vector<View> measuring;
    for (std::size_t k = 0; k < aimed.size(); ++k)
      if (losses[k] == Loss::Measured) measuring.push_back(aimed[k]);
    std::vector<View> kept;
    for (std::size_t b = 0; b < measuring.size() && kept.size() < kFramedKept; b += kFramedBatch) {
      const std::span<const View> batch(measuring.data() + b,
                                        std::min(kFramedBatch, measuring.size() - b));
      const std::vector<std::vector<int>> on = seen(batch);
      for (std::size_t k = 0; k < batch.size() && kept.size() < kFramedKept; ++k)
        if (registers(on[k]) && poseIsValid(at_.simulator, batch[k], at_.cell))
          kept.push_back(batch[k]);
    }
    return kept;
  }

 private:
  static std::vector<Vec3> offsets(const Scanner& s) {
    std::vector<Vec3> offsets;
    for (double z : {0.0, -0.2, 0.2})
      for (double x : {0.0, -0.35, 0.35})
        for (double y : {0.0, -0.35, 0.35}) offsets.push_back(placeInVolume(s, x, y, z));
    return offsets;
  }

  const Placement& at_;
  const VisibilityMap grid_;
  const std::vector<Vec3> offsets_;
};

}  // namespace

std::vector<char> addMarkerShifts(const Placement& at, MeasuredViews& pool,
                                  const std::vector<Marker>& markers, const Progress& progress) {
  if (markers.empty()) return {};
  report(progress, "shifting poses towards markers", 0);
  const MarkerShift shift(at, markers);
  const std::vector<std::vector<int>> seen = shift.seen(pool.views);
  std::vector<char> framed(pool.size());
  std::vector<std::optional<std::pair<View, std::vector<int>>>> moved(pool.size());
  tbb::parallel_for(std::size_t{0}, pool.size(), [&](std::size_t v) {
    framed[v] = shift.registers(seen[v]);
    if (!pool.samples[v].empty() && !framed[v])
      moved[v] = shift.shifted(pool.views[v], pool.samples[v]);
  });
  for (auto& found : moved)
    if (found) {
      pool.add(found->first, std::move(found->second));
      framed.push_back(1);  // shifted until it registers
    }
  report(progress, "shifting poses towards markers", 1);
  return framed;
}

std::vector<char> addFramedPoses(const Placement& at, MeasuredViews& pool,
                                 const std::vector<Marker>& markers, std::vector<char> framed,
                                 const Progress& progress) {
  if (markers.empty()) return {};
  const FramedSearch search(at, markers);
  // The samples some pose of the pool measures, and whether a framed one does.
  std::vector<char> measured(at.points.size(), 0), served(at.points.size(), 0);
  for (std::size_t v = 0; v < pool.size(); ++v) {
    for (int i : pool.samples[v]) {
      measured[i] = 1;
      served[i] |= framed[v];
    }
  }
  const IndexedPoints samples(at.points);
  const auto total = static_cast<std::size_t>(std::count(measured.begin(), measured.end(), 1) -
                                              std::count(served.begin(), served.end(), 1));
  std::size_t done = 0;
  for (std::size_t i = 0; i < at.points.size(); ++i) {
    if (!measured[i] || served[i]) continue;
    report(progress, "framing poses on markers",
           static_cast<double>(done++) / static_cast<double>(std::max<std::size_t>(total, 1)));
    const std::vector<View> found = search.posesFor(at.points[i]);
    const std::vector<std::vector<int>> on = samples.measured(at.simulator, found);
    for (std::size_t k = 0; k < found.size(); ++k) {
      for (int j : on[k]) served[j] = 1;
      pool.add(found[k], on[k]);
      framed.push_back(1);
    }
    served[i] = 1;  // searched, whatever was found
  }
  report(progress, "framing poses on markers", 1);
  return framed;
}

}  // namespace scanplan::detail
