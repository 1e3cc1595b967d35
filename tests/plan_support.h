#pragma once
// Helpers of the tests that plan: specs from text, a part's top face, coverage against the
// dense reference (poses aimed at every sample itself, a wider search than the planner's
// pool).

#include "support.h"

#include <scanplan/io/spec_yaml.h>
#include <scanplan/planning.h>
#include <scanplan/spec/spec.h>

#include <string>
#include <utility>
#include <vector>

namespace scanplan::test {

// The spec `text`, written into `dir` and read back.
inline Spec specWith(const std::string& text, const TempDir& dir) {
  writeText(dir.file("spec.yaml"), text);
  return loadSpec(dir.file("spec.yaml"));
}

// The face of `part` with the largest area whose normal (at its samples) is +Z.
inline int topFace(const Part& part) {
  int best = 0;
  for (const Face& face : part.faces)
    if (face.bounds.size().z() < 1e-6 && face.bounds.max.z() > part.bounds().max.z() - 1e-6 &&
        (best == 0 || face.area > part.face(best).area))
      best = face.id;
  return best;
}

// Samples of `plan` that some valid pose of the wider dense reference measures
// (coverableByWiderCandidates: poses aimed at each sample and moved to place it across the
// measuring volume, simulated by the same model as the plan's, built afresh), and how many
// of those the plan measures. It confirms that the plan's pool and selection miss nothing
// those poses reach, not the simulation model.
// Every `stride`-th sample only, where the plan has thousands.
inline std::pair<std::size_t, std::size_t> coverableAndMeasured(const Part& part, const Plan& plan,
                                                                std::size_t stride = 1) {
  SimulationOptions simulation;
  simulation.part_to_world = plan.part_to_world;
  const Simulator simulator(part, plan.scanner, simulation);
  const std::vector<SurfacePoint> all = plan.samplePoints();
  std::vector<SurfacePoint> points;
  std::vector<bool> measured_by_plan;
  for (std::size_t i = 0; i < all.size(); i += stride) {
    points.push_back(all[i]);
    measured_by_plan.push_back(!plan.samples[i].measured_by.empty());
  }
  const std::vector<char> coverable = coverableByWiderCandidates(simulator, points);
  std::size_t can = 0, measured = 0;
  for (std::size_t i = 0; i < points.size(); ++i) {
    can += coverable[i];
    measured += coverable[i] && measured_by_plan[i];
  }
  return {can, measured};
}

}  // namespace scanplan::test
