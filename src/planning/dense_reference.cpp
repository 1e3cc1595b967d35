// The dense references of benchmarks and tests (planner.h): poses aimed at every sample
// itself, a wider search than the planner's pool.

#include "registration/overlaps.h"

#include <scanplan/planning/planner.h>
#include <scanplan/planning/poses.h>

#include <algorithm>
#include <span>

namespace scanplan {

namespace {

constexpr std::size_t kBlock = 64;  // samples per batch of poses

// The dense poses of samples [first, last) with the sample each is aimed at, each also
// moved by every one of `offsets` (camera frame, mm).
struct DensePoses {
  std::vector<View> views;
  std::vector<SurfacePoint> points;
  std::vector<std::size_t> owner;
};

DensePoses densePosesOf(const Simulator& simulator, const std::vector<SurfacePoint>& samples,
                        std::size_t first, std::size_t last, const VisibilityMap& grid,
                        int rotations, const std::vector<Vec3>& offsets) {
  DensePoses poses;
  for (std::size_t i = first; i < last; ++i)
    for (const View& view : densePoses(simulator.scanner(), samples[i], grid, rotations))
      for (const Vec3& offset : offsets) {
        poses.views.push_back(offset.isZero() ? view : shiftedInView(view, offset));
        poses.points.push_back(samples[i]);
        poses.owner.push_back(i);
      }
  return poses;
}

// Moves of a pose that keep its sample inside the measuring volume: across the axis by 0,
// a quarter and 0.45 of the field each way, along it by 0 and a quarter of the depth of
// field each way.
std::vector<Vec3> volumeOffsets(const Scanner& scanner) {
  std::vector<Vec3> offsets;
  const std::vector<double> across = {0.0, -0.25, 0.25, -0.45, 0.45};
  for (double z : {0.0, -0.25, 0.25})
    for (double x : across)
      for (double y : across) offsets.push_back(placeInVolume(scanner, x, y, z));
  return offsets;
}

}  // namespace

std::vector<char> coverableByDenseCandidates(const Simulator& simulator,
                                             const std::vector<SurfacePoint>& samples, double step,
                                             int rotations, const CellCheck& cell) {
  const VisibilityMap grid(step);
  std::vector<char> coverable(samples.size(), 0);
  for (std::size_t first = 0; first < samples.size(); first += kBlock) {
    const DensePoses poses =
        densePosesOf(simulator, samples, first, std::min(samples.size(), first + kBlock), grid,
                     rotations, {Vec3::Zero()});
    const std::vector<Loss> losses = simulator.measurePairs(poses.views, poses.points);
    for (std::size_t k = 0; k < losses.size(); ++k)
      if (losses[k] == Loss::Measured && !coverable[poses.owner[k]] &&
          poseIsValid(simulator, poses.views[k], cell))
        coverable[poses.owner[k]] = 1;
  }
  return coverable;
}

std::vector<char> coverableByWiderCandidates(const Simulator& simulator,
                                             const std::vector<SurfacePoint>& samples, double step,
                                             int rotations, const CellCheck& cell) {
  std::vector<char> coverable =
      coverableByDenseCandidates(simulator, samples, step, rotations, cell);
  const VisibilityMap grid(step);
  std::vector<Vec3> offsets = volumeOffsets(simulator.scanner());
  std::erase_if(offsets, [](const Vec3& offset) { return offset.isZero(); });  // tried above
  for (std::size_t i = 0; i < samples.size(); ++i) {
    if (coverable[i]) continue;
    const DensePoses poses = densePosesOf(simulator, samples, i, i + 1, grid, rotations, offsets);
    const std::vector<Loss> losses = simulator.measurePairs(poses.views, poses.points);
    for (std::size_t k = 0; k < losses.size() && !coverable[i]; ++k)
      coverable[i] = losses[k] == Loss::Measured && poseIsValid(simulator, poses.views[k], cell);
  }
  return coverable;
}

std::vector<char> framedByDenseCandidates(const Simulator& simulator,
                                          const std::vector<SurfacePoint>& samples,
                                          const std::vector<Marker>& markers,
                                          const RegistrationOptions& options, double step,
                                          int rotations, const CellCheck& cell) {
  const VisibilityMap grid(step);
  const std::vector<Vec3> offsets = volumeOffsets(simulator.scanner());
  const IndexedPoints marker_points(detail::markerPoints(markers));
  std::vector<char> framed(samples.size(), 0);
  for (std::size_t i = 0; i < samples.size(); ++i) {
    const DensePoses poses = densePosesOf(simulator, samples, i, i + 1, grid, rotations, offsets);
    const std::vector<Loss> losses = simulator.measurePairs(poses.views, poses.points);
    std::vector<View> measuring;
    for (std::size_t k = 0; k < losses.size(); ++k)
      if (losses[k] == Loss::Measured) measuring.push_back(poses.views[k]);
    // In batches, so that a sample framed early costs little.
    constexpr std::size_t kBatch = 256;
    for (std::size_t b = 0; b < measuring.size() && !framed[i]; b += kBatch) {
      const std::span<const View> batch(measuring.data() + b,
                                        std::min(kBatch, measuring.size() - b));
      const std::vector<std::vector<int>> seen = marker_points.measured(simulator, batch);
      for (std::size_t k = 0; k < batch.size() && !framed[i]; ++k) {
        std::vector<Vec3> positions;
        for (int m : seen[k]) positions.push_back(markers[m].position);
        framed[i] = markersRegister(positions, options.min_markers, options.marker_spread) &&
                    poseIsValid(simulator, batch[k], cell);
      }
    }
  }
  return framed;
}

}  // namespace scanplan
